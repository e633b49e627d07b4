#include "rove/registration/rigid_transform.h"

#include <cmath>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/poses/lie_conversion.h"
#include "rove/registration/pose_covariance.h"
#include "rigid_fit_internal.h"

namespace rove {
namespace {

void check_inputs(std::size_t n_target, std::size_t n_source, std::span<const double> weights,
                  const RigidFitOptions& options) {
  ROVE_CHECK_EQ(n_target, n_source);
  ROVE_CHECK_MSG(weights.empty() || weights.size() == n_source,
                 "weights must be empty or one per pair ({} weights, {} pairs)", weights.size(),
                 n_source);
  ROVE_CHECK_MSG(std::isfinite(options.point_variance) && options.point_variance > 0.0,
                 "point_variance must be finite and > 0, got {}", options.point_variance);
  ROVE_CHECK_MSG(options.degeneracy_ratio > 0.0 && options.degeneracy_ratio < 1.0,
                 "degeneracy_ratio must be in (0, 1), got {}", options.degeneracy_ratio);
}

template <typename Vec>
bool all_finite_input(std::span<const Vec> a, std::span<const Vec> b,
                      std::span<const double> w, std::size_t& bad) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double wi = w.empty() ? 1.0 : w[i];
    if (!a[i].allFinite() || !b[i].allFinite() || !std::isfinite(wi)) {
      bad = i;
      return false;
    }
    ROVE_CHECK_MSG(wi >= 0.0, "weight {} is negative ({})", i, wi);
  }
  return true;
}

/// The weight of pair i (1 when no weights are given).
auto weight_of(std::span<const double> weights) {
  return [weights](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };
}

/// The checks and centroids both fits start with: InvalidInput for a
/// non-finite pair, TooFewCorrespondences below `min_pairs` positive weights
/// (the result's termination and message say so; false is returned).
template <int D, class Result>
bool prepare_fit(std::span<const Eigen::Matrix<double, D, 1>> target,
                 std::span<const Eigen::Matrix<double, D, 1>> source, std::span<const double> weights,
                 const RigidFitOptions& options, std::size_t min_pairs, Result& r,
                 detail::WeightedCentroids<D>& c) {
  check_inputs(target.size(), source.size(), weights, options);
  std::size_t bad = 0;
  if (!all_finite_input(target, source, weights, bad)) {
    r.message = fmt::format("pair {} has a non-finite coordinate or weight", bad);
    return false;
  }
  c = detail::weighted_centroids<D>(
      source.size(), [&](std::size_t i) { return source[i]; },
      [&](std::size_t i) { return target[i]; }, weight_of(weights));
  r.pairs = c.pairs;
  if (r.pairs < min_pairs) {
    r.termination = RegistrationTermination::TooFewCorrespondences;
    r.message = fmt::format("{} pair(s) with positive weight; {} are needed", r.pairs, min_pairs);
    return false;
  }
  return true;
}

}  // namespace

RigidFit2Result fit_rigid_2d(std::span<const Eigen::Vector2d> target,
                             std::span<const Eigen::Vector2d> source,
                             std::span<const double> weights, const RigidFitOptions& options) {
  RigidFit2Result r;
  detail::WeightedCentroids<2> cen;
  if (!prepare_fit<2>(target, source, weights, options, 2, r, cen)) return r;
  const double sw = cen.weight_sum;
  const Eigen::Vector2d cs = cen.source;
  const Pose2 mean = detail::centered_rigid_fit_2d(
      source.size(), [&](std::size_t i) { return source[i]; },
      [&](std::size_t i) { return target[i]; }, weight_of(weights), cen);
  const double c = std::cos(mean.phi()), s = std::sin(mean.phi());
  const Eigen::Vector2d t = mean.translation();

  // Information Σ w JᵀJ with J = [I | R'·s] (d/dphi of R·s is the perpendicular of R·s).
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  double sse = 0, radius2 = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (w <= 0.0) continue;
    const Eigen::Vector2d rs(c * source[i].x() - s * source[i].y(),
                             s * source[i].x() + c * source[i].y());
    Eigen::Matrix<double, 2, 3> J;
    J << 1, 0, -rs.y(), 0, 1, rs.x();
    H += w * J.transpose() * J;
    sse += w * (rs + t - target[i]).squaredNorm();
    radius2 += w * (source[i] - cs).squaredNorm();
  }
  r.rmse = std::sqrt(sse / sw);
  // Normalize the rotation column by the RMS radius so the ratio test compares
  // meters with meters (otherwise the test would depend on the unit of length).
  const double L = std::sqrt(radius2 / sw);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (L > 0) S(2, 2) = L;
  int n_free = 0;
  Eigen::Matrix3d C;
  if (L > 0) {
    const Eigen::Matrix3d Hn = S.inverse() * H * S.inverse();
    C = S.inverse() * covariance_from_information<3>(Hn, options.point_variance,
                                                      options.degeneracy_ratio, &n_free) *
        S.inverse();
  } else {
    C = covariance_from_information<3>(H, options.point_variance, options.degeneracy_ratio,
                                       &n_free);
    n_free = std::max(n_free, 1);
  }
  r.T_target_source = to_se2(mean);
  r.covariance = xyphi_to_right_tangent_covariance(mean, C);
  if (n_free > 0 || L <= 0) {
    r.termination = RegistrationTermination::Degenerate;
    r.message = "the source points coincide: the rotation is unconstrained";
  } else {
    r.termination = RegistrationTermination::Converged;
    r.message = fmt::format("closed-form fit of {} pairs, rmse {:.4g} m", r.pairs, r.rmse);
  }
  return r;
}

RigidFit3Result fit_rigid_3d(std::span<const Eigen::Vector3d> target,
                             std::span<const Eigen::Vector3d> source,
                             std::span<const double> weights, const RigidFitOptions& options) {
  RigidFit3Result r;
  detail::WeightedCentroids<3> cen;
  if (!prepare_fit<3>(target, source, weights, options, 3, r, cen)) return r;
  const double sw = cen.weight_sum;
  const Eigen::Vector3d cs = cen.source, ct = cen.target;
  // Umeyama 1991, eq. 38-40: Σ_xy = Σ w (t − t̄)(s − s̄)ᵀ = U D Vᵀ, R = U S Vᵀ.
  Eigen::Matrix3d Sigma = Eigen::Matrix3d::Zero();
  double radius2 = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (w <= 0.0) continue;
    Sigma += w * (target[i] - ct) * (source[i] - cs).transpose();
    radius2 += w * (source[i] - cs).squaredNorm();
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d Sg = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) Sg(2, 2) = -1;  // no reflection
  Eigen::Matrix3d R = svd.matrixU() * Sg * svd.matrixV().transpose();
  // Re-orthonormalize through a quaternion so Pose3 accepts it at 1e-6.
  R = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  const Eigen::Vector3d t = ct - R * cs;

  // Information in the left tangent (δt, δω): J = [I | −[R·s]ₓ].
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  double sse = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (w <= 0.0) continue;
    const Eigen::Vector3d rs = R * source[i];
    Eigen::Matrix<double, 3, 6> J;
    J.leftCols<3>().setIdentity();
    J.rightCols<3>() << 0, rs.z(), -rs.y(), -rs.z(), 0, rs.x(), rs.y(), -rs.x(), 0;
    H += w * J.transpose() * J;
    sse += w * (rs + t - target[i]).squaredNorm();
  }
  r.rmse = std::sqrt(sse / sw);
  const double L = std::sqrt(radius2 / sw);
  int n_free = 0;
  Eigen::Matrix<double, 6, 6> C;
  if (L > 0) {
    Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>::Identity();
    S.bottomRightCorner<3, 3>() *= 1.0 / L;
    C = S * covariance_from_information<6>(S * H * S, options.point_variance,
                                           options.degeneracy_ratio, &n_free) *
        S;
  } else {
    C = covariance_from_information<6>(H, options.point_variance, options.degeneracy_ratio,
                                       &n_free);
    n_free = std::max(n_free, 3);
  }
  // Left (δt, δω) to right (ρ, ω) tangent: δt = R·ρ, δω = R·ω.
  Eigen::Matrix<double, 6, 6> Rt = Eigen::Matrix<double, 6, 6>::Zero();
  Rt.topLeftCorner<3, 3>() = R.transpose();
  Rt.bottomRightCorner<3, 3>() = R.transpose();
  Eigen::Matrix<double, 6, 6> Cr = Rt * C * Rt.transpose();
  r.T_target_source = SE3d(R, t);
  r.covariance = 0.5 * (Cr + Cr.transpose());
  if (n_free > 0) {
    r.termination = RegistrationTermination::Degenerate;
    r.message = fmt::format(
        "the source points are {}: {} rotation direction(s) unconstrained",
        L > 0 ? "collinear" : "coincident", n_free);
  } else {
    r.termination = RegistrationTermination::Converged;
    r.message = fmt::format("closed-form fit of {} pairs, rmse {:.4g} m", r.pairs, r.rmse);
  }
  return r;
}

}  // namespace rove
