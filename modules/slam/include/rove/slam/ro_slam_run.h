#pragma once
/// \file
/// Running range-only RBPF SLAM (rove/slam/ro_slam.h) over a whole log, as
/// MRPT's rbpf-slam application does with a beacon map
/// (RO-SLAM_simulatedData_MC.ini, _SOG.ini): the steps of the log move the
/// odometry; the first step with beacon ranges is inserted at the origin;
/// afterwards the filter runs once the robot has moved localizeLinDistance
/// or localizeAngDistance by odometry since the last update (with the
/// actions' Gaussian models composed) and inserts once it has moved
/// insertionLinDistance or insertionAngDistance since the last insertion
/// (MRPT's RO configs set both insertion distances to 0: every update
/// inserts). Observations other than beacon ranges are not used.
///
/// Issues of a finished run: "ess-collapse" and "no-updates" as grid
/// mapping (rove/slam/rbpf_slam_run.h), and "unresolved-beacons" when the
/// most likely map still holds beacons as samples or sums of Gaussians (seen
/// from too few places to fix them: their position is a ring or arcs).

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/io/any_rawlog.h"
#include "rove/maps/beacon_map.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"
#include "rove/slam/rbpf_slam_config.h"
#include "rove/slam/rbpf_slam_run.h"
#include "rove/slam/ro_slam.h"

namespace rove {

/// One step of a range-only run.
struct RoSlamStep {
  /// 0-based step index in the log (counting steps skipped by rawlog_offset).
  std::uint64_t index = 0;
  /// Time of the step's first observation (invalid if none has one).
  Timestamp time;
  /// The accumulated odometry after the step, T_odom_robot.
  Pose2 odometry;
  /// True if the step held beacon ranges.
  bool ranges = false;
  /// True if the filter ran.
  bool updated = false;
  /// True if the ranges were inserted into the maps.
  bool inserted = false;
  /// The filter's report when updated.
  RoSlamUpdateResult update;
  /// Wall time of the step's processing, seconds (reading excluded).
  double seconds = 0.0;
};

/// The result of run_ro_slam.
struct RoSlamResult : RbpfRunTotals {
  /// Every processed step.
  std::vector<RoSlamStep> steps;
  /// The most likely particle's beacons (map frame, meters).
  BeaconMap map;
  /// Steps holding beacon ranges.
  std::uint64_t observations = 0;
  /// The options the filter ran with (seed, threads, overrides applied).
  RoSlamOptions options;
};

/// Maps the beacons of the log at `rawlog_path` with a configuration whose
/// map is Beacons (see the file comment), polling
/// rove::throw_if_interrupted() once per entry. Throws InvalidArgument if
/// config.map is not Beacons; IoError / ParseError on an unreadable log
/// (ParseError names the step's offset when the filter rejects an
/// observation, e.g. a NaN range); SelectionError when rawlog_offset skips
/// every step or the processed steps hold no beacon ranges.
RoSlamResult run_ro_slam(const RbpfSlamConfig& config, const std::string& rawlog_path,
                         const RbpfSlamRunOptions& options = {});

/// A beacon's position error against the truth.
struct BeaconError {
  std::int32_t id = 0;
  /// Estimated and true positions, map frame, meters.
  Eigen::Vector3d estimate = Eigen::Vector3d::Zero(), truth = Eigen::Vector3d::Zero();
  /// |estimate − truth|, meters.
  double error = 0.0;
};

/// The beacons of `map` (their means) against true positions by id.
struct BeaconErrors {
  /// One per beacon present in both, by increasing id.
  std::vector<BeaconError> matched;
  /// Ids of true beacons the map lacks, and of mapped beacons without truth.
  std::vector<std::int32_t> missing, unknown;
  /// Root mean square of the matched errors, meters (0 with none).
  double rmse = 0.0;
};

/// Compares `map` with true beacon positions (id → position).
BeaconErrors beacon_errors(const BeaconMap& map, const std::vector<std::pair<std::int32_t, Eigen::Vector3d>>& truth);

/// Reads MRPT's beacon ground-truth file (CBeaconMap::saveToTextFile: one
/// beacon a line, "ID X Y Z" followed by covariance terms, which are
/// ignored). Throws IoError if unreadable, ParseError naming the line for a
/// row with fewer than four numbers, a non-integer or repeated ID, or a
/// non-finite coordinate.
std::vector<std::pair<std::int32_t, Eigen::Vector3d>> load_beacon_truth(const std::string& path);

}  // namespace rove
