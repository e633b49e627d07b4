#include "rove/vision/pnp.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/math/ransac.h"

namespace rove {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

struct PnpDatum {
  Eigen::Vector3d p_world;
  Eigen::Vector2d normalized;  // (a, b) of the pixel's ray
};

// Reprojection error in (ideal) pixels, or NaN behind the camera.
double reprojection_error(const SE3d& T, const PnpDatum& d, double fx, double fy) {
  const Eigen::Vector3d p = T * d.p_world;
  if (!(p.z() > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::hypot(fx * (p.x() / p.z() - d.normalized.x()),
                    fy * (p.y() / p.z() - d.normalized.y()));
}

struct PnpProblem {
  using Model = SE3d;
  using Datum = PnpDatum;
  double fx = 1.0, fy = 1.0;
  int refine_iterations = 10;

  std::size_t sample_size() const { return 3; }

  // AP3P (Ke & Roumeliotis 2017) through OpenCV on normalized rays (K = I).
  void fit(std::span<const Datum> sample, std::vector<Model>& models) const {
    cv::Mat object(3, 3, CV_64F), image(3, 2, CV_64F);
    for (int i = 0; i < 3; ++i) {
      const Datum& d = sample[static_cast<std::size_t>(i)];
      for (int k = 0; k < 3; ++k) object.at<double>(i, k) = d.p_world[k];
      image.at<double>(i, 0) = d.normalized.x();
      image.at<double>(i, 1) = d.normalized.y();
    }
    std::vector<cv::Mat> rvecs, tvecs;
    const int n = cv::solveP3P(object, image, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), rvecs,
                               tvecs, cv::SOLVEPNP_AP3P);
    for (int s = 0; s < n; ++s) {
      cv::Mat R_cv;
      cv::Rodrigues(rvecs[static_cast<std::size_t>(s)], R_cv);
      Eigen::Matrix3d R;
      Eigen::Vector3d t;
      cv::cv2eigen(R_cv, R);
      cv::cv2eigen(tvecs[static_cast<std::size_t>(s)], t);
      if (!R.allFinite() || !t.allFinite()) continue;
      // Re-orthonormalize: AP3P's rotation is orthogonal only to rounding.
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
      R = svd.matrixU() * svd.matrixV().transpose();
      if (R.determinant() < 0.0) continue;
      models.emplace_back(R, t);
    }
  }

  double distance(const Model& T, const Datum& d) const {
    return reprojection_error(T, d, fx, fy);
  }

  bool refit(std::span<const Datum> inliers, Model& T) const {
    if (inliers.size() < 4) return false;
    std::vector<Eigen::Vector3d> p(inliers.size());
    std::vector<Eigen::Vector2d> m(inliers.size());
    for (std::size_t i = 0; i < inliers.size(); ++i) {
      p[i] = inliers[i].p_world;
      m[i] = inliers[i].normalized;
    }
    const SE3d refined = refine_pnp(p, m, fx, fy, T, refine_iterations);
    if (!refined.matrix().allFinite()) return false;
    T = refined;
    return true;
  }
};

}  // namespace

void PnpOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(reprojection_threshold_px) && reprojection_threshold_px > 0.0,
                 "PnpOptions: reprojection_threshold_px = {} must be finite and > 0",
                 reprojection_threshold_px);
  ROVE_CHECK_MSG(success_probability > 0.0 && success_probability < 1.0,
                 "PnpOptions: success_probability = {} must be in (0, 1)", success_probability);
  ROVE_CHECK_GE(max_iterations, std::size_t{1});
  ROVE_CHECK_GE(min_inliers, std::size_t{4});
  ROVE_CHECK_GE(refine_iterations, 1);
}

SE3d refine_pnp(std::span<const Eigen::Vector3d> points_world,
                std::span<const Eigen::Vector2d> normalized, double fx, double fy,
                const SE3d& T_camera_world, int iterations, Matrix6d* covariance) {
  ROVE_CHECK_EQ(points_world.size(), normalized.size());
  ROVE_CHECK_MSG(fx != 0.0 && fy != 0.0, "refine_pnp: fx = {}, fy = {} must be nonzero", fx, fy);
  ROVE_CHECK_GE(iterations, 1);
  SE3d T = T_camera_world;
  Matrix6d H = Matrix6d::Zero();
  double cost = 0.0;
  std::size_t used = 0;
  // Normal equations of Σ‖rᵢ‖² at T. rᵢ = f ⊙ (π(R·Xᵢ + t) − mᵢ); with the
  // right perturbation T·exp(ξ): ∂p/∂ρ = R, ∂p/∂ω = −R·[X]ₓ (Solà et al.
  // 2018, Eq. 179 composed with the action), ∂π/∂p = [1/z 0 −x/z²; 0 1/z −y/z²].
  const auto linearize = [&](const SE3d& pose, Vector6d& g) {
    H.setZero();
    g.setZero();
    cost = 0.0;
    used = 0;
    const Eigen::Matrix3d R = pose.rotation().matrix();
    for (std::size_t i = 0; i < points_world.size(); ++i) {
      const Eigen::Vector3d& X = points_world[i];
      const Eigen::Vector3d p = pose * X;
      if (!(p.z() > 0.0)) continue;
      const double iz = 1.0 / p.z();
      const Eigen::Vector2d r(fx * (p.x() * iz - normalized[i].x()),
                              fy * (p.y() * iz - normalized[i].y()));
      Eigen::Matrix<double, 2, 3> Jp;
      Jp << fx * iz, 0.0, -fx * p.x() * iz * iz, 0.0, fy * iz, -fy * p.y() * iz * iz;
      Eigen::Matrix3d X_hat;
      X_hat << 0.0, -X.z(), X.y(), X.z(), 0.0, -X.x(), -X.y(), X.x(), 0.0;
      Eigen::Matrix<double, 2, 6> J;
      J.leftCols<3>() = Jp * R;
      J.rightCols<3>() = -Jp * R * X_hat;
      H.noalias() += J.transpose() * J;
      g.noalias() += J.transpose() * r;
      cost += r.squaredNorm();
      ++used;
    }
  };
  Vector6d g;
  for (int it = 0; it < iterations; ++it) {
    linearize(T, g);
    if (used < 3) break;
    const Vector6d delta = H.ldlt().solve(-g);
    if (!delta.allFinite()) break;
    const SE3d candidate = T.oplus(delta);
    Vector6d g_candidate;
    const double old_cost = cost;
    linearize(candidate, g_candidate);
    if (!(cost <= old_cost)) break;  // Gauss–Newton overshot: keep the last pose
    T = candidate;
    if (delta.norm() < 1e-12) break;
  }
  if (covariance != nullptr) {
    linearize(T, g);
    const double dof = 2.0 * static_cast<double>(used) - 6.0;
    const double sigma2 = dof > 0.0 ? cost / dof : std::numeric_limits<double>::quiet_NaN();
    *covariance = sigma2 * H.inverse();
  }
  return T;
}

PnpResult solve_pnp_ransac(std::span<const Eigen::Vector3d> points_world,
                           std::span<const Eigen::Vector2d> pixels, const PinholeCamera& camera,
                           const PnpOptions& options) {
  ROVE_CHECK_EQ(points_world.size(), pixels.size());
  camera.check();
  options.check();
  PnpResult result;
  const std::size_t n = points_world.size();
  std::vector<PnpDatum> data(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!points_world[i].allFinite() || !pixels[i].allFinite()) {
      result.message = fmt::format("pair {} has a non-finite coordinate", i);
      return result;
    }
    try {
      data[i] = {points_world[i], camera.unproject(pixels[i].x(), pixels[i].y()).head<2>()};
    } catch (const NumericError&) {
      result.message = fmt::format("pixel ({}, {}) of pair {} cannot be unprojected",
                                   pixels[i].x(), pixels[i].y(), i);
      return result;
    }
  }
  if (n < options.min_inliers) {
    result.termination = RegistrationTermination::TooFewCorrespondences;
    result.message = fmt::format("{} pairs, fewer than min_inliers = {}", n, options.min_inliers);
    return result;
  }
  PnpProblem problem{camera.fx, camera.fy, options.refine_iterations};
  RansacOptions ro;
  ro.distance_threshold = options.reprojection_threshold_px;
  ro.success_probability = options.success_probability;
  ro.max_iterations = options.max_iterations;
  ro.seed = options.seed;
  const auto ransac_result = ransac(problem, std::span<const PnpDatum>(data), ro);
  result.ransac_iterations = ransac_result.iterations;
  if (!ransac_result.model) {
    result.termination = RegistrationTermination::Degenerate;
    result.message = fmt::format("no P3P sample gave a pose: {}", ransac_result.message);
    return result;
  }
  result.T_camera_world = *ransac_result.model;
  result.inliers = ransac_result.inliers;
  if (result.inliers.size() < options.min_inliers) {
    result.termination = RegistrationTermination::TooFewCorrespondences;
    result.message = fmt::format("{} inliers of {} pairs, fewer than min_inliers = {}",
                                 result.inliers.size(), n, options.min_inliers);
    return result;
  }
  std::vector<Eigen::Vector3d> p;
  std::vector<Eigen::Vector2d> m;
  for (const std::size_t i : result.inliers) {
    p.push_back(data[i].p_world);
    m.push_back(data[i].normalized);
  }
  result.T_camera_world = refine_pnp(p, m, camera.fx, camera.fy, result.T_camera_world,
                                     options.refine_iterations, &result.covariance);
  double sum = 0.0;
  for (const std::size_t i : result.inliers) {
    const double e = reprojection_error(result.T_camera_world, data[i], camera.fx, camera.fy);
    sum += std::isfinite(e) ? e * e : 0.0;
  }
  result.rmse_px = std::sqrt(sum / static_cast<double>(result.inliers.size()));
  result.termination = RegistrationTermination::Converged;
  result.message = fmt::format("{} inliers of {} pairs, reprojection RMS {:.3f} px, {} samples",
                               result.inliers.size(), n, result.rmse_px,
                               result.ransac_iterations);
  return result;
}

}  // namespace rove
