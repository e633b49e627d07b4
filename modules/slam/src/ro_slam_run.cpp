#include "rove/slam/ro_slam_run.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/obs/beacon_ranges.h"
#include "kf_slam_truth.h"
#include "rbpf_runner.h"

namespace rove {
namespace {

void conclude(RoSlamResult& res, const RbpfSlamConfig& config) {
  res.issues = detail::filter_issues(res.steps, res.options.particles, config);
  std::vector<std::int32_t> unresolved;
  for (const Beacon& b : res.map.beacons()) {
    if (b.kind != BeaconPdfKind::Gaussian) unresolved.push_back(b.id);
  }
  if (!unresolved.empty()) {
    res.issues.push_back(
        {"unresolved-beacons",
         fmt::format("{} of {} beacons of the most likely map are still rings or arcs (samples or "
                     "sums of Gaussians), not points: ids {}",
                     unresolved.size(), res.map.beacons().size(), fmt::join(unresolved, ", "))});
  }
  res.termination =
      res.issues.empty() ? RbpfSlamTermination::Completed : RbpfSlamTermination::CompletedWithIssues;
  res.message = fmt::format("{} steps, {} updates, {} insertions, {} particles; {} beacons; most "
                            "likely particle {} (weight {:.3g})",
                            res.steps.size(), res.updates, res.insertions, res.particles.size(),
                            res.map.beacons().size(), res.best, std::exp(res.best_log_weight));
}

}  // namespace

RoSlamResult run_ro_slam(const RbpfSlamConfig& config, const std::string& rawlog_path,
                         const RbpfSlamRunOptions& options) {
  ROVE_CHECK_MSG(config.map == RbpfMapKind::Beacons,
                 "run_ro_slam needs a configuration with a beacon map ({} has an occupancy grid)",
                 config.source);
  RoSlamResult res;
  res.options = detail::with_run_options(config.beacons, options);
  RoSlam slam(res.options);
  detail::RbpfRunCounts counts;
  const detail::LogRead read = detail::run_filter_over_log<BeaconRanges, RoSlamStep, &RoSlamStep::ranges>(
      slam, config, options, rawlog_path, res.steps, counts, "beacon ranges");
  res.observations = counts.observations;
  const RoSlamParticle& best = slam.particles()[slam.best()];
  detail::fill_totals(res, read, counts, slam, res.steps, path_of(best.path));
  res.map = *best.map;
  conclude(res, config);
  return res;
}

BeaconErrors beacon_errors(const BeaconMap& map,
                           const std::vector<std::pair<std::int32_t, Eigen::Vector3d>>& truth) {
  BeaconErrors out;
  std::map<std::int32_t, Eigen::Vector3d> true_of(truth.begin(), truth.end());
  double sum = 0.0;
  std::map<std::int32_t, const Beacon*> mapped;
  for (const Beacon& b : map.beacons()) mapped.emplace(b.id, &b);
  for (const auto& [id, b] : mapped) {
    const auto it = true_of.find(id);
    if (it == true_of.end()) {
      out.unknown.push_back(id);
      continue;
    }
    BeaconError e;
    e.id = id;
    e.estimate = b->moments().mean;
    e.truth = it->second;
    e.error = (e.estimate - e.truth).norm();
    sum += e.error * e.error;
    out.matched.push_back(e);
  }
  for (const auto& [id, p] : true_of) {
    if (!mapped.contains(id)) out.missing.push_back(id);
  }
  if (!out.matched.empty()) out.rmse = std::sqrt(sum / static_cast<double>(out.matched.size()));
  return out;
}

std::vector<std::pair<std::int32_t, Eigen::Vector3d>> load_beacon_truth(const std::string& path) {
  std::vector<std::pair<std::int32_t, Eigen::Vector3d>> out;
  std::map<std::int32_t, std::size_t> seen;
  for (const auto& [line, v] : detail::read_rows(path, "beacon ground truth")) {
    const auto fail = [&, line = line](const std::string& what) {
      throw ParseError({path, line, std::nullopt, "beacon ground truth"}, what);
    };
    if (v.size() < 4) fail(fmt::format("{} values; a beacon row is ID X Y Z [covariance]", v.size()));
    if (v[0] != std::floor(v[0]) || std::abs(v[0]) > 2147483647.0) {
      fail(fmt::format("the ID {} is not an integer", v[0]));
    }
    const auto id = static_cast<std::int32_t>(v[0]);
    if (const auto [it, fresh] = seen.emplace(id, line); !fresh) {
      fail(fmt::format("beacon {} is listed twice (first on line {})", id, it->second));
    }
    out.emplace_back(id, Eigen::Vector3d(v[1], v[2], v[3]));
  }
  return out;
}

}  // namespace rove
