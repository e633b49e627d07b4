#include "rove/registration/icp_2d.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/angle.h"
#include "rove/core/parallel.h"
#include "rove/registration/pose_covariance.h"
#include "rove/registration/rigid_transform.h"

namespace rove {

void Icp2dOptions::check() const {
  ROVE_CHECK_GE(max_iterations, 1u);
  ROVE_CHECK_MSG(std::isfinite(min_abs_step_trans) && min_abs_step_trans >= 0,
                 "minAbsStep_trans must be finite and >= 0, got {}", min_abs_step_trans);
  ROVE_CHECK_MSG(std::isfinite(min_abs_step_rot) && min_abs_step_rot >= 0,
                 "minAbsStep_rot must be finite and >= 0, got {}", min_abs_step_rot);
  ROVE_CHECK_MSG(std::isfinite(threshold_dist) && threshold_dist > 0,
                 "thresholdDist must be finite and > 0, got {}", threshold_dist);
  ROVE_CHECK_MSG(std::isfinite(threshold_ang) && threshold_ang >= 0,
                 "thresholdAng must be finite and >= 0, got {}", threshold_ang);
  ROVE_CHECK_MSG(alfa >= 0 && alfa < 1, "ALFA must be in [0, 1), got {}", alfa);
  ROVE_CHECK_MSG(std::isfinite(smallest_threshold_dist) && smallest_threshold_dist > 0,
                 "smallestThresholdDist must be finite and > 0, got {}", smallest_threshold_dist);
  ROVE_CHECK_GE(corresponding_points_decimation, 1u);
  ROVE_CHECK_MSG(std::isfinite(covariance_var_points) && covariance_var_points > 0,
                 "covariance_varPoints must be finite and > 0, got {}", covariance_var_points);
  ROVE_CHECK_MSG(std::isfinite(kernel_rho) && kernel_rho > 0,
                 "kernel_rho must be finite and > 0, got {}", kernel_rho);
  ROVE_CHECK_MSG(std::isfinite(lm_initial_lambda) && lm_initial_lambda > 0,
                 "LM_initial_lambda must be finite and > 0, got {}", lm_initial_lambda);
  ROVE_CHECK_GE(lm_inner_iterations, 1u);
  ROVE_CHECK_MSG(std::isfinite(axy_aprox_derivatives) && axy_aprox_derivatives > 0,
                 "Axy_aprox_derivatives must be finite and > 0, got {}", axy_aprox_derivatives);
  ROVE_CHECK_MSG(algorithm != IcpAlgorithm::LevenbergMarquardt || metric == Icp2dMetric::PointToPoint,
                 "MRPT's icpLevenbergMarquardt is point-to-point only; use "
                 "icpRobustLevenbergMarquardt for the point-to-line metric");
  ROVE_CHECK_MSG(degeneracy_threshold >= 0 && degeneracy_threshold < 1,
                 "degeneracy_threshold must be in [0, 1), got {}", degeneracy_threshold);
  ROVE_CHECK_GE(normal_neighbors, 3u);
  (void)resolve_thread_count(num_threads, "num_threads");
  ransac.check();
}

namespace {
/// MRPT reads these [ICP] keys with read_float (its TConfigParams fields are
/// double, the reads are not): the value in effect, given or default, is
/// the nearest float. Reading them the same way keeps every gate and step
/// threshold bit-identical to MRPT's.
double mrpt_float_key(const IniFile& ini, const std::string& s, const char* key, double fallback) {
  return static_cast<float>(ini.get_or<double>(s, key, fallback));
}
/// MRPT's DEG2RAD of a float read: x·float(π)/180 in float.
double mrpt_float_deg_key(const IniFile& ini, const std::string& s, const char* key, double fallback_rad) {
  const float deg = static_cast<float>(ini.get_or<double>(s, key, rad_to_deg(fallback_rad)));
  return deg * std::numbers::pi_v<float> / 180.0f;
}
}  // namespace

Icp2dOptions Icp2dOptions::from_config(const ConfigSection& section) {
  Icp2dOptions o;
  const IniFile& ini = section.ini();
  const std::string& s = section.name();
  o.algorithm = ini.has(s, "ICP_algorithm")
                    ? ini.get_enum<IcpAlgorithm>(s, "ICP_algorithm",
                                                 {{"icpClassic", IcpAlgorithm::Classic},
                                                  {"icpLevenbergMarquardt",
                                                   IcpAlgorithm::LevenbergMarquardt},
                                                  {"icpRobustLevenbergMarquardt",
                                                   IcpAlgorithm::RobustLevenbergMarquardt}})
                    : o.algorithm;
  o.covariance_method =
      ini.has(s, "ICP_covariance_method")
          ? ini.get_enum<IcpCovarianceMethod>(
                s, "ICP_covariance_method",
                {{"icpCovLinealMSE", IcpCovarianceMethod::LinearMse},
                 {"icpCovFiniteDifferences", IcpCovarianceMethod::FiniteDifferences}})
          : o.covariance_method;
  o.metric = ini.has(s, "metric")
                 ? ini.get_enum<Icp2dMetric>(s, "metric",
                                             {{"point_to_point", Icp2dMetric::PointToPoint},
                                              {"point_to_line", Icp2dMetric::PointToLine}})
                 : o.metric;
  o.fit_arithmetic =
      ini.has(s, "fit_arithmetic")
          ? ini.get_enum<Icp2dFitArithmetic>(s, "fit_arithmetic",
                                             {{"double", Icp2dFitArithmetic::Double},
                                              {"mrpt_float", Icp2dFitArithmetic::MrptFloat}})
          : o.fit_arithmetic;
  o.max_iterations = ini.get_or<unsigned>(s, "maxIterations", o.max_iterations);
  o.min_abs_step_trans = mrpt_float_key(ini, s, "minAbsStep_trans", o.min_abs_step_trans);
  o.min_abs_step_rot = mrpt_float_key(ini, s, "minAbsStep_rot", o.min_abs_step_rot);
  o.threshold_dist = mrpt_float_key(ini, s, "thresholdDist", o.threshold_dist);
  o.threshold_ang = mrpt_float_deg_key(ini, s, "thresholdAng_DEG", o.threshold_ang);
  o.alfa = mrpt_float_key(ini, s, "ALFA", o.alfa);
  o.smallest_threshold_dist =
      mrpt_float_key(ini, s, "smallestThresholdDist", o.smallest_threshold_dist);
  o.only_closest_correspondences =
      ini.get_or<bool>(s, "onlyClosestCorrespondences", o.only_closest_correspondences);
  o.only_unique_robust = ini.get_or<bool>(s, "onlyUniqueRobust", o.only_unique_robust);
  o.corresponding_points_decimation = ini.get_or<unsigned>(
      s, "corresponding_points_decimation", o.corresponding_points_decimation);
  o.covariance_var_points = mrpt_float_key(ini, s, "covariance_varPoints", o.covariance_var_points);
  o.skip_cov_calculation = ini.get_or<bool>(s, "skip_cov_calculation", o.skip_cov_calculation);
  o.use_kernel = ini.get_or<bool>(s, "use_kernel", o.use_kernel);
  o.kernel_rho = mrpt_float_key(ini, s, "kernel_rho", o.kernel_rho);
  if (ini.has(s, "robust_kernel")) {
    const std::string text = ini.get<std::string>(s, "robust_kernel");
    try {
      o.robust_kernel = parse_robust_kernel(text, ini.source());
    } catch (const ParseError& e) {
      throw ConfigError(ini.source(), s, "robust_kernel", e.problem());
    }
  }
  o.lm_initial_lambda = mrpt_float_key(ini, s, "LM_initial_lambda", o.lm_initial_lambda);
  o.lm_inner_iterations = ini.get_or<unsigned>(s, "LM_inner_iterations", o.lm_inner_iterations);
  o.do_ransac = ini.get_or<bool>(s, "doRANSAC", o.do_ransac);
  o.ransac.min_set_size = ini.get_or<unsigned>(s, "ransac_minSetSize", o.ransac.min_set_size);
  o.ransac.max_set_size = ini.get_or<unsigned>(s, "ransac_maxSetSize", o.ransac.max_set_size);
  o.ransac.n_simulations = ini.get_or<unsigned>(s, "ransac_nSimulations", o.ransac.n_simulations);
  o.ransac.mahalanobis_threshold = mrpt_float_key(
      ini, s, "ransac_mahalanobisDistanceThreshold", o.ransac.mahalanobis_threshold);
  o.ransac.normalization_std = mrpt_float_key(ini, s, "normalizationStd", o.ransac.normalization_std);
  o.ransac.fuse_by_corrs_match =
      ini.get_or<bool>(s, "ransac_fuseByCorrsMatch", o.ransac.fuse_by_corrs_match);
  o.ransac.fuse_max_diff_xy = mrpt_float_key(ini, s, "ransac_fuseMaxDiffXY", o.ransac.fuse_max_diff_xy);
  o.ransac.fuse_max_diff_phi =
      mrpt_float_deg_key(ini, s, "ransac_fuseMaxDiffPhi_DEG", o.ransac.fuse_max_diff_phi);
  o.degeneracy_threshold = ini.get_or<double>(s, "degeneracy_threshold", o.degeneracy_threshold);
  o.normal_neighbors = ini.get_or<unsigned>(s, "normal_neighbors", o.normal_neighbors);
  o.num_threads = ini.get_or<int>(s, "num_threads", o.num_threads);
  o.axy_aprox_derivatives =
      mrpt_float_key(ini, s, "Axy_aprox_derivatives", o.axy_aprox_derivatives);
  // Accepted for MRPT compatibility, without effect: rove has no separate
  // quality measure.
  (void)ini.get_or<bool>(s, "skip_quality_calculation", true);

  section.check_all_read();
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), s, "", e.message());
  }
  return o;
}

namespace {

struct Pair2 {
  std::uint32_t source = 0;  // index into the source span
  std::uint32_t target = 0;  // index into target.points()
  double sq_dist = 0;        // squared distance at pairing, m²
};

struct Matching {
  std::vector<Pair2> pairs;
  std::size_t sources_with_pair = 0;
  std::size_t sources_considered = 0;
  /// onlyUniqueRobust scratch: per target point, the index in `pairs` of its
  /// closest pair so far (kNone when untouched). Sized once per icp_2d call
  /// and reset entry by entry, so a pairing costs O(pairs), not O(target).
  std::vector<std::uint32_t> best_of_target;
  /// Per source point, its nearest target point at the last pairing that
  /// considered it (kNone: none yet). Its distance bounds the next search
  /// (see match_range). Sized once per icp_2d call.
  std::vector<std::uint32_t> last_partner;
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
};

/// Pairs the source points k·decimation + offset, k in [b, e), appending to
/// `pairs`; returns how many of them found a pair.
std::size_t match_range(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                        double c, double s, const Eigen::Vector2d& t,
                        const Eigen::Vector2d& pivot, double thr,
                        double thr_ang, std::size_t offset, std::size_t decimation,
                        bool only_closest, std::size_t b, std::size_t e,
                        std::vector<Pair2>& pairs, std::vector<Neighbor<float>>& nbrs,
                        std::uint32_t* last_partner) {
  std::size_t with_pair = 0;
  // MRPT's CPointsMap::determineMatching2D arithmetic (as Debian builds
  // MRPT 2.5.8, without its hand-written SSE2 paths), so that pairs at the
  // gate fall on the same side as MRPT's: the source points moved in float,
  // (x₀ + cos·x) − sin·y; the squared distance to the nearest map point in
  // float, as its float KD-tree computes it (the target's tree does); the
  // gate in double from MRPT's float thresholds.
  const float cf = static_cast<float>(c), sf = static_cast<float>(s);
  const float txf = static_cast<float>(t.x()), tyf = static_cast<float>(t.y());
  for (std::size_t k = b; k < e; ++k) {
    const std::size_t i = offset + k * decimation;
    const Eigen::Vector2d& p = source[i];
    if (!p.allFinite()) continue;
    if (only_closest) {
      const float px = static_cast<float>(p.x()), py = static_cast<float>(p.y());
      const float lx = txf + cf * px - sf * py;
      const float ly = tyf + sf * px + cf * py;
      const double gate = thr_ang * std::sqrt((pivot.x() - lx) * (pivot.x() - lx) +
                                              (pivot.y() - ly) * (pivot.y() - ly)) + thr;
      // The search is bounded by the gate (inclusive, a hair wider: the test
      // below is MRPT's, a float distance against a double gate), strict as
      // MRPT's. Between ICP iterations the pose moves little, so the point's
      // previous partner, given as the hint, bounds the search much tighter
      // (same result).
      std::uint32_t& lp = last_partner[i];
      const auto nn = target.tree().nearest(Eigen::Vector2f(lx, ly),
                                            static_cast<float>(gate * (1 + 1e-6)), lp);
      lp = nn ? nn->index : Matching::kNone;
      if (!nn) continue;
      const float err = nn->sq_distance;
      if (err < gate * gate) {
        pairs.push_back({static_cast<std::uint32_t>(i), nn->index, err});
        ++with_pair;
      }
    } else {
      const Eigen::Vector2d q(c * p.x() - s * p.y() + t.x(), s * p.x() + c * p.y() + t.y());
      const double gate = thr_ang * (q - pivot).norm() + thr;
      target.tree().radius(q.cast<float>(), static_cast<float>(gate), nbrs, false);
      bool any = false;
      for (const auto& nb : nbrs) {
        if (nb.sq_distance < gate * gate) {
          pairs.push_back({static_cast<std::uint32_t>(i), nb.index, nb.sq_distance});
          any = true;
        }
      }
      if (any) ++with_pair;
    }
  }
  return with_pair;
}

/// MRPT's CPointsMap::determineMatching2D / COccupancyGridMap2D matching,
/// over a KD-tree (see the header comment for the gate). Pairs come out in
/// source order.
void match(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source, const Pose2& T,
           const Eigen::Vector2d& pivot, double thr, double thr_ang, std::size_t offset,
           std::size_t decimation,
           bool only_closest, bool unique, int threads, Matching& out) {
  out.pairs.clear();
  out.sources_with_pair = 0;
  const std::size_t n = source.size();
  const std::size_t n_sel = offset < n ? (n - offset + decimation - 1) / decimation : 0;
  out.sources_considered = n_sel;
  const double c = std::cos(T.phi()), s = std::sin(T.phi());
  const Eigen::Vector2d t = T.translation();
  if (out.last_partner.size() != n) out.last_partner.assign(n, Matching::kNone);
  std::uint32_t* last = out.last_partner.data();
  if (threads <= 1 || n_sel <= kReduceBlock) {
    // Serial: straight into out.pairs, whose capacity is reused across
    // iterations (no allocation once warm).
    std::vector<Neighbor<float>> nbrs;
    out.sources_with_pair = match_range(target, source, c, s, t, pivot, thr, thr_ang, offset,
                                        decimation, only_closest, 0, n_sel, out.pairs, nbrs, last);
  } else {
    struct Acc {
      std::vector<Pair2> pairs;
      std::size_t with_pair = 0;
      Acc& operator+=(const Acc& o) {
        pairs.insert(pairs.end(), o.pairs.begin(), o.pairs.end());
        with_pair += o.with_pair;
        return *this;
      }
    };
    Acc acc = parallel_reduce(n_sel, threads, Acc{},
                                      [&](std::size_t b, std::size_t e, Acc& a) {
      std::vector<Neighbor<float>> nbrs;
      a.with_pair += match_range(target, source, c, s, t, pivot, thr, thr_ang, offset, decimation,
                                 only_closest, b, e, a.pairs, nbrs, last);
    });
    out.sources_with_pair = acc.with_pair;
    out.pairs.assign(acc.pairs.begin(), acc.pairs.end());
  }
  if (unique && !out.pairs.empty()) {
    // Each target point keeps its closest pair (ties: the lower source
    // index, i.e. the earlier pair). One pass records the winner per target
    // point, a second keeps the winners in source order.
    auto& best = out.best_of_target;
    if (best.size() != target.size()) best.assign(target.size(), Matching::kNone);
    const auto np = static_cast<std::uint32_t>(out.pairs.size());
    for (std::uint32_t r = 0; r < np; ++r) {
      std::uint32_t& w = best[out.pairs[r].target];
      if (w == Matching::kNone || out.pairs[r].sq_dist < out.pairs[w].sq_dist) w = r;
    }
    std::size_t kept = 0;
    for (std::uint32_t r = 0; r < np; ++r)
      if (best[out.pairs[r].target] == r) out.pairs[kept++] = out.pairs[r];
    out.pairs.resize(kept);
    for (const Pair2& p : out.pairs) best[p.target] = Matching::kNone;
  }
}

/// MRPT's tfest::se2_l2 (Martínez et al., J. Field Robotics 2006), in its
/// single-precision arithmetic: see Icp2dFitArithmetic::MrptFloat. "a" is
/// the target (MRPT's global) side, "b" the source (local) side. The
/// project builds with -ffp-contract=off, so no product is fused into an
/// FMA that MRPT's build does not have.
Pose2 mrpt_float_fit(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                     const std::vector<Pair2>& pairs) {
  const auto& tp = target.points();
  float sum_xa = 0, sum_ya = 0, sum_xb = 0, sum_yb = 0;
  float sxx = 0, sxy = 0, syx = 0, syy = 0;
  for (const Pair2& pr : pairs) {
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

/// The closed-form least-squares rigid motion of the pairs (Lu & Milios
/// 1997, eqs. 12-13; the arithmetic of fit_rigid_2d with unit weights,
/// without its covariance, which ICP needs only at the end).
Pose2 closed_form_fit(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                      const std::vector<Pair2>& pairs, Icp2dFitArithmetic arithmetic) {
  if (arithmetic == Icp2dFitArithmetic::MrptFloat) return mrpt_float_fit(target, source, pairs);
  const auto& tp = target.points();
  Eigen::Vector2d cs = Eigen::Vector2d::Zero(), ct = Eigen::Vector2d::Zero();
  for (const Pair2& pr : pairs) {
    cs += source[pr.source];
    ct += tp[pr.target];
  }
  const double sw = static_cast<double>(pairs.size());
  cs /= sw;
  ct /= sw;
  double s_dot = 0, s_cross = 0;
  for (const Pair2& pr : pairs) {
    const Eigen::Vector2d a = source[pr.source] - cs, b = tp[pr.target] - ct;
    s_dot += a.x() * b.x() + a.y() * b.y();
    s_cross += a.x() * b.y() - a.y() * b.x();
  }
  const double phi = std::atan2(s_cross, s_dot);
  const double c = std::cos(phi), s = std::sin(phi);
  const Eigen::Vector2d t = ct - Eigen::Vector2d(c * cs.x() - s * cs.y(), s * cs.x() + c * cs.y());
  return Pose2(t.x(), t.y(), phi);
}

/// Residual Jacobian row(s) of one pair with respect to (x, y, phi) at T:
/// point-to-point: 2×3 [I | perp(R·s)]; point-to-line: nᵀ times that.
struct Normal3 {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  double cost = 0;
  Normal3& operator+=(const Normal3& o) {
    H += o.H;
    g += o.g;
    cost += o.cost;
    return *this;
  }
};

/// Accumulates Σ w JᵀJ, Σ w Jᵀr and Σ ρ(r²) over the pairs at pose T.
template <typename Kernel>
Normal3 accumulate(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                   const std::vector<Pair2>& pairs, const Pose2& T, Icp2dMetric metric,
                   const Kernel& kernel, bool weighted, int threads) {
  const double c = std::cos(T.phi()), s = std::sin(T.phi());
  return parallel_reduce(pairs.size(), threads, Normal3{},
                                 [&](std::size_t b, std::size_t e, Normal3& a) {
    for (std::size_t k = b; k < e; ++k) {
      const Pair2& pr = pairs[k];
      const Eigen::Vector2d& p = source[pr.source];
      const Eigen::Vector2d rs(c * p.x() - s * p.y(), s * p.x() + c * p.y());
      const Eigen::Vector2d r2 = rs + T.translation() - target.points()[pr.target];
      Eigen::Matrix<double, 2, 3> J;
      J << 1, 0, -rs.y(), 0, 1, rs.x();
      if (metric == Icp2dMetric::PointToLine) {
        const Eigen::Vector2d& nrm = target.normals()[pr.target];
        const Eigen::RowVector3d Jl = nrm.transpose() * J;
        const double r = nrm.dot(r2);
        const auto kv = kernel.evaluate(r * r);
        const double w = weighted ? kv.d1 : 1.0;
        a.H += w * Jl.transpose() * Jl;
        a.g += w * Jl.transpose() * r;
        a.cost += kv.rho;
      } else {
        const auto kv = kernel.evaluate(r2.squaredNorm());
        const double w = weighted ? kv.d1 : 1.0;
        a.H += w * J.transpose() * J;
        a.g += w * J.transpose() * r2;
        a.cost += kv.rho;
      }
    }
  });
}

Pose2 apply_step(const Pose2& T, const Eigen::Vector3d& dx) {
  return Pose2(T.x() + dx(0), T.y() + dx(1), wrap_to_pi(T.phi() + dx(2)));
}

RobustKernel kernel_of(const Icp2dOptions& o) {
  if (o.robust_kernel) return *o.robust_kernel;
  if (o.use_kernel) return RobustKernel(RobustKernelType::Cauchy, o.kernel_rho);
  return RobustKernel();
}

/// Minimizes ½Σρ over fixed pairs with Levenberg–Marquardt (Nielsen's
/// damping update, Madsen–Nielsen–Tingleff 2004, eq. 3.16 / Sec. 3.2).
Pose2 lm_update(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                const std::vector<Pair2>& pairs, Pose2 T, const Icp2dOptions& o) {
  const RobustKernel kernel = kernel_of(o);
  return kernel.visit([&](const auto& k) {
    Normal3 ne = accumulate(target, source, pairs, T, o.metric, k, true, o.num_threads);
    double mu = o.lm_initial_lambda * std::max(ne.H.diagonal().maxCoeff(), 1e-12);
    double nu = 2;
    for (unsigned it = 0; it < o.lm_inner_iterations; ++it) {
      const Eigen::Matrix3d A = ne.H + mu * Eigen::Matrix3d::Identity();
      const Eigen::Vector3d h = A.ldlt().solve(-ne.g);
      if (!h.allFinite()) break;
      const Pose2 Tn = apply_step(T, h);
      const Normal3 nn = accumulate(target, source, pairs, Tn, o.metric, k, true, o.num_threads);
      const double predicted = -(h.dot(ne.g) + 0.5 * h.dot(ne.H * h));
      const double actual = 0.5 * (ne.cost - nn.cost);
      if (actual > 0 && predicted > 0) {
        const double rho = actual / predicted;
        mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2 * rho - 1, 3));
        nu = 2;
        T = Tn;
        ne = nn;
        if (h.head<2>().cwiseAbs().maxCoeff() <= o.min_abs_step_trans &&
            std::abs(h(2)) <= o.min_abs_step_rot)
          break;
      } else {
        mu *= nu;
        nu *= 2;
      }
    }
    return T;
  });
}

/// The slope at w2 of the parabola through (w1, q1), (w2, q2), (w3, q3):
/// MRPT's three-point derivative of its LM gradient, in its order of
/// operations (double).
double parabola_slope(double w1, double w2, double w3, double q1, double q2, double q3) {
  const double a = ((q3 - q2) / ((w3 - w2) * (w3 - w1))) - ((q1 - q2) / ((w1 - w2) * (w3 - w1)));
  const double b = ((q1 - q2) + (a * ((w2 * w2) - (w1 * w1)))) / (w1 - w2);
  return (2 * a * w2) + b;
}

/// The pairs' coordinates as MRPT's TMatchingPairList holds them (float),
/// by column: the source ("local") and the map ("global") point of each.
struct FloatPairs {
  std::vector<float> lx, ly, gx, gy;
  FloatPairs(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
             const std::vector<Pair2>& pairs) {
    const auto& tp = target.points();
    const std::size_t n = pairs.size();
    lx.resize(n);
    ly.resize(n);
    gx.resize(n);
    gy.resize(n);
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
float mrpt_square_errors(const FloatPairs& fp, const Pose2& p, float* e, float* xs, float* ys) {
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
template <class In, class Out>
void mrpt_inverse_llt(const In& A, Out& X) {
  float L[3][3] = {};
  L[0][0] = std::sqrt(A(0, 0));
  L[1][0] = A(1, 0) / L[0][0];
  L[2][0] = A(2, 0) / L[0][0];
  L[1][1] = std::sqrt(A(1, 1) - L[1][0] * L[1][0]);
  L[2][1] = (A(2, 1) - L[2][0] * L[1][0]) / L[1][1];
  L[2][2] = std::sqrt(A(2, 2) - (L[2][0] * L[2][0] + L[2][1] * L[2][1]));
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
}

/// One pairing of MRPT's icpLevenbergMarquardt (see IcpAlgorithm) in MRPT
/// 2.5.8's arithmetic, so that runs reproduce MRPT's: the gradient J
/// (3 × pairs) of the kernelized squared distances by finite differences
/// (distances to the nearest map point in float, as its float KD-tree;
/// the kernel x²/(x² + ρ²) in float; slopes in double, stored in float),
/// H = J·Jᵀ summed in float, then damped steps x ← x − (H + λ·diag H)⁻¹·J·e
/// on the fixed J and e, with the 3×3 inverse (MRPT's inverse_LLt) and the
/// product C⁻¹·J·e computed in the order Eigen evaluates MRPT's expressions
/// (mrpt_inverse_llt; the loop below), so the sums round as MRPT's do.
Pose2 mrpt_lm_update(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                     const std::vector<Pair2>& pairs, Pose2 q, const Icp2dOptions& o) {
  const std::size_t n = pairs.size();
  const float rho2 = static_cast<float>(o.kernel_rho * o.kernel_rho);
  const auto kern = [&](float x2) -> float { return o.use_kernel ? x2 / (x2 + rho2) : x2; };
  // Squared distance from (x, y) to its nearest map point, in float (the
  // target's tree computes it as MRPT's). The query is a source point
  // shifted by ±Axy: its pair's map point, given as the hint, bounds the
  // search (the same nearest point as an unbounded search, far fewer nodes).
  constexpr float kNoBound = std::numeric_limits<float>::infinity();
  const auto nearest_sq = [&](float x, float y, std::uint32_t partner) -> float {
    return target.tree().nearest(Eigen::Vector2f(x, y), kNoBound, partner)->sq_distance;
  };
  const FloatPairs fp(target, source, pairs);
  std::vector<float> e(n), xs(n), ys(n);
  double ose = mrpt_square_errors(fp, q, e.data(), xs.data(), ys.data());
  const double c = std::cos(q.phi()), s = std::sin(q.phi());
  const double axy = o.axy_aprox_derivatives;
  // The Jacobian, 3 × n (MRPT's CMatrixFloat dJ_dq), by rows.
  std::array<std::vector<float>, 3> J;
  for (auto& row : J) row.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const float xk = xs[k], yk = ys[k];
    const float gx = fp.gx[k], gy = fp.gy[k];
    const double lx = fp.lx[k], ly = fp.ly[k];  // MRPT's float local point
    // ∂/∂x: distances to the nearest map point at x − Axy, x, x + Axy.
    const double x1 = xk - axy, x3 = xk + axy;
    const std::uint32_t partner = pairs[k].target;
    // At (x, y) itself the nearest map point is the pair's: the pairing
    // moved the point to the same float coordinates (same formula, same
    // pose) and kept the nearest point's float distance.
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
  // H = J·Jᵀ (MRPT's matProductOf_AAt: float sums in order).
  // The six sums in one pass (independent chains, each in MRPT's order).
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
    Eigen::Matrix3f C_inv;
    mrpt_inverse_llt(C, C_inv);
    // MRPT's (C⁻¹·J·e) as Eigen evaluates it, without its 3 × n temporary:
    // T(i, k) = c₀J₀ₖ + (c₁J₁ₖ + c₂J₂ₖ), then Σₖ T(i, k)·eₖ in order (checked
    // bit for bit against the Eigen expression over MRPT's types).
    // The three rows in one pass: three independent chains of float adds,
    // each in MRPT's order (a sum per row would wait on one add latency per
    // pair, three times over).
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
    const float ose_new = mrpt_square_errors(fp, q_new, nullptr, nullptr, nullptr);
    keep = std::abs(delta[0]) > o.min_abs_step_trans || std::abs(delta[1]) > o.min_abs_step_trans ||
           std::abs(delta[2]) > o.min_abs_step_rot;
    if (ose_new < ose) {
      lambda /= 10;
      q = q_new;
      ose = ose_new;
    } else {
      lambda *= 10;
    }
  }
  return q;
}

}  // namespace

Icp2dResult icp_2d(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                   const Pose2Gaussian& initial_T_target_source, const Icp2dOptions& options) {
  return icp_2d(target, source, initial_T_target_source.mean(), options);
}

Icp2dResult icp_2d(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                   const Pose2& initial, const Icp2dOptions& options) {
  options.check();
  // 0 threads means all hardware threads; the count is resolved once here.
  Icp2dOptions o = options;
  o.num_threads = resolve_thread_count(options.num_threads, "num_threads");
  ROVE_CHECK_MSG(o.metric != Icp2dMetric::PointToLine || target.has_normals(),
                 "the point-to-line metric needs target normals: build the IcpTarget2D with "
                 "normal_neighbors > 0");
  ROVE_CHECK_MSG(source.size() < std::numeric_limits<std::uint32_t>::max(),
                 "at most 2^32-1 source points, got {}", source.size());
  Icp2dResult res;
  res.T_target_source = Pose2Gaussian(initial);
  res.conditioning = std::numeric_limits<double>::quiet_NaN();
  const std::size_t finite =
      std::count_if(source.begin(), source.end(), [](const auto& p) { return p.allFinite(); });
  if (target.empty() || finite == 0) {
    res.termination = RegistrationTermination::InvalidInput;
    res.message = target.empty() ? "the target has no point" : "the source has no finite point";
    return res;
  }
  const std::size_t min_pairs = o.metric == Icp2dMetric::PointToLine ? 3 : 2;
  const std::size_t decimation = o.corresponding_points_decimation;

  Pose2 pose = initial, last = initial;
  // MRPT keeps the two gates in float (TMatchingParams): every shrink is
  // rounded to float, and the gate compares as MRPT's does.
  float thr = static_cast<float>(o.threshold_dist), thr_ang = static_cast<float>(o.threshold_ang);
  std::size_t offset = 0;
  unsigned iterations = 0;
  bool keep_approaching = true;
  bool too_few = false, diverged = false, settled = false;
  Matching m;
  // MRPT's icpLevenbergMarquardt measures the gate widening from the target
  // frame's origin; the other methods from the current pose.
  const bool mrpt_lm = o.algorithm == IcpAlgorithm::LevenbergMarquardt;
  do {
    const Eigen::Vector2d pivot = mrpt_lm ? Eigen::Vector2d::Zero() : pose.translation();
    // MRPT's LM always pairs each point with its nearest target point.
    match(target, source, pose, pivot, thr, thr_ang,
          offset % std::max<std::size_t>(decimation, 1), decimation,
          mrpt_lm || o.only_closest_correspondences, o.only_unique_robust, o.num_threads, m);
    if (m.pairs.size() < min_pairs) {
      keep_approaching = false;
      too_few = true;
      ++iterations;
      break;
    }
    Pose2 next = pose;
    if (o.algorithm == IcpAlgorithm::Classic && o.metric == Icp2dMetric::PointToPoint) {
      next = closed_form_fit(target, source, m.pairs, o.fit_arithmetic);
    } else if (o.algorithm == IcpAlgorithm::Classic) {
      const Normal3 ne = accumulate(target, source, m.pairs, pose, o.metric, TrivialKernel{},
                                    false, o.num_threads);
      const Eigen::Vector3d h = ne.H.ldlt().solve(-ne.g);
      if (h.allFinite()) next = apply_step(pose, h);
    } else if (mrpt_lm) {
      next = mrpt_lm_update(target, source, m.pairs, pose, o);
    } else {
      next = lm_update(target, source, m.pairs, pose, o);
    }
    if (!std::isfinite(next.x()) || !std::isfinite(next.y()) || !std::isfinite(next.phi()) ||
        (next.translation() - pose.translation()).norm() > 1e6) {
      diverged = true;
      ++iterations;
      break;
    }
    pose = next;
    keep_approaching = true;
    if (!(std::abs(last.x() - pose.x()) > o.min_abs_step_trans ||
          std::abs(last.y() - pose.y()) > o.min_abs_step_trans ||
          std::abs(wrap_to_pi(last.phi() - pose.phi())) > o.min_abs_step_rot)) {
      thr = static_cast<float>(thr * o.alfa);
      thr_ang = static_cast<float>(thr_ang * o.alfa);
      if (thr < o.smallest_threshold_dist) {
        keep_approaching = false;
        if (iterations < o.max_iterations) settled = true;
      }
      if (++offset >= decimation) offset = 0;
    }
    last = pose;
    ++iterations;
    if (iterations >= o.max_iterations && thr > o.smallest_threshold_dist)
      thr = static_cast<float>(thr * o.alfa);
  } while ((keep_approaching && iterations < o.max_iterations) ||
           (iterations >= o.max_iterations && thr > o.smallest_threshold_dist));

  res.iterations = iterations;
  res.final_threshold_dist = thr;
  res.correspondences = m.pairs.size();
  // MRPT's correspondencesRatio, in its float arithmetic: decimation ×
  // (points with a pair) / (all points), so with decimation the share of
  // the points considered is measured against N / decimation, not their
  // integer count. (Capped at 1: with N not a multiple of the decimation
  // and every point paired MRPT reports slightly more.)
  const std::size_t finite_points = finite;
  res.goodness =
      finite_points == 0
          ? 0.0
          : std::min(1.0, static_cast<double>(static_cast<float>(std::max<std::size_t>(decimation, 1) *
                                                                 m.sources_with_pair) /
                                              static_cast<float>(finite_points)));
  double sse = 0;
  for (const auto& p : m.pairs) sse += p.sq_dist;
  res.fitness = m.pairs.empty() ? 0.0 : sse / static_cast<double>(m.pairs.size());

  if (diverged) {
    res.T_target_source = Pose2Gaussian(pose);
    res.termination = RegistrationTermination::Diverged;
    res.message = fmt::format("the pose update became non-finite or unbounded at iteration {}",
                              iterations);
    return res;
  }
  if (too_few) {
    res.T_target_source = Pose2Gaussian(pose);
    res.termination = RegistrationTermination::TooFewCorrespondences;
    res.message = fmt::format("{} pair(s) at iteration {} (gate {:.3g} m); {} needed",
                              m.pairs.size(), iterations, thr, min_pairs);
    return res;
  }

  // Covariance: σ²·H⁻¹ of the final pairs (header comment).
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  if (!o.skip_cov_calculation) {
    const bool weighted = o.covariance_method == IcpCovarianceMethod::FiniteDifferences;
    const Normal3 ne = kernel_of(o).visit([&](const auto& k) {
      return accumulate(target, source, m.pairs, pose, o.metric, k, weighted, o.num_threads);
    });
    cov = covariance_from_information<3>(ne.H, o.covariance_var_points, 1e-12);
  }
  res.T_target_source = Pose2Gaussian(detail::kUnchecked, pose, cov);

  // Degeneracy: point-to-line information about the pairs' centroid.
  bool degenerate = false;
  if (o.degeneracy_threshold > 0) {
    const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
    std::vector<Eigen::Vector2d> q(m.pairs.size());
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (std::size_t k = 0; k < m.pairs.size(); ++k) {
      const Eigen::Vector2d& p = source[m.pairs[k].source];
      q[k] = Eigen::Vector2d(c * p.x() - s * p.y(), s * p.x() + c * p.y()) + pose.translation();
      centroid += q[k];
    }
    centroid /= static_cast<double>(q.size());
    double r2 = 0;
    for (const auto& x : q) r2 += (x - centroid).squaredNorm();
    const double L = std::sqrt(r2 / static_cast<double>(q.size()));
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    std::vector<Neighbor<float>> nn(o.normal_neighbors);
    for (std::size_t k = 0; k < m.pairs.size(); ++k) {
      Eigen::Vector2d nrm;
      if (target.has_normals()) {
        nrm = target.normals()[m.pairs[k].target];
      } else {
        const Eigen::Vector2d& tp = target.points()[m.pairs[k].target];
        const std::size_t cnt = target.tree().knn(tp.cast<float>(), o.normal_neighbors, nn);
        Eigen::Vector2d mean = Eigen::Vector2d::Zero();
        for (std::size_t j = 0; j < cnt; ++j) mean += target.points()[nn[j].index];
        mean /= static_cast<double>(std::max<std::size_t>(cnt, 1));
        Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
        for (std::size_t j = 0; j < cnt; ++j) {
          const Eigen::Vector2d d = target.points()[nn[j].index] - mean;
          C += d * d.transpose();
        }
        nrm = C.trace() > 0 ? Eigen::Vector2d(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(C)
                                                  .eigenvectors()
                                                  .col(0))
                            : Eigen::Vector2d::Zero();
      }
      const Eigen::Vector2d d = q[k] - centroid;
      const double rot = L > 0 ? (nrm.y() * d.x() - nrm.x() * d.y()) / L : 0.0;
      const Eigen::Vector3d j(nrm.x(), nrm.y(), rot);
      A += j * j.transpose();
    }
    const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(A).eigenvalues();
    res.conditioning = ev(2) > 0 ? std::max(ev(0), 0.0) / ev(2) : 0.0;
    degenerate = res.conditioning < o.degeneracy_threshold;
  }

  if (o.do_ransac) {
    std::vector<Eigen::Vector2d> tp(m.pairs.size()), sp(m.pairs.size());
    for (std::size_t k = 0; k < m.pairs.size(); ++k) {
      tp[k] = target.points()[m.pairs[k].target];
      sp[k] = source[m.pairs[k].source];
    }
    const RansacRigid2dResult rr = ransac_rigid_2d(tp, sp, o.ransac);
    res.sog = rr.sog;
  }

  if (degenerate) {
    res.termination = RegistrationTermination::Degenerate;
    res.message = fmt::format(
        "the matched geometry leaves a direction unconstrained (conditioning {:.3g} < {:.3g}, "
        "e.g. a corridor)",
        res.conditioning, o.degeneracy_threshold);
  } else if (!settled) {
    res.termination = RegistrationTermination::MaxIterations;
    res.message = fmt::format("maxIterations ({}) reached before the gate settled; {} iterations "
                              "in all, final gate {:.3g} m",
                              o.max_iterations, iterations, thr);
  } else {
    res.termination = RegistrationTermination::Converged;
    res.message = fmt::format("converged in {} iterations, {} pairs, goodness {:.3f}", iterations,
                              res.correspondences, res.goodness);
  }
  return res;
}

}  // namespace rove
