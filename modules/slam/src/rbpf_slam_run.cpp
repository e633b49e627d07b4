#include "rove/slam/rbpf_slam_run.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/selection_error.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rbpf_runner.h"

namespace rove {
namespace {

void conclude(RbpfSlamResult& res, const RbpfSlam& slam, const RbpfSlamConfig& config) {
  res.issues = detail::filter_issues(res.steps, slam.options().particles, config);
  const RbpfScanChecks c = scan_checks(res.steps);
  res.contradicted_updates = c.contradicted;
  if (c.updates > 0 && c.mean_fit < 0.5) {
    res.issues.push_back(
        {"poor-scan-fit",
         fmt::format("on average {:.0f} % of the scans' points lay within LF_maxCorrsDistance of "
                     "a wall of the most likely map (< 50 %): the map disagrees with the scans",
                     100.0 * c.mean_fit)});
  }
  if (contradicted_run(c.contradicted, c.updates)) {
    res.issues.push_back(
        {"map-contradicts-scans",
         fmt::format("in {} of {} updates more than {:.0f} % of the scan's rays crossed a wall of the "
                     "most likely map (> {:.0f} % of the updates): parts of the map were built by "
                     "passes that disagree, e.g. a loop closed wrong (see ess.csv, through_walls)",
                     c.contradicted, c.updates, 100.0 * kContradictedRays, 100.0 * kContradictedScans)});
  }
  res.termination =
      res.issues.empty() ? RbpfSlamTermination::Completed : RbpfSlamTermination::CompletedWithIssues;
  res.message = fmt::format("{} steps, {} updates, {} insertions, {} particles; most likely particle "
                            "{} (weight {:.3g})",
                            res.steps.size(), res.updates, res.insertions,
                            slam.particles().size(), res.best, std::exp(res.best_log_weight));
}

}  // namespace

RbpfScanChecks scan_checks(const std::vector<RbpfSlamStep>& steps) {
  RbpfScanChecks c;
  double fit_sum = 0.0;
  for (const auto& s : steps) {
    if (!s.updated) continue;
    ++c.updates;
    fit_sum += s.update.fit;
    c.contradicted += s.update.through_walls > kContradictedRays ? 1 : 0;
  }
  if (c.updates > 0) c.mean_fit = fit_sum / static_cast<double>(c.updates);
  return c;
}

std::string_view to_string(RbpfSlamTermination t) noexcept {
  switch (t) {
    case RbpfSlamTermination::Completed: return "completed";
    case RbpfSlamTermination::CompletedWithIssues: return "completed-with-issues";
  }
  return "unknown";
}

RbpfSlamResult run_rbpf_slam(const RbpfSlamConfig& config, const std::string& rawlog_path,
                             const RbpfSlamRunOptions& options) {
  RbpfSlamResult res;
  res.options = detail::with_run_options(config.options, options);
  RbpfSlam slam(res.options);
  detail::RbpfRunCounts counts;
  const detail::LogRead read = detail::run_filter_over_log<RangeScan2D, RbpfSlamStep, &RbpfSlamStep::scan>(
      slam, config, options, rawlog_path, res.steps, counts, "2D laser scan", [&](const RbpfSlamStep& s) {
        if (s.updated) res.peak_tiles = std::max(res.peak_tiles, s.update.distinct_tiles);
      });
  res.scans = counts.observations;
  const RbpfParticle& best = slam.particles()[slam.best()];
  detail::fill_totals(res, read, counts, slam, res.steps, path_of(best));
  res.map = best.map.to_occupancy_grid();
  res.peak_tiles = std::max(res.peak_tiles, slam.distinct_tiles());
  res.peak_tile_bytes = res.peak_tiles * sizeof(GridTile);
  std::size_t largest = 0;
  for (const auto& p : slam.particles()) largest = std::max(largest, p.map.tile_count());
  res.unshared_tiles = largest * slam.particles().size();
  conclude(res, slam, config);
  return res;
}

}  // namespace rove
