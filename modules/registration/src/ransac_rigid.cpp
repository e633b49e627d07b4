#include "rove/registration/ransac_rigid.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/poses/angle.h"
#include "rove/poses/lie_conversion.h"
#include "rove/registration/rigid_transform.h"

namespace rove {

void RansacRigid2dOptions::check() const {
  ROVE_CHECK_GE(min_set_size, 2u);
  ROVE_CHECK_GE(max_set_size, min_set_size);
  ROVE_CHECK_GE(n_simulations, 1u);
  ROVE_CHECK_MSG(std::isfinite(mahalanobis_threshold) && mahalanobis_threshold > 0,
                 "mahalanobis_threshold must be finite and > 0, got {}", mahalanobis_threshold);
  ROVE_CHECK_MSG(std::isfinite(normalization_std) && normalization_std > 0,
                 "normalization_std must be finite and > 0, got {}", normalization_std);
  ROVE_CHECK_MSG(std::isfinite(fuse_max_diff_xy) && fuse_max_diff_xy >= 0,
                 "fuse_max_diff_xy must be finite and >= 0, got {}", fuse_max_diff_xy);
  ROVE_CHECK_MSG(std::isfinite(fuse_max_diff_phi) && fuse_max_diff_phi >= 0,
                 "fuse_max_diff_phi must be finite and >= 0, got {}", fuse_max_diff_phi);
}

RansacRigid2dResult ransac_rigid_2d(std::span<const Eigen::Vector2d> target,
                                    std::span<const Eigen::Vector2d> source,
                                    const RansacRigid2dOptions& options) {
  ROVE_CHECK_EQ(target.size(), source.size());
  options.check();
  RansacRigid2dResult result;
  const std::size_t n = source.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!target[i].allFinite() || !source[i].allFinite()) {
      result.message = fmt::format("pair {} has a non-finite coordinate", i);
      return result;
    }
  }
  if (n < options.min_set_size) {
    result.termination = RegistrationTermination::TooFewCorrespondences;
    result.message = fmt::format("{} pairs, {} needed", n, options.min_set_size);
    return result;
  }
  const double sigma2 = options.normalization_std * options.normalization_std;
  RigidFitOptions fit_options;
  fit_options.point_variance = sigma2;

  std::mt19937_64 rng(options.seed);
  std::vector<std::uint32_t> order(n);
  std::vector<Eigen::Vector2d> set_t, set_s;
  struct Mode {
    Pose2Gaussian g;
    std::vector<std::uint32_t> pairs;
    double count = 0;
  };
  std::vector<Mode> modes;

  for (unsigned sim = 0; sim < options.n_simulations; ++sim) {
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), rng);
    // Seed: the first two pairs of the shuffled order with distinct source points.
    std::vector<std::uint32_t> set{order[0]};
    std::size_t next = 1;
    for (; next < n; ++next) {
      if ((source[order[next]] - source[order[0]]).squaredNorm() > 0) {
        set.push_back(order[next]);
        break;
      }
    }
    if (set.size() < 2) continue;
    auto refit = [&]() {
      set_t.clear();
      set_s.clear();
      for (auto k : set) {
        set_t.push_back(target[k]);
        set_s.push_back(source[k]);
      }
      return fit_rigid_2d(set_t, set_s, {}, fit_options);
    };
    RigidFit2Result fit = refit();
    // The pair set must be self-consistent: two pairs whose distances differ
    // cannot come from one rigid motion.
    if (fit.rmse > options.mahalanobis_threshold * options.normalization_std * 2) continue;
    for (std::size_t m = 1; m < n && set.size() < options.max_set_size; ++m) {
      if (m == next) continue;
      const std::uint32_t k = order[m];
      const Pose2 T = to_pose2(fit.T_target_source);
      const double c = std::cos(T.phi()), s = std::sin(T.phi());
      const Eigen::Vector2d rs(c * source[k].x() - s * source[k].y(),
                               s * source[k].x() + c * source[k].y());
      const Eigen::Vector2d d = target[k] - (rs + T.translation());
      Eigen::Matrix<double, 2, 3> J;
      J << 1, 0, -rs.y(), 0, 1, rs.x();
      const Eigen::Matrix3d C = right_tangent_to_xyphi_covariance(fit.T_target_source, fit.covariance);
      const Eigen::Matrix2d S = J * C * J.transpose() +
                                2 * sigma2 * Eigen::Matrix2d::Identity();
      const double maha2 = d.dot(S.ldlt().solve(d));
      if (!(maha2 < options.mahalanobis_threshold * options.mahalanobis_threshold)) continue;
      set.push_back(k);
      fit = refit();
    }
    if (set.size() < options.min_set_size) continue;
    std::sort(set.begin(), set.end());
    bool fused = false;
    for (auto& mode : modes) {
      bool same = false;
      if (options.fuse_by_corrs_match) {
        same = mode.pairs == set;
      } else {
        const Pose2& a = mode.g.mean();
        const Pose2 b = to_pose2(fit.T_target_source);
        same = std::abs(a.x() - b.x()) <= options.fuse_max_diff_xy &&
               std::abs(a.y() - b.y()) <= options.fuse_max_diff_xy &&
               std::abs(wrap_to_pi(a.phi() - b.phi())) <= options.fuse_max_diff_phi;
      }
      if (same) {
        mode.count += 1;
        fused = true;
        break;
      }
    }
    if (!fused) modes.push_back({to_pose2_gaussian(fit.T_target_source, fit.covariance), set, 1.0});
  }
  if (modes.empty()) {
    result.termination = RegistrationTermination::Degenerate;
    result.message = fmt::format("no trial found {} mutually consistent pairs among {}",
                                 options.min_set_size, n);
    return result;
  }
  for (const auto& m : modes) {
    result.sog.push_back(m.g, std::log(m.count));
    result.mode_pairs.push_back(m.pairs);
  }
  result.sog.normalize_weights();
  result.termination = RegistrationTermination::Converged;
  result.message = fmt::format("{} mode(s) from {} trials over {} pairs", modes.size(),
                               options.n_simulations, n);
  return result;
}

}  // namespace rove
