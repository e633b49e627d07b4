#pragma once
/// \file
/// Running lidar SLAM (lidar_slam.h) over a whole log: MRPT rawlogs
/// (layout #1, action collections and sensory frames, or #2, bare
/// observations), rove rawlogs and CARMEN logs, streamed in constant memory
/// through AnyRawlogReader. Every 2D scan of one sensor is a scan for
/// SLAM; the odometry between two of them (the action collections' best 2D
/// movements, or the change of the odometry observations) is its odometry
/// increment. Then the rebuilt map: an occupancy grid with every node's
/// scan inserted at its optimized pose.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/graph/optimizer.h"
#include "rove/io/any_rawlog.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/math/se2.h"
#include "rove/obs/timestamp.h"
#include "rove/slam/lidar_slam.h"
#include "rove/slam/scan_consistency.h"

namespace rove {

/// Something a finished run must tell its user: the path and map were
/// built, but they are not what lidar SLAM promises.
struct LidarSlamIssue {
  /// "optimization-not-converged": the last graph optimization stopped
  /// without converging; "no-loop-closure": loop closure searched but
  /// accepted nothing (the map is the front-end's alone);
  /// "poor-matching": over max_poor_match_fraction of the scans matched
  /// the submap poorly (score under min_match_score): the front-end may be
  /// lost; "scans-without-points": some scans had no return in range (they
  /// only got a predicted pose); "map-contradicts-scans": the nodes' scans
  /// contradict each other at their final poses (scan_consistency.h,
  /// LidarSlamRunResult::consistency).
  std::string code;
  /// One line for a person, with the counts.
  std::string message;
};

/// Options of run_lidar_slam.
struct LidarSlamRunOptions {
  /// Stop after this many scans (all if unset).
  std::optional<std::uint64_t> max_scans;
  /// The sensor whose scans are used; empty: the first 2D scan's.
  std::string sensor_label;
  /// Options of the log reader.
  AnyRawlogOptions reader;
  /// Called after every scan, if set.
  std::function<void(const LidarSlamScanUpdate&)> on_scan;
  /// A matched scan whose score is below this is a poor match. Default 0.3.
  double min_match_score = 0.3;
  /// More poor matches than this share of the matched scans is an issue.
  /// Default 0.05.
  double max_poor_match_fraction = 0.05;
};

/// Result of run_lidar_slam.
struct LidarSlamRunResult {
  /// The log's format.
  RawlogFormat format = RawlogFormat::Mrpt;
  /// Entries read from the log.
  std::uint64_t entries = 0;
  /// The sensor label used.
  std::string sensor_label;
  /// 2D scans of other sensors, left out.
  std::uint64_t other_scans = 0;
  /// Cumulative odometry T_odom_robot at every scan (identity at the first
  /// scan); empty when the log has no odometry.
  std::vector<SE2d> odometry;
  /// Matched scans scoring below min_match_score.
  std::uint64_t poor_matches = 0;
  /// Time of the first and last scan, seconds (0 when unknown).
  double first_time = 0.0, last_time = 0.0;
  /// Time spent in LidarSlam (add_scan and finish), seconds.
  double mapping_seconds = 0.0;
  /// Time spent reading and decoding the log, seconds.
  double read_seconds = 0.0;
  /// The final optimization (LidarSlam::finish), if one ran.
  std::optional<GraphOptimizerResult> final_optimization;
  /// The nodes' scans replayed against each other at their final poses
  /// (scan_consistency.h; a 5 cm grid, MRPT's insertion defaults).
  ScanConsistency consistency;
  /// What the result does not deliver (empty when fine); see LidarSlamIssue.
  std::vector<LidarSlamIssue> issues;
};

/// Feeds the 2D scans of the log at `path` to `slam` (polling
/// rove::throw_if_interrupted() once per entry), then calls slam.finish().
/// Throws IoError if the log cannot be opened, ParseError (file, offset or
/// line) on malformed data; SelectionError when the log holds no 2D scan
/// (the message lists what it holds), a single one, or none with a return
/// within the front-end's range interval.
LidarSlamRunResult run_lidar_slam(LidarSlam& slam, const std::string& path,
                                  const LidarSlamRunOptions& options = {});

/// How the final map is rebuilt ([map] section).
struct LidarMapOptions {
  /// (resolution) cell side, meters, > 0. Default 0.05.
  double resolution = 0.05;
  /// MRPT's insertion options and keys (maxDistanceInsertion,
  /// maxOccupancyUpdateCertainty, ...; grid_insertion.h) with their defaults.
  GridInsertionOptions insertion;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The [map] keys over the defaults. Strict: ConfigError (file, section,
  /// key) for an unknown key or a malformed or out-of-range value.
  static LidarMapOptions from_config(const ConfigSection& section);
};

/// The occupancy grid of every node's scan (LidarSlamNode::observation)
/// inserted at its world pose, grown to fit. Nodes without an observation
/// are left out. Precondition (InvalidArgument): options.check().
OccupancyGrid build_lidar_slam_map(const LidarSlam& slam, const LidarMapOptions& options = {});

}  // namespace rove
