#include "rove/registration/icp_2d.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/angle.h"
#include "rove/core/parallel.h"
#include "rove/registration/degeneracy.h"
#include "rove/poses/lie_conversion.h"
#include "rove/registration/pose_covariance.h"
#include "rove/registration/rigid_transform.h"
#include "icp_2d_internal.h"
#include "rigid_fit_internal.h"

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
/// A key in degrees read into radians (MRPT's *_DEG keys).
double deg_key(const IniFile& ini, const std::string& s, const char* key, double fallback_rad) {
  return ini.has(s, key) ? deg_to_rad(ini.get<double>(s, key)) : fallback_rad;
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
  o.arithmetic = ini.has(s, "arithmetic")
                     ? ini.get_enum<Arithmetic>(s, "arithmetic", kArithmeticNames)
                     : o.arithmetic;
  o.max_iterations = ini.get_or<unsigned>(s, "maxIterations", o.max_iterations);
  o.min_abs_step_trans = ini.get_or<double>(s, "minAbsStep_trans", o.min_abs_step_trans);
  o.min_abs_step_rot = ini.get_or<double>(s, "minAbsStep_rot", o.min_abs_step_rot);
  o.threshold_dist = ini.get_or<double>(s, "thresholdDist", o.threshold_dist);
  o.threshold_ang = deg_key(ini, s, "thresholdAng_DEG", o.threshold_ang);
  o.alfa = ini.get_or<double>(s, "ALFA", o.alfa);
  o.smallest_threshold_dist =
      ini.get_or<double>(s, "smallestThresholdDist", o.smallest_threshold_dist);
  o.only_closest_correspondences =
      ini.get_or<bool>(s, "onlyClosestCorrespondences", o.only_closest_correspondences);
  o.only_unique_robust = ini.get_or<bool>(s, "onlyUniqueRobust", o.only_unique_robust);
  o.corresponding_points_decimation = ini.get_or<unsigned>(
      s, "corresponding_points_decimation", o.corresponding_points_decimation);
  o.covariance_var_points = ini.get_or<double>(s, "covariance_varPoints", o.covariance_var_points);
  o.skip_cov_calculation = ini.get_or<bool>(s, "skip_cov_calculation", o.skip_cov_calculation);
  o.use_kernel = ini.get_or<bool>(s, "use_kernel", o.use_kernel);
  o.kernel_rho = ini.get_or<double>(s, "kernel_rho", o.kernel_rho);
  if (ini.has(s, "robust_kernel")) {
    const std::string text = ini.get<std::string>(s, "robust_kernel");
    try {
      o.robust_kernel = parse_robust_kernel(text, ini.source());
    } catch (const ParseError& e) {
      throw ConfigError(ini.source(), s, "robust_kernel", e.problem());
    }
  }
  o.lm_initial_lambda = ini.get_or<double>(s, "LM_initial_lambda", o.lm_initial_lambda);
  o.lm_inner_iterations = ini.get_or<unsigned>(s, "LM_inner_iterations", o.lm_inner_iterations);
  o.do_ransac = ini.get_or<bool>(s, "doRANSAC", o.do_ransac);
  o.ransac.min_set_size = ini.get_or<unsigned>(s, "ransac_minSetSize", o.ransac.min_set_size);
  o.ransac.max_set_size = ini.get_or<unsigned>(s, "ransac_maxSetSize", o.ransac.max_set_size);
  o.ransac.n_simulations = ini.get_or<unsigned>(s, "ransac_nSimulations", o.ransac.n_simulations);
  o.ransac.mahalanobis_threshold = ini.get_or<double>(s, "ransac_mahalanobisDistanceThreshold", o.ransac.mahalanobis_threshold);
  o.ransac.normalization_std = ini.get_or<double>(s, "normalizationStd", o.ransac.normalization_std);
  o.ransac.fuse_by_corrs_match =
      ini.get_or<bool>(s, "ransac_fuseByCorrsMatch", o.ransac.fuse_by_corrs_match);
  o.ransac.fuse_max_diff_xy = ini.get_or<double>(s, "ransac_fuseMaxDiffXY", o.ransac.fuse_max_diff_xy);
  o.ransac.fuse_max_diff_phi =
      deg_key(ini, s, "ransac_fuseMaxDiffPhi_DEG", o.ransac.fuse_max_diff_phi);
  o.degeneracy_threshold = ini.get_or<double>(s, "degeneracy_threshold", o.degeneracy_threshold);
  o.normal_neighbors = ini.get_or<unsigned>(s, "normal_neighbors", o.normal_neighbors);
  o.num_threads = ini.get_or<int>(s, "num_threads", o.num_threads);
  o.axy_aprox_derivatives =
      ini.get_or<double>(s, "Axy_aprox_derivatives", o.axy_aprox_derivatives);
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


namespace detail {
template std::size_t icp2d_match_range(const KdTree<2, double>&, const Icp2dMatchInput&,
                                       std::size_t, std::size_t, std::vector<Icp2dPair>&,
                                       std::vector<Neighbor<double>>&, std::uint32_t*);
}  // namespace detail

namespace {

using detail::Icp2dMatching;
using detail::Icp2dPair;

/// onlyUniqueRobust: each target point keeps its closest pair (ties: the
/// lower source index, i.e. the earlier pair). One pass records the winner
/// per target point, a second keeps the winners in source order.
void keep_closest_per_target(std::size_t target_size, Icp2dMatching& out) {
  auto& best = out.best_of_target;
  if (best.size() != target_size) best.assign(target_size, Icp2dMatching::kNone);
  const auto np = static_cast<std::uint32_t>(out.pairs.size());
  for (std::uint32_t r = 0; r < np; ++r) {
    std::uint32_t& w = best[out.pairs[r].target];
    if (w == Icp2dMatching::kNone || out.pairs[r].sq_dist < out.pairs[w].sq_dist) w = r;
  }
  std::size_t kept = 0;
  for (std::uint32_t r = 0; r < np; ++r)
    if (best[out.pairs[r].target] == r) out.pairs[kept++] = out.pairs[r];
  out.pairs.resize(kept);
  for (const Icp2dPair& p : out.pairs) best[p.target] = Icp2dMatching::kNone;
}

/// MRPT's CPointsMap::determineMatching2D / COccupancyGridMap2D matching,
/// over the target's KD-tree (see the header comment for the gate). Pairs
/// come out in source order.
template <typename Scalar>
void match_in(const KdTree<2, Scalar>& tree, const detail::Icp2dMatchInput& in, int threads,
              Icp2dMatching& out) {
  out.pairs.clear();
  out.sources_with_pair = 0;
  const std::size_t n = in.source.size(), dec = in.decimation;
  const std::size_t n_sel = in.offset < n ? (n - in.offset + dec - 1) / dec : 0;
  out.sources_considered = n_sel;
  if (out.last_partner.size() != n) out.last_partner.assign(n, Icp2dMatching::kNone);
  std::uint32_t* last = out.last_partner.data();
  if (threads <= 1 || n_sel <= kReduceBlock) {
    // Serial: straight into out.pairs, whose capacity is reused across
    // iterations (no allocation once warm).
    std::vector<Neighbor<Scalar>> nbrs;
    out.sources_with_pair = detail::icp2d_match_range(tree, in, 0, n_sel, out.pairs, nbrs, last);
    return;
  }
  struct Acc {
    std::vector<Icp2dPair> pairs;
    std::size_t with_pair = 0;
    Acc& operator+=(const Acc& o) {
      pairs.insert(pairs.end(), o.pairs.begin(), o.pairs.end());
      with_pair += o.with_pair;
      return *this;
    }
  };
  Acc acc = parallel_reduce(n_sel, threads, Acc{}, [&](std::size_t b, std::size_t e, Acc& a) {
    std::vector<Neighbor<Scalar>> nbrs;
    a.with_pair += detail::icp2d_match_range(tree, in, b, e, a.pairs, nbrs, last);
  });
  out.sources_with_pair = acc.with_pair;
  out.pairs.assign(acc.pairs.begin(), acc.pairs.end());
}

void match(const IcpTarget2D& target, const detail::Icp2dMatchInput& in, bool unique, int threads,
           Icp2dMatching& out) {
  target.with_tree([&](const auto& tree) { match_in(tree, in, threads, out); });
  if (unique && !out.pairs.empty()) keep_closest_per_target(target.size(), out);
}

/// The closed-form least-squares rigid motion of the pairs (Lu & Milios
/// 1997, eqs. 12-13, about the centroids; rigid_fit_2d without weights and
/// covariance, which ICP needs only at the end).
Pose2 closed_form_fit(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                      const std::vector<Icp2dPair>& pairs) {
  const auto& tp = target.points();
  const auto src = [&](std::size_t k) -> const Eigen::Vector2d& { return source[pairs[k].source]; };
  const auto tgt = [&](std::size_t k) -> const Eigen::Vector2d& { return tp[pairs[k].target]; };
  const auto unit = [](std::size_t) { return 1.0; };
  return detail::centered_rigid_fit_2d(pairs.size(), src, tgt, unit,
                                       detail::weighted_centroids<2>(pairs.size(), src, tgt, unit));
}

/// Σ w JᵀJ, Σ w Jᵀr and Σ ρ(r²) of the pairs at a pose; the residual
/// Jacobian of a pair with respect to (x, y, phi) is, point-to-point, 2×3
/// [I | perp(R·s)], point-to-line nᵀ times that.
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
                   const std::vector<Icp2dPair>& pairs, const Pose2& T, Icp2dMetric metric,
                   const Kernel& kernel, bool weighted, int threads) {
  const double c = std::cos(T.phi()), s = std::sin(T.phi());
  return parallel_reduce(pairs.size(), threads, Normal3{},
                         [&](std::size_t b, std::size_t e, Normal3& a) {
    for (std::size_t k = b; k < e; ++k) {
      const Icp2dPair& pr = pairs[k];
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
                const std::vector<Icp2dPair>& pairs, Pose2 T, const Icp2dOptions& o) {
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

/// One pairing of MRPT's icpLevenbergMarquardt (IcpAlgorithm) in double
/// precision: the gradient J (3 × pairs) of the kernelized squared distances
/// by three-point finite differences of step Axy (x: distances to the
/// nearest target point; y: to the pair's own point, as MRPT), H = J·Jᵀ,
/// then damped steps x ← x − (H + λ·diag H)⁻¹·J·e on the fixed J and the
/// pairs' squared errors e, λ ÷ 10 on a lower Σe and × 10 otherwise, until
/// a step is below minAbsStep (at most 99). Arithmetic::Mrpt runs MRPT's
/// float version (icp_2d_mrpt.cpp).
Pose2 finite_difference_lm(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                           const std::vector<Icp2dPair>& pairs, Pose2 q, const Icp2dOptions& o) {
  const std::size_t n = pairs.size();
  const auto& tp = target.points();
  const double rho2 = o.kernel_rho * o.kernel_rho;
  const auto kern = [&](double x2) { return o.use_kernel ? x2 / (x2 + rho2) : x2; };
  Eigen::Matrix2Xd moved(2, n);
  Eigen::VectorXd e(n);
  // Σ of the pairs' squared errors at p (and, if `keep`, the moved points
  // and the errors).
  const auto errors = [&](const Pose2& p, bool keep) {
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(p.phi()).toRotationMatrix();
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector2d x = R * source[pairs[k].source] + p.translation();
      const double ek = (tp[pairs[k].target] - x).squaredNorm();
      if (keep) {
        moved.col(static_cast<Eigen::Index>(k)) = x;
        e(static_cast<Eigen::Index>(k)) = ek;
      }
      sum += ek;
    }
    return sum;
  };
  const auto nearest_sq = [&](double x, double y, std::uint32_t partner) {
    return target.tree()
        .nearest(Eigen::Vector2d(x, y), std::numeric_limits<double>::infinity(), partner)
        ->sq_distance;
  };
  double ose = errors(q, true);
  const double c = std::cos(q.phi()), s = std::sin(q.phi()), a = o.axy_aprox_derivatives;
  Eigen::Matrix3Xd J(3, n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto col = static_cast<Eigen::Index>(k);
    const Eigen::Vector2d& l = source[pairs[k].source];
    const Eigen::Vector2d& g = tp[pairs[k].target];
    const double x = moved(0, col), y = moved(1, col), mid = kern(e(col));
    const std::uint32_t partner = pairs[k].target;
    J(0, col) = detail::parabola_slope(x - a, x, x + a, kern(nearest_sq(x - a, y, partner)), mid,
                                       kern(nearest_sq(x + a, y, partner)));
    const double fx2 = (g.x() - x) * (g.x() - x);
    const double below = g.y() - (y - a), above = g.y() - (y + a);
    J(1, col) = detail::parabola_slope(y - a, y, y + a, kern(fx2 + below * below), mid,
                                       kern(fx2 + above * above));
    J(2, col) = J(0, col) * (-s * l.x() - c * l.y()) + J(1, col) * (c * l.x() - s * l.y());
  }
  const Eigen::Matrix3d H = J * J.transpose();
  const Eigen::Vector3d Je = J * e;
  double lambda = o.lm_initial_lambda;
  for (unsigned it = 1; it < 100; ++it) {
    Eigen::Matrix3d C = H;
    C.diagonal() *= 1 + lambda;
    const Eigen::LLT<Eigen::Matrix3d> llt(C);
    if (llt.info() != Eigen::Success) break;
    const Eigen::Vector3d delta = llt.solve(Je);
    if (!delta.allFinite()) break;
    const Pose2 q_new(q.x() - delta(0), q.y() - delta(1), q.phi() - delta(2));
    const double ose_new = errors(q_new, false);
    detail::lm_accept_or_damp(q_new, ose_new, q, ose, lambda);
    if (delta.head<2>().cwiseAbs().maxCoeff() <= o.min_abs_step_trans &&
        std::abs(delta(2)) <= o.min_abs_step_rot)
      break;
  }
  return q;
}

/// The pose after one pairing: the update of the chosen algorithm on the
/// pairs.
Pose2 next_pose(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                const std::vector<Icp2dPair>& pairs, const Pose2& pose, const Icp2dOptions& o) {
  const bool mrpt = o.arithmetic == Arithmetic::Mrpt;
  switch (o.algorithm) {
    case IcpAlgorithm::Classic:
      if (o.metric == Icp2dMetric::PointToPoint) {
        return mrpt ? detail::mrpt_se2_l2_fit(target, source, pairs)
                    : closed_form_fit(target, source, pairs);
      } else {
        const Normal3 ne = accumulate(target, source, pairs, pose, o.metric, TrivialKernel{},
                                      false, o.num_threads);
        const Eigen::Vector3d h = ne.H.ldlt().solve(-ne.g);
        return h.allFinite() ? apply_step(pose, h) : pose;
      }
    case IcpAlgorithm::LevenbergMarquardt:
      return mrpt ? detail::mrpt_finite_difference_lm(target, source, pairs, pose, o)
                  : finite_difference_lm(target, source, pairs, pose, o);
    case IcpAlgorithm::RobustLevenbergMarquardt:
      return lm_update(target, source, pairs, pose, o);
  }
  return pose;
}

/// Where MRPT's gate schedule left the run.
struct IcpLoop {
  Pose2 pose;
  double thr = 0;  // the pairing gate when the run ended
  unsigned iterations = 0;
  bool too_few = false, diverged = false, settled = false;
  Icp2dMatching m;
};

/// The pairing / update iterations with MRPT's gate schedule (header
/// comment). With Arithmetic::Mrpt the gates are kept and shrunk in float,
/// as MRPT's TMatchingParams holds them.
IcpLoop iterate(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                const Pose2& initial, const Icp2dOptions& o, std::size_t min_pairs) {
  const auto gate = [&](double v) {
    return o.arithmetic == Arithmetic::Mrpt ? static_cast<double>(static_cast<float>(v)) : v;
  };
  const std::size_t decimation = o.corresponding_points_decimation;
  // MRPT's icpLevenbergMarquardt measures the gate widening from the target
  // frame's origin and pairs each point with its nearest target point; the
  // other methods measure from the current pose.
  const bool mrpt_lm = o.algorithm == IcpAlgorithm::LevenbergMarquardt;
  IcpLoop run;
  run.pose = initial;
  Pose2 last = initial;
  double thr = gate(o.threshold_dist), thr_ang = gate(o.threshold_ang);
  std::size_t offset = 0;
  bool keep_approaching = true;
  do {
    detail::Icp2dMatchInput in{source, std::cos(run.pose.phi()), std::sin(run.pose.phi()),
                               run.pose.translation(),
                               mrpt_lm ? Eigen::Vector2d::Zero() : run.pose.translation(),
                               thr, thr_ang, offset, decimation,
                               mrpt_lm || o.only_closest_correspondences};
    match(target, in, o.only_unique_robust, o.num_threads, run.m);
    ++run.iterations;
    if (run.m.pairs.size() < min_pairs) {
      run.too_few = true;
      break;
    }
    const Pose2 next = next_pose(target, source, run.m.pairs, run.pose, o);
    if (!std::isfinite(next.x()) || !std::isfinite(next.y()) || !std::isfinite(next.phi()) ||
        (next.translation() - run.pose.translation()).norm() > 1e6) {
      run.diverged = true;
      break;
    }
    run.pose = next;
    keep_approaching = true;
    if (!(std::abs(last.x() - run.pose.x()) > o.min_abs_step_trans ||
          std::abs(last.y() - run.pose.y()) > o.min_abs_step_trans ||
          std::abs(wrap_to_pi(last.phi() - run.pose.phi())) > o.min_abs_step_rot)) {
      thr = gate(thr * o.alfa);
      thr_ang = gate(thr_ang * o.alfa);
      if (thr < o.smallest_threshold_dist) {
        keep_approaching = false;
        if (run.iterations <= o.max_iterations) run.settled = true;
      }
      if (++offset >= decimation) offset = 0;
    }
    last = run.pose;
    if (run.iterations >= o.max_iterations && thr > o.smallest_threshold_dist) thr = gate(thr * o.alfa);
  } while ((keep_approaching && run.iterations < o.max_iterations) ||
           (run.iterations >= o.max_iterations && thr > o.smallest_threshold_dist));
  run.thr = thr;
  return run;
}

/// λmin/λmax of the point-to-line information of the pairs at `pose`: the
/// target normals at the matched points, the rotation about the pairs'
/// centroid scaled by their RMS radius (so that the ratio compares meters
/// with meters).
double pair_conditioning(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                         const std::vector<Icp2dPair>& pairs, const Pose2& pose,
                         std::size_t normal_neighbors) {
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  std::vector<Eigen::Vector2d> q(pairs.size());
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Eigen::Vector2d& p = source[pairs[k].source];
    q[k] = Eigen::Vector2d(c * p.x() - s * p.y(), s * p.x() + c * p.y()) + pose.translation();
    centroid += q[k];
  }
  centroid /= static_cast<double>(q.size());
  double r2 = 0;
  for (const auto& x : q) r2 += (x - centroid).squaredNorm();
  const double L = std::sqrt(r2 / static_cast<double>(q.size()));
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Eigen::Vector2d nrm = target.normal_at(pairs[k].target, normal_neighbors);
    const Eigen::Vector2d d = q[k] - centroid;
    const double rot = L > 0 ? (nrm.y() * d.x() - nrm.x() * d.y()) / L : 0.0;
    const Eigen::Vector3d j(nrm.x(), nrm.y(), rot);
    A += j * j.transpose();
  }
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(A).eigenvalues();
  return ev(2) > 0 ? std::max(ev(0), 0.0) / ev(2) : 0.0;
}

/// The termination of a run that neither diverged nor ran out of pairs.
void set_termination(const Icp2dOptions& o, const IcpLoop& run, bool degenerate,
                     Icp2dResult& res) {
  if (degenerate) {
    res.termination = RegistrationTermination::Degenerate;
    res.message = degenerate_geometry_message(res.conditioning, o.degeneracy_threshold,
                                              "a corridor");
  } else if (!run.settled) {
    res.termination = RegistrationTermination::MaxIterations;
    res.message = fmt::format("maxIterations ({}) reached before the gate settled; {} iterations "
                              "in all, final gate {:.3g} m",
                              o.max_iterations, run.iterations, run.thr);
  } else {
    res.termination = RegistrationTermination::Converged;
    res.message = fmt::format("converged in {} iterations, {} pairs, goodness {:.3f}",
                              run.iterations, res.correspondences, res.goodness);
  }
}

}  // namespace

Icp2dResult icp_2d(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                   const SE2d& initial_T_target_source, const Icp2dOptions& options) {
  options.check();
  ROVE_CHECK_MSG(target.arithmetic() == options.arithmetic,
                 "the IcpTarget2D was built for arithmetic '{}' but the ICP runs in '{}': set "
                 "IcpTarget2DOptions::arithmetic as Icp2dOptions::arithmetic",
                 to_string(target.arithmetic()), to_string(options.arithmetic));
  // 0 threads means all hardware threads; the count is resolved once here.
  Icp2dOptions o =
      options.arithmetic == Arithmetic::Mrpt ? detail::mrpt_rounded_options(options) : options;
  o.num_threads = resolve_thread_count(options.num_threads, "num_threads");
  ROVE_CHECK_MSG(o.metric != Icp2dMetric::PointToLine || target.has_normals(),
                 "the point-to-line metric needs target normals: build the IcpTarget2D with "
                 "normal_neighbors > 0");
  ROVE_CHECK_MSG(source.size() < std::numeric_limits<std::uint32_t>::max(),
                 "at most 2^32-1 source points, got {}", source.size());
  // MRPT's ICP iterates on (x, y, phi); its arithmetic mode needs exactly that.
  const Pose2 initial = to_pose2(initial_T_target_source);
  Icp2dResult res;
  res.T_target_source = initial_T_target_source;
  res.conditioning = std::numeric_limits<double>::quiet_NaN();
  const std::size_t finite =
      std::count_if(source.begin(), source.end(), [](const auto& p) { return p.allFinite(); });
  if (target.empty() || finite == 0) {
    res.termination = RegistrationTermination::InvalidInput;
    res.message = target.empty() ? "the target has no point" : "the source has no finite point";
    return res;
  }
  const std::size_t min_pairs = o.metric == Icp2dMetric::PointToLine ? 3 : 2;
  const IcpLoop run = iterate(target, source, initial, o, min_pairs);
  const auto& pairs = run.m.pairs;

  res.iterations = run.iterations;
  res.final_threshold_dist = run.thr;
  res.correspondences = pairs.size();
  // MRPT's correspondencesRatio: decimation × (points with a pair) / (all
  // points), so with decimation the share of the points considered is
  // measured against N / decimation, not their integer count.
  const std::size_t decimation = o.corresponding_points_decimation;
  res.goodness = o.arithmetic == Arithmetic::Mrpt
                     ? detail::mrpt_goodness(decimation, run.m.sources_with_pair, finite)
                     : std::min(1.0, static_cast<double>(decimation * run.m.sources_with_pair) /
                                         static_cast<double>(finite));
  double sse = 0;
  for (const auto& p : pairs) sse += p.sq_dist;
  res.fitness = pairs.empty() ? 0.0 : sse / static_cast<double>(pairs.size());
  res.T_target_source = to_se2(run.pose);
  if (run.diverged) {
    res.termination = RegistrationTermination::Diverged;
    res.message = fmt::format("the pose update became non-finite or unbounded at iteration {}",
                              run.iterations);
    return res;
  }
  if (run.too_few) {
    res.termination = RegistrationTermination::TooFewCorrespondences;
    res.message = fmt::format("{} pair(s) at iteration {} (gate {:.3g} m); {} needed",
                              pairs.size(), run.iterations, run.thr, min_pairs);
    return res;
  }

  // Covariance: σ²·H⁻¹ of the final pairs (header comment).
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  if (!o.skip_cov_calculation) {
    const bool weighted = o.covariance_method == IcpCovarianceMethod::FiniteDifferences;
    const Normal3 ne = kernel_of(o).visit([&](const auto& k) {
      return accumulate(target, source, pairs, run.pose, o.metric, k, weighted, o.num_threads);
    });
    cov = covariance_from_information<3>(ne.H, o.covariance_var_points, 1e-12);
  }
  res.covariance = xyphi_to_right_tangent_covariance(run.pose, cov);

  bool degenerate = false;
  if (o.degeneracy_threshold > 0) {
    res.conditioning = pair_conditioning(target, source, pairs, run.pose, o.normal_neighbors);
    degenerate = res.conditioning < o.degeneracy_threshold;
  }
  if (o.do_ransac) {
    std::vector<Eigen::Vector2d> tp(pairs.size()), sp(pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      tp[k] = target.points()[pairs[k].target];
      sp[k] = source[pairs[k].source];
    }
    res.sog = ransac_rigid_2d(tp, sp, o.ransac).sog;
  }
  set_termination(o, run, degenerate, res);
  return res;
}

}  // namespace rove
