// icp_2d with Arithmetic::Mrpt: MRPT 2.5.8's arithmetic to the bit, so that a
// run of MRPT's CICP (and of its icp-slam) is reproduced step by step. Built
// with -ffp-contract=off (cmake/RoveModule.cmake) so that no product is fused
// into an FMA that MRPT's build does not have. rove's own arithmetic is in
// icp_2d.cpp; docs/icp-slam.md tells how each item below was found.

#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "icp_2d_internal.h"
#include "rove/poses/angle.h"

namespace rove::detail {

template std::size_t icp2d_match_range(const KdTree<2, float>&, const Icp2dMatchInput&,
                                       std::size_t, std::size_t, std::vector<Icp2dPair>&,
                                       std::vector<Neighbor<float>>&, std::uint32_t*);

namespace {

// Both helpers stay out of line. Inlined, GCC 12's basic-block SLP
// vectorizer (on at -O3, and with its cheap cost model at -O2) drops some
// of the (double)(float) round trips of neighbouring fields: in a Release
// build 8 of the 12 options of mrpt_rounded_options came out unrounded
// (minAbsStep_trans and _rot, ALFA, smallestThresholdDist,
// LM_initial_lambda, Axy_aprox_derivatives, the RANSAC Mahalanobis
// threshold, normalizationStd), and the LM run of icp-slam left MRPT's path
// at step 20. The sanitizer build (-O1) has no SLP pass and never showed it.
// Icp2dMrptCompat.Gcc12SlpKeepsEveryOptionRoundedToFloat pins it.

/// MRPT's read_float of a double field: the nearest float.
[[gnu::noinline]] double as_float(double v) { return static_cast<float>(v); }
/// MRPT's DEG2RAD of a float read of degrees: x·float(π)/180 in float.
[[gnu::noinline]] double as_float_deg_to_rad(double rad) {
  const float deg = static_cast<float>(rad_to_deg(rad));
  return deg * std::numbers::pi_v<float> / 180.0f;
}

}  // namespace

Icp2dOptions mrpt_rounded_options(Icp2dOptions o) {
  for (double* v : {&o.min_abs_step_trans, &o.min_abs_step_rot, &o.threshold_dist, &o.alfa,
                    &o.smallest_threshold_dist, &o.covariance_var_points, &o.kernel_rho,
                    &o.lm_initial_lambda, &o.axy_aprox_derivatives,
                    &o.ransac.mahalanobis_threshold, &o.ransac.normalization_std,
                    &o.ransac.fuse_max_diff_xy})
    *v = as_float(*v);
  o.threshold_ang = as_float_deg_to_rad(o.threshold_ang);
  o.ransac.fuse_max_diff_phi = as_float_deg_to_rad(o.ransac.fuse_max_diff_phi);
  return o;
}

Pose2 mrpt_se2_l2_fit(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                      const std::vector<Icp2dPair>& pairs) {
  // "a" is the target (MRPT's global) side, "b" the source (local) side.
  const auto& tp = target.points();
  float sum_xa = 0, sum_ya = 0, sum_xb = 0, sum_yb = 0;
  float sxx = 0, sxy = 0, syx = 0, syy = 0;
  for (const Icp2dPair& pr : pairs) {
    const float xa = static_cast<float>(tp[pr.target].x()), ya = static_cast<float>(tp[pr.target].y());
    const float xb = static_cast<float>(source[pr.source].x());
    const float yb = static_cast<float>(source[pr.source].y());
    sum_xa += xa;
    sum_ya += ya;
    sum_xb += xb;
    sum_yb += yb;
    sxx += xa * xb;
    syy += ya * yb;
    sxy += xa * yb;
    syx += ya * xb;
  }
  const float n = static_cast<float>(pairs.size());
  const float n_inv = 1.0f / n;
  const float mean_xa = sum_xa * n_inv, mean_ya = sum_ya * n_inv;
  const float mean_xb = sum_xb * n_inv, mean_yb = sum_yb * n_inv;
  const float ax = n * (sxx + syy) - sum_xa * sum_xb - sum_ya * sum_yb;
  const float ay = sum_xa * sum_yb + n * (syx - sxy) - sum_xb * sum_ya;
  const double phi = (ax != 0 || ay != 0) ? std::atan2(static_cast<double>(ay), static_cast<double>(ax)) : 0.0;
  const double c = std::cos(phi), s = std::sin(phi);
  return Pose2(mean_xa - mean_xb * c + mean_yb * s, mean_ya - mean_xb * s - mean_yb * c, phi);
}

double mrpt_goodness(std::size_t decimation, std::size_t with_pair, std::size_t finite_points) {
  // Capped at 1: with N not a multiple of the decimation and every point
  // paired MRPT reports slightly more.
  if (finite_points == 0) return 0.0;
  return std::min(1.0, static_cast<double>(static_cast<float>(decimation * with_pair) /
                                           static_cast<float>(finite_points)));
}

namespace {

/// The pairs' coordinates as MRPT's TMatchingPairList holds them (float),
/// by column: the source ("local") and the map ("global") point of each.
struct FloatPairs {
  std::vector<float> lx, ly, gx, gy;
  FloatPairs(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
             const std::vector<Icp2dPair>& pairs) {
    const auto& tp = target.points();
    const std::size_t n = pairs.size();
    for (auto* v : {&lx, &ly, &gx, &gy}) v->resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      lx[k] = static_cast<float>(source[pairs[k].source].x());
      ly[k] = static_cast<float>(source[pairs[k].source].y());
      gx[k] = static_cast<float>(tp[pairs[k].target].x());
      gy[k] = static_cast<float>(tp[pairs[k].target].y());
    }
  }
  std::size_t size() const { return lx.size(); }
};

/// MRPT's TMatchingPairList::squareErrorVector at pose p, in float: the
/// source points moved by p (written to xs, ys when not null) and each
/// pair's squared error (to e when not null); returns the errors' sum in
/// float, summed in pair order as MRPT's math::sum.
float square_errors(const FloatPairs& fp, const Pose2& p, float* e, float* xs, float* ys) {
  const float c = static_cast<float>(std::cos(p.phi())), s = static_cast<float>(std::sin(p.phi()));
  const float px = static_cast<float>(p.x()), py = static_cast<float>(p.y());
  float sum = 0;
  for (std::size_t k = 0; k < fp.size(); ++k) {
    const float x = px + c * fp.lx[k] - s * fp.ly[k];
    const float y = py + s * fp.lx[k] + c * fp.ly[k];
    const float err = (fp.gx[k] - x) * (fp.gx[k] - x) + (fp.gy[k] - y) * (fp.gy[k] - y);
    if (e) e[k] = err;
    if (xs) xs[k] = x;
    if (ys) ys[k] = y;
    sum += err;
  }
  return sum;
}

/// C⁻¹ of a symmetric positive definite 3×3 as MRPT's inverse_LLt computes
/// it through Eigen (LLᵀ of a row-major float matrix, then L·Lᵀ·X = I
/// solved column by column in the order Eigen's triangular solver uses for
/// a row-major right-hand side: each entry is reduced by the known ones in
/// order, then multiplied by the reciprocal of the pivot). Checked bit for
/// bit against Eigen 3.4 on random matrices. A matrix that is not positive
/// definite gives NaN entries.
Eigen::Matrix3f inverse_llt(const Eigen::Matrix3f& A) {
  float L[3][3] = {};
  L[0][0] = std::sqrt(A(0, 0));
  L[1][0] = A(1, 0) / L[0][0];
  L[2][0] = A(2, 0) / L[0][0];
  L[1][1] = std::sqrt(A(1, 1) - L[1][0] * L[1][0]);
  L[2][1] = (A(2, 1) - L[2][0] * L[1][0]) / L[1][1];
  L[2][2] = std::sqrt(A(2, 2) - (L[2][0] * L[2][0] + L[2][1] * L[2][1]));
  Eigen::Matrix3f X;
  for (int col = 0; col < 3; ++col) {
    float b[3] = {col == 0 ? 1.0f : 0.0f, col == 1 ? 1.0f : 0.0f, col == 2 ? 1.0f : 0.0f};
    for (int i = 0; i < 3; ++i) {  // L·y = e_col
      for (int k = 0; k < i; ++k) b[i] -= b[k] * L[i][k];
      b[i] *= 1.0f / L[i][i];
    }
    for (int i = 2; i >= 0; --i) {  // Lᵀ·x = y
      for (int k = i + 1; k < 3; ++k) b[i] -= b[k] * L[k][i];
      b[i] *= 1.0f / L[i][i];
    }
    for (int i = 0; i < 3; ++i) X(i, col) = b[i];
  }
  return X;
}

/// MRPT's gradient J (3 × pairs, CMatrixFloat dJ_dq) of the kernelized
/// squared distances by finite differences, and the errors e: nearest
/// distances in float (as its float KD-tree), the kernel x²/(x² + ρ²) in
/// float, slopes in double stored in float. Returns the float sum of e.
float float_gradient(const IcpTarget2D& target, const FloatPairs& fp,
                    const std::vector<Icp2dPair>& pairs, const Pose2& q, const Icp2dOptions& o,
                    std::array<std::vector<float>, 3>& J, std::vector<float>& e) {
  const std::size_t n = pairs.size();
  const float rho2 = static_cast<float>(o.kernel_rho * o.kernel_rho);
  const auto kern = [&](float x2) -> float { return o.use_kernel ? x2 / (x2 + rho2) : x2; };
  // The query is a source point shifted by ±Axy: its pair's map point,
  // given as the hint, bounds the search (the same nearest point as an
  // unbounded search, far fewer nodes).
  constexpr float kNoBound = std::numeric_limits<float>::infinity();
  const auto nearest_sq = [&](float x, float y, std::uint32_t partner) -> float {
    return target.mrpt_tree().nearest(Eigen::Vector2f(x, y), kNoBound, partner)->sq_distance;
  };
  std::vector<float> xs(n), ys(n);
  e.resize(n);
  const float sum = square_errors(fp, q, e.data(), xs.data(), ys.data());
  const double c = std::cos(q.phi()), s = std::sin(q.phi());
  const double axy = o.axy_aprox_derivatives;
  for (auto& row : J) row.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const float xk = xs[k], yk = ys[k];
    const float gx = fp.gx[k], gy = fp.gy[k];
    const double lx = fp.lx[k], ly = fp.ly[k];  // MRPT's float local point
    // ∂/∂x: distances to the nearest map point at x − Axy, x, x + Axy. At
    // (x, y) itself the nearest map point is the pair's: the pairing moved
    // the point to the same float coordinates (same formula, same pose) and
    // kept the nearest point's float distance.
    const double x1 = xk - axy, x3 = xk + axy;
    const std::uint32_t partner = pairs[k].target;
    const double q2 = kern(static_cast<float>(pairs[k].sq_dist));
    J[0][k] = static_cast<float>(parabola_slope(x1, xk, x3,
                                                kern(nearest_sq(static_cast<float>(x1), yk, partner)), q2,
                                                kern(nearest_sq(static_cast<float>(x3), yk, partner))));
    // ∂/∂y: distances to the pair's own map point (MRPT reuses q2).
    const float fx2 = (gx - xk) * (gx - xk);
    const double y1 = yk - axy, y3 = yk + axy;
    J[1][k] = static_cast<float>(parabola_slope(
        y1, yk, y3, kern(static_cast<float>(fx2 + (gy - y1) * (gy - y1))), q2,
        kern(static_cast<float>(fx2 + (gy - y3) * (gy - y3)))));
    J[2][k] = static_cast<float>(static_cast<double>(J[0][k]) * (-s * lx - c * ly) +
                                 static_cast<double>(J[1][k]) * (c * lx - s * ly));
  }
  return sum;
}

}  // namespace

/// H = J·Jᵀ summed in float, then damped steps x ← x − (H + λ·diag H)⁻¹·J·e
/// on the fixed J and e, with the 3×3 inverse (MRPT's inverse_LLt) and the
/// product C⁻¹·J·e computed in the order Eigen evaluates MRPT's expressions,
/// so the sums round as MRPT's do.
Pose2 mrpt_finite_difference_lm(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                                const std::vector<Icp2dPair>& pairs, Pose2 q,
                                const Icp2dOptions& o) {
  const std::size_t n = pairs.size();
  const FloatPairs fp(target, source, pairs);
  std::array<std::vector<float>, 3> J;
  std::vector<float> e;
  double ose = float_gradient(target, fp, pairs, q, o, J, e);
  // H = J·Jᵀ (MRPT's matProductOf_AAt: float sums in order). The six sums
  // in one pass (independent chains, each in MRPT's order).
  float h00 = 0, h01 = 0, h02 = 0, h11 = 0, h12 = 0, h22 = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const float j0 = J[0][k], j1 = J[1][k], j2 = J[2][k];
    h00 += j0 * j0;
    h01 += j0 * j1;
    h02 += j0 * j2;
    h11 += j1 * j1;
    h12 += j1 * j2;
    h22 += j2 * j2;
  }
  Eigen::Matrix3f H;
  H << h00, h01, h02, h01, h11, h12, h02, h12, h22;
  double lambda = o.lm_initial_lambda;
  // MRPT: while (keep && ++n < 100).
  bool keep = true;
  for (unsigned it = 1; keep && it < 100; ++it) {
    Eigen::Matrix3f C = H;
    for (int d = 0; d < 3; ++d) C(d, d) *= (1 + lambda);  // float *= double, as MRPT
    const Eigen::Matrix3f C_inv = inverse_llt(C);
    // MRPT's (C⁻¹·J·e) as Eigen evaluates it, without its 3 × n temporary:
    // T(i, k) = c₀J₀ₖ + (c₁J₁ₖ + c₂J₂ₖ), then Σₖ T(i, k)·eₖ in order (checked
    // bit for bit against the Eigen expression over MRPT's types). The three
    // rows in one pass: three independent chains of float adds, each in
    // MRPT's order.
    const float a0 = C_inv(0, 0), a1 = C_inv(0, 1), a2 = C_inv(0, 2);
    const float b0 = C_inv(1, 0), b1 = C_inv(1, 1), b2 = C_inv(1, 2);
    const float d0 = C_inv(2, 0), d1 = C_inv(2, 1), d2 = C_inv(2, 2);
    float sum0 = 0, sum1 = 0, sum2 = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const float j0 = J[0][k], j1 = J[1][k], j2 = J[2][k], ek = e[k];
      sum0 += (a0 * j0 + (a1 * j1 + a2 * j2)) * ek;
      sum1 += (b0 * j0 + (b1 * j1 + b2 * j2)) * ek;
      sum2 += (d0 * j0 + (d1 * j1 + d2 * j2)) * ek;
    }
    const Eigen::Vector3f delta(sum0, sum1, sum2);
    if (!delta.allFinite()) break;
    const Pose2 q_new(q.x() - delta[0], q.y() - delta[1], q.phi() - delta[2]);
    const float ose_new = square_errors(fp, q_new, nullptr, nullptr, nullptr);
    keep = std::abs(delta[0]) > o.min_abs_step_trans || std::abs(delta[1]) > o.min_abs_step_trans ||
           std::abs(delta[2]) > o.min_abs_step_rot;
    lm_accept_or_damp(q_new, ose_new, q, ose, lambda);
  }
  return q;
}

}  // namespace rove::detail
