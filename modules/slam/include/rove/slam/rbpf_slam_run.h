#pragma once
/// \file
/// Running RBPF grid mapping (rove/slam/rbpf_slam.h) over a whole log (and
/// the options and issues range-only SLAM's run, ro_slam_run.h, shares), as
/// MRPT's rbpf-slam application does (CMetricMapBuilderRBPF): the steps of
/// the log (an action collection and the sensory frame after it, or one
/// observation; rawlog_steps) move the odometry; the first 2D scan is
/// inserted at the origin; afterwards, once the robot has moved
/// localizeLinDistance or localizeAngDistance by odometry since the last
/// update, the filter runs with the accumulated odometry (its Gaussian: the
/// actions' Gaussian models composed) and the step's first 2D scan, and once
/// it has moved insertionLinDistance or insertionAngDistance since the last
/// insertion the scan is inserted too (a step that inserts always updates
/// first). Observations other than 2D scans are not used.
///
/// What a finished run must say (issues, exit status 3 on the command
/// line): "ess-collapse" when in more than half of the updates the weights
/// sat on fewer than 1.5 effective particles (the filter kept a single
/// hypothesis); "poor-scan-fit" when, on average over the updates, fewer
/// than half of the scan's points lay within LF_maxCorrsDistance of a wall
/// of the most likely particle's map (the map disagrees with the scans);
/// "map-contradicts-scans" when in more than a tenth of the updates (and at
/// least 3) more than a fifth of the scan's rays crossed a wall of the most
/// likely particle's map (RbpfUpdateResult::through_walls: passes that
/// disagree, a loop closed wrong); "no-updates" when the robot never moved
/// enough to run the filter. The checks see what the scans contradict, not
/// every inconsistent map: a loop closed wrong where the passes do not
/// overlap passes them (compare with another map: --reference).

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/any_rawlog.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"
#include "rove/slam/rbpf_slam.h"
#include "rove/slam/rbpf_slam_config.h"
#include "rove/slam/scan_consistency.h"

namespace rove {

/// One step of a run.
struct RbpfSlamStep {
  /// 0-based step index in the log (counting steps skipped by rawlog_offset).
  std::uint64_t index = 0;
  /// Time of the step's first observation (invalid if none has one).
  Timestamp time;
  /// The accumulated odometry after the step, T_odom_robot.
  Pose2 odometry;
  /// True if the step held a 2D scan.
  bool scan = false;
  /// True if the filter ran.
  bool updated = false;
  /// True if the scan was inserted into the maps.
  bool inserted = false;
  /// The filter's report when updated.
  RbpfUpdateResult update;
  /// Wall time of the step's processing, seconds (reading excluded).
  double seconds = 0.0;
};

/// Something the user must know about a finished run.
struct RbpfSlamIssue {
  /// "ess-collapse", "poor-scan-fit" or "no-updates" (see the file comment).
  std::string code;
  /// One line for a person.
  std::string message;
};

/// Options of run_rbpf_slam (what the command line sets).
struct RbpfSlamRunOptions {
  /// Seed of the run's random numbers.
  std::uint64_t seed = 0;
  /// Threads (1–256, 0 all); the result does not depend on it.
  int num_threads = 1;
  /// Replace the configuration's sampleSize.
  std::optional<std::uint32_t> particles;
  /// Stop after this many processed steps (all if unset).
  std::optional<std::uint64_t> max_steps;
  /// Options of the log reader.
  AnyRawlogOptions reader;
  /// Called after every processed step with its index, if set.
  std::function<void(std::uint64_t)> on_step;
};

/// How a run ended.
enum class RbpfSlamTermination : std::uint8_t {
  /// Ran to the end of the log (or max_steps) with no issue.
  Completed,
  /// Ran to the end, with issues (see RbpfSlamResult::issues).
  CompletedWithIssues,
};

/// "completed" or "completed-with-issues".
std::string_view to_string(RbpfSlamTermination termination) noexcept;

/// What every RBPF run reports (grid mapping here, range-only SLAM in
/// ro_slam_run.h) besides its steps, its map and its options.
struct RbpfRunTotals {
  /// How the run ended.
  RbpfSlamTermination termination = RbpfSlamTermination::Completed;
  /// One line: steps, updates, insertions, the most likely particle.
  std::string message;
  /// The most likely particle's pose T_map_robot at every step: its pose
  /// at its last update up to the step, moved on by the odometry since.
  std::vector<Pose2> path;
  /// Every particle's final pose T_map_robot.
  std::vector<SE2d> particles;
  /// Index of the most likely particle and its normalized log-weight.
  std::size_t best = 0;
  double best_log_weight = 0.0;
  /// Filter updates and insertions run.
  std::uint64_t updates = 0, insertions = 0;
  /// Sum of the steps' processing times, seconds.
  double mapping_seconds = 0.0;
  /// Time spent reading the log, seconds.
  double read_seconds = 0.0;
  /// The log's format and entries read.
  RawlogFormat format = RawlogFormat::Mrpt;
  std::uint64_t entries = 0;
  /// What the user must know (empty when fine).
  std::vector<RbpfSlamIssue> issues;
  /// True when the run completed without issues.
  bool ok() const noexcept { return termination == RbpfSlamTermination::Completed; }
};

/// The result of run_rbpf_slam.
struct RbpfSlamResult : RbpfRunTotals {
  /// Every processed step.
  std::vector<RbpfSlamStep> steps;
  /// The most likely particle's map.
  OccupancyGrid map;
  /// 2D scans in the processed steps.
  std::uint64_t scans = 0;
  /// Most distinct tiles all particles held at once, and their bytes.
  std::size_t peak_tiles = 0;
  std::size_t peak_tile_bytes = 0;
  /// Tiles the particles would hold without sharing (particles × tiles of
  /// the largest map), at the end.
  std::size_t unshared_tiles = 0;
  /// The options the filter ran with (seed, threads, overrides applied).
  RbpfSlamOptions options;
  /// Updates in which more than kContradictedRays of the scan's rays
  /// crossed a wall of the most likely map (RbpfUpdateResult::through_walls).
  std::size_t contradicted_updates = 0;
};

/// Updates of `steps` that ran the filter, those with through_walls above
/// kContradictedRays, and the mean fit: what the scan checks of a run
/// (the file comment) are decided from.
struct RbpfScanChecks {
  std::size_t updates = 0;
  std::size_t contradicted = 0;
  double mean_fit = 1.0;
};
RbpfScanChecks scan_checks(const std::vector<RbpfSlamStep>& steps);

/// Maps the log at `rawlog_path` with the configuration (see the file
/// comment), polling rove::throw_if_interrupted() once per entry. Throws
/// IoError / ParseError on an unreadable log (ParseError names the step's
/// offset when the filter rejects an observation, e.g. a NaN range);
/// SelectionError when rawlog_offset skips every step or the processed
/// steps hold no 2D scan.
RbpfSlamResult run_rbpf_slam(const RbpfSlamConfig& config, const std::string& rawlog_path,
                             const RbpfSlamRunOptions& options = {});

}  // namespace rove
