#include "rove/registration/icp_3d.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/math/se3.h"
#include "rove/registration/degeneracy.h"
#include "rove/registration/parallel.h"
#include "rove/registration/pose_covariance.h"

namespace rove {

void Icp3dOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(max_correspondence_distance) && max_correspondence_distance > 0,
                 "max_correspondence_distance must be finite and > 0, got {}",
                 max_correspondence_distance);
  ROVE_CHECK_GE(max_iterations, 1);
  ROVE_CHECK_MSG(std::isfinite(rotation_epsilon) && rotation_epsilon >= 0,
                 "rotation_epsilon must be finite and >= 0, got {}", rotation_epsilon);
  ROVE_CHECK_MSG(std::isfinite(translation_epsilon) && translation_epsilon >= 0,
                 "translation_epsilon must be finite and >= 0, got {}", translation_epsilon);
  ROVE_CHECK_MSG(std::isfinite(lm_initial_lambda) && lm_initial_lambda >= 0,
                 "lm_initial_lambda must be finite and >= 0, got {}", lm_initial_lambda);
  ROVE_CHECK_MSG(std::isfinite(point_variance) && point_variance > 0,
                 "point_variance must be finite and > 0, got {}", point_variance);
  ROVE_CHECK_GE(min_correspondences, std::size_t{6});
  ROVE_CHECK_MSG(degeneracy_threshold >= 0 && degeneracy_threshold < 1,
                 "degeneracy_threshold must be in [0, 1), got {}", degeneracy_threshold);
  ROVE_CHECK_GE(normal_neighbors, std::size_t{3});
  ROVE_CHECK_GE(num_threads, 1);
}

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

struct Pair3 {
  std::uint32_t source;
  std::uint32_t target;
};

struct Linear6 {
  Mat6 H = Mat6::Zero();
  Vec6 b = Vec6::Zero();
  double cost = 0;     // Σ ρ(s)
  double sq_dist = 0;  // Σ ‖q‖²
  Linear6& operator+=(const Linear6& o) {
    H += o.H;
    b += o.b;
    cost += o.cost;
    sq_dist += o.sq_dist;
    return *this;
  }
};

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// Adds w·JᵀR W RᵀJ to the upper triangle of a.H and w·JᵀR·v to a.b, for
/// J = [R, −R[s]×] (see linearize): H += w[W, −WS; SW, −SWS], S = [s]×.
inline void add_quadratic(Linear6& a, const Eigen::Matrix3d& W, const Eigen::Vector3d& s, double w,
                          const Eigen::Vector3d& v) {
  const Eigen::Matrix3d S = skew(s);
  const Eigen::Matrix3d WS = W * S;
  a.H.topLeftCorner<3, 3>().noalias() += w * W;
  a.H.topRightCorner<3, 3>().noalias() -= w * WS;
  a.H.bottomRightCorner<3, 3>().noalias() -= w * (S * WS);
  a.b.head<3>().noalias() += w * v;
  a.b.tail<3>().noalias() += w * s.cross(v);
}

/// Linearizes (or, with `cost_only`, evaluates) the cost of the pairs at T.
template <typename Kernel>
Linear6 linearize(const PreparedCloud3D& target, const PreparedCloud3D& source,
                  const std::vector<Pair3>& pairs, const Eigen::Isometry3d& T,
                  Icp3dMethod method, const Kernel& kernel, bool cost_only,
                  detail::ThreadTeam& team) {
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation();
  Linear6 sum = detail::parallel_reduce(pairs.size(), team, Linear6{},
                                 [&](std::size_t b, std::size_t e, Linear6& a) {
    // With J = ∂q/∂(ρ, ω) = [R, −R[s]×] and Rᵀ applied to the target side,
    // every product is taken in the source frame: for a symmetric W,
    // JᵀRWRᵀJ = [W, −W[s]×; [s]×W, −[s]×W[s]×], and JᵀR·v = (v, s × v).
    for (std::size_t k = b; k < e; ++k) {
      const Pair3& pr = pairs[k];
      const Eigen::Vector3d s = source.points()[pr.source].cast<double>();
      const Eigen::Vector3d q = R * s + t - target.points()[pr.target].cast<double>();
      a.sq_dist += q.squaredNorm();
      switch (method) {
        case Icp3dMethod::PointToPoint: {
          const auto kv = kernel.evaluate(q.squaredNorm());
          a.cost += kv.rho;
          if (!cost_only) add_quadratic(a, Eigen::Matrix3d::Identity(), s, kv.d1, R.transpose() * q);
          break;
        }
        case Icp3dMethod::PointToPlane: {
          const Eigen::Vector3d n = target.normals()[pr.target].cast<double>();
          const double r = n.dot(q);
          const auto kv = kernel.evaluate(r * r);
          a.cost += kv.rho;
          if (!cost_only) {
            const Eigen::Vector3d m = R.transpose() * n;
            Vec6 j;
            j << m, s.cross(m);
            a.H.noalias() += (kv.d1 * j) * j.transpose();
            a.b += (kv.d1 * r) * j;
          }
          break;
        }
        case Icp3dMethod::Gicp: {
          // (C_t + R C_s Rᵀ)⁻¹ = R (Rᵀ C_t R + C_s)⁻¹ Rᵀ: invert in the
          // source frame.
          Eigen::Matrix3d C = source.covariances()[pr.source];
          C.noalias() += R.transpose() * target.covariances()[pr.target] * R;
          const Eigen::Matrix3d W = C.inverse();
          const Eigen::Vector3d qs = R.transpose() * q;
          const Eigen::Vector3d Wq = W * qs;
          const auto kv = kernel.evaluate(std::max(0.0, qs.dot(Wq)));
          a.cost += kv.rho;
          if (!cost_only) add_quadratic(a, W, s, kv.d1, Wq);
          break;
        }
      }
    }
  });
  // add_quadratic fills the upper triangle only.
  if (method != Icp3dMethod::PointToPlane) sum.H.triangularView<Eigen::StrictlyLower>() = sum.H.transpose();
  return sum;
}

/// The unit normal of a plane-to-plane covariance C = I − (1 − ε)·n·nᵀ
/// (prepared_cloud.h): n·nᵀ = (I − C)/(1 − ε), read off its largest column
/// without an eigen-decomposition. Zero for C = I (a point without extent).
Eigen::Vector3d normal_of_gicp_covariance(const Eigen::Matrix3d& C, double epsilon) {
  if (!(epsilon < 1)) return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvectors().col(0);
  const Eigen::Matrix3d nn = (Eigen::Matrix3d::Identity() - C) / (1 - epsilon);
  Eigen::Index j = 0;
  const double top = nn.diagonal().maxCoeff(&j);
  if (!(top > 0)) return Eigen::Vector3d::Zero();
  return nn.col(j) / std::sqrt(top);
}

/// Squared distance as KdTree computes it (float, (0 + dx²) + dy² + dz²), so
/// that comparisons agree with its searches.
inline float tree_sq_distance(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  const float dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

/// The unique nearest target point to q, found without a tree search by
/// walking from `start` over the target's neighbourhoods; −1 when that
/// cannot be certified (then search the tree). Point p is q's unique
/// nearest when q is strictly nearer to p than to each of p's k nearest
/// and |q − p| < r/2, r the distance from p to the farthest of them: every
/// other point p' lies at |p' − p| >= r, so |q − p'| >= r − |q − p| > |q − p|.
/// The half is taken with a margin (1e-4 relative) far above the rounding
/// of the float distances, so the computed distances order as the true ones
/// and the tree would return the same point. A neighbour strictly nearer
/// than p moves the walk there.
struct Walk {
  std::uint32_t point;  // where the walk ended: q's nearest when certified
  bool certified;
};
Walk certified_nearest(const PreparedCloud3D& target, const Eigen::Vector3f& q, std::uint32_t start) {
  const std::size_t k = target.neighbors_per_point();
  const std::uint32_t* rows = target.neighbor_indices().data();
  const float* reach_sq = target.neighbor_reach_sq().data();
  const Eigen::Vector3f* pts = target.points().data();
  std::uint32_t p = start;
  float dp = tree_sq_distance(q, pts[p]);
  for (int step = 0; step < 4; ++step) {
    const std::uint32_t* row = rows + static_cast<std::size_t>(p) * k;
    std::uint32_t best = p;
    float best_d = dp;
    bool tie = false;
    for (std::size_t j = 0; j < k; ++j) {
      const std::uint32_t o = row[j];
      if (o == p) continue;
      const float d = tree_sq_distance(q, pts[o]);
      tie = tie || d == best_d;
      if (d < best_d) {
        best = o;
        best_d = d;
        tie = false;
      }
    }
    if (best == p) return {p, !tie && 4.0f * dp < reach_sq[p] * (1.0f - 1e-4f)};
    p = best;
    dp = best_d;
  }
  return {p, false};
}

/// Pairs every source point (moved by T) with its nearest target point within
/// max_dist. `slot` holds the previous pairing (−1: none; empty on the
/// first call): the previous partner's distance bounds the search, which
/// prunes most of the tree and finds the same nearest point.
void find_pairs(const PreparedCloud3D& target, const PreparedCloud3D& source,
                const Eigen::Isometry3d& T, double max_dist, detail::ThreadTeam& team,
                std::vector<std::int64_t>& slot, std::vector<Pair3>& pairs) {
  if (slot.size() != source.size()) slot.assign(source.size(), -1);
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  const float gate = static_cast<float>(max_dist);
  // Admitted as the tree admits: strictly below one ulp above gate².
  const float gate_sq = std::nextafter(gate * gate, std::numeric_limits<float>::infinity());
  const bool certify = target.has_neighborhoods();
  // Source points in their tree's order: consecutive queries are close in
  // space, so their searches walk the same part of the target tree.
  const std::span<const std::uint32_t> order = source.tree().tree_order();
  struct Nothing {
    Nothing& operator+=(const Nothing&) { return *this; }
  };
  detail::parallel_reduce(source.size(), team, Nothing{}, [&](std::size_t b, std::size_t e, Nothing&) {
    // The partner of the previous query of the block: where a query without
    // a partner of its own (the first iteration) starts its walk.
    std::int64_t previous = -1;
    for (std::size_t k = b; k < e; ++k) {
      const std::size_t i = order[k];
      const Eigen::Vector3f q = R * source.points()[i] + t;
      std::int64_t hint = slot[i] >= 0 ? slot[i] : previous;
      if (certify && hint >= 0) {
        const Walk w = certified_nearest(target, q, static_cast<std::uint32_t>(hint));
        if (w.certified) {
          previous = w.point;
          slot[i] = tree_sq_distance(q, target.points()[w.point]) < gate_sq
                        ? static_cast<std::int64_t>(w.point)
                        : std::int64_t{-1};
          continue;
        }
        hint = w.point;
      }
      // The hint (none: −1, out of range) bounds the search: the same
      // nearest point, a smaller ball.
      const auto nn = target.tree().nearest(q, gate, static_cast<std::uint32_t>(hint));
      slot[i] = nn ? static_cast<std::int64_t>(nn->index) : -1;
      if (nn) previous = slot[i];
    }
  });
  pairs.clear();
  for (std::size_t i = 0; i < slot.size(); ++i)
    if (slot[i] >= 0)
      pairs.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(slot[i])});
}

}  // namespace

Icp3dResult icp_3d(const PreparedCloud3D& target, const PreparedCloud3D& source,
                   const Eigen::Isometry3d& initial, const Icp3dOptions& o) {
  o.check();
  ROVE_CHECK_FINITE(initial.matrix());
  ROVE_CHECK_MSG((initial.linear().transpose() * initial.linear() - Eigen::Matrix3d::Identity())
                         .cwiseAbs()
                         .maxCoeff() < 1e-6,
                 "the initial transform is not rigid");
  ROVE_CHECK_MSG(o.method != Icp3dMethod::PointToPlane || target.has_normals() || target.empty(),
                 "point-to-plane ICP needs target normals (PrepareOptions::normals)");
  ROVE_CHECK_MSG(o.method != Icp3dMethod::Gicp ||
                     ((target.has_covariances() || target.empty()) &&
                      (source.has_covariances() || source.empty())),
                 "GICP needs covariances on both clouds (PrepareOptions::covariances)");
  Icp3dResult res;
  res.conditioning = std::numeric_limits<double>::quiet_NaN();
  Eigen::Isometry3d T = initial;
  auto finish_pose = [&](const Mat6* H, double scale) {
    res.matrix = T.matrix();
    const Pose3 mean(T.linear(), T.translation(), 1e-6);
    if (!H) {
      res.T_target_source = Pose3Gaussian(mean);
      return;
    }
    res.information = *H;
    const Mat6 C_right = covariance_from_information<6>(*H, scale, 1e-12);
    Mat6 right_to_left = Mat6::Zero();  // T·exp(δ) ≈ (exp([Rω]ₓ)R, t + Rρ)
    right_to_left.topLeftCorner<3, 3>() = T.linear();
    right_to_left.bottomRightCorner<3, 3>() = T.linear();
    const Mat6 J = ypr_jacobian_wrt_left_tangent(mean) * right_to_left;
    Mat6 C = J * C_right * J.transpose();
    C = 0.5 * (C + C.transpose());
    res.T_target_source = Pose3Gaussian(detail::kUnchecked, mean, C);
  };
  if (target.empty() || source.empty()) {
    finish_pose(nullptr, 1);
    res.termination = RegistrationTermination::InvalidInput;
    res.message = target.empty() ? "the target cloud has no finite point"
                                 : "the source cloud has no finite point";
    return res;
  }

  std::vector<std::int64_t> slot;
  std::vector<Pair3> pairs;
  bool converged = false, diverged = false, too_few = false;
  Linear6 lin;
  detail::ThreadTeam team(o.num_threads);
  o.kernel.visit([&](const auto& kernel) {
    double lambda = o.lm_initial_lambda;
    for (int it = 0; it < o.max_iterations; ++it) {
      find_pairs(target, source, T, o.max_correspondence_distance, team, slot, pairs);
      res.iterations = it + 1;
      if (pairs.size() < o.min_correspondences) {
        too_few = true;
        return;
      }
      lin = linearize(target, source, pairs, T, o.method, kernel, false, team);
      // Levenberg–Marquardt on the fixed pairs: raise the damping until the
      // cost decreases (at most 10 tries; a zero step means converged).
      Vec6 delta = Vec6::Zero();
      Eigen::Isometry3d T_new = T;
      bool accepted = false;
      for (int tries = 0; tries < 10; ++tries) {
        const Mat6 A = lin.H + lambda * Mat6::Identity();
        delta = A.ldlt().solve(-lin.b);
        if (!delta.allFinite()) break;
        T_new = T * Eigen::Isometry3d(SE3d::exp(delta).matrix());
        const Linear6 trial = linearize(target, source, pairs, T_new, o.method, kernel, true, team);
        if (trial.cost <= lin.cost) {
          lambda = std::max(lambda / 10.0, o.lm_initial_lambda);
          accepted = true;
          break;
        }
        lambda = std::max(lambda * 10.0, 1e-9);
      }
      if (!delta.allFinite() || !T_new.matrix().allFinite()) {
        diverged = true;
        return;
      }
      if (!accepted) {
        // No decrease even with heavy damping: a minimum of the current pairing.
        converged = true;
        return;
      }
      T = T_new;
      if (delta.tail<3>().norm() < o.rotation_epsilon &&
          delta.head<3>().norm() < o.translation_epsilon) {
        converged = true;
        return;
      }
    }
  });

  // Final statistics at T with the last pairing.
  res.correspondences = pairs.size();
  res.goodness = static_cast<double>(pairs.size()) / static_cast<double>(source.size());
  if (diverged) {
    finish_pose(nullptr, 1);
    res.termination = RegistrationTermination::Diverged;
    res.message = fmt::format("the step became non-finite at iteration {}", res.iterations);
    return res;
  }
  if (too_few) {
    finish_pose(nullptr, 1);
    res.termination = RegistrationTermination::TooFewCorrespondences;
    res.message = fmt::format("{} pair(s) within {} m at iteration {}; {} needed", pairs.size(),
                              o.max_correspondence_distance, res.iterations,
                              o.min_correspondences);
    return res;
  }
  const Linear6 fin = o.kernel.visit([&](const auto& kernel) {
    return linearize(target, source, pairs, T, o.method, kernel, false, team);
  });
  res.fitness = fin.sq_dist / static_cast<double>(pairs.size());
  res.final_cost = 0.5 * fin.cost;
  finish_pose(&fin.H, o.method == Icp3dMethod::Gicp ? 1.0 : o.point_variance);

  bool degenerate = false;
  if (o.degeneracy_threshold > 0) {
    std::vector<Eigen::Vector3d> q(pairs.size()), n(pairs.size());
    // A target without normals or covariances: fit a normal once per matched
    // target point (several source points often share one), on the team.
    std::vector<Eigen::Vector3f> fitted;
    if (!target.has_normals() && !target.has_covariances()) {
      std::vector<std::uint32_t> matched;
      matched.reserve(pairs.size());
      std::vector<bool> seen(target.size(), false);
      for (const Pair3& pr : pairs)
        if (!seen[pr.target]) {
          seen[pr.target] = true;
          matched.push_back(pr.target);
        }
      fitted.assign(target.size(), Eigen::Vector3f::Zero());
      detail::parallel_for(matched.size(), team, [&](std::size_t j) {
        const std::uint32_t ti = matched[j];
        local_surface_3d(target.tree(), target.points()[ti], o.normal_neighbors, 1e-3, &fitted[ti],
                         nullptr);
      });
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      q[k] = T * source.points()[pairs[k].source].cast<double>();
      const std::uint32_t ti = pairs[k].target;
      if (target.has_normals()) {
        n[k] = target.normals()[ti].cast<double>();
      } else if (target.has_covariances()) {
        n[k] = normal_of_gicp_covariance(target.covariances()[ti], target.options().gicp_epsilon);
      } else {
        n[k] = fitted[ti].cast<double>();
      }
    }
    res.conditioning = point_to_plane_conditioning(q, n);
    degenerate = res.conditioning < o.degeneracy_threshold;
  }

  if (degenerate) {
    res.termination = RegistrationTermination::Degenerate;
    res.message = fmt::format(
        "the matched geometry leaves a direction unconstrained (conditioning {:.3g} < {:.3g}, "
        "e.g. a single plane)",
        res.conditioning, o.degeneracy_threshold);
  } else if (converged) {
    res.termination = RegistrationTermination::Converged;
    res.message = fmt::format("converged in {} iterations, {} pairs, fitness {:.4g} m²",
                              res.iterations, res.correspondences, res.fitness);
  } else {
    res.termination = RegistrationTermination::MaxIterations;
    res.message = fmt::format("{} iterations without meeting the step tolerances", res.iterations);
  }
  return res;
}

}  // namespace rove
