#pragma once
/// \file
/// Running ICP-SLAM over a whole log, as MRPT's icp-slam application does:
/// each step is one action collection with the sensory frame after it
/// (layout #1) or one observation (layout #2). As MRPT's
/// CRawlog::getActionObservationPairOrObservation, sensory frames met before
/// the first action collection are passed over. Reads rove rawlogs, MRPT
/// rawlogs and CARMEN logs (AnyRawlogReader), streaming in constant memory.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rove/io/any_rawlog.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"
#include "rove/slam/icp_slam.h"
#include "rove/slam/scan_consistency.h"

namespace rove {

/// One step of a run: the state after processing it.
struct IcpSlamStep {
  /// 0-based step index in the log (counting skipped steps).
  std::uint64_t index = 0;
  /// Time of the step's first sensor observation (or of its odometry).
  Timestamp time;
  /// The estimated pose T_map_robot after the step.
  Pose2 pose;
  /// The cumulative odometry after the step (layout #1: the accumulated
  /// action increments; layout #2: the last odometry reading).
  Pose2 odometry;
  /// ICP alignments run / accepted in this step, their iterations.
  unsigned icp_runs = 0;
  unsigned icp_accepted = 0;
  unsigned icp_iterations = 0;
  /// Goodness of the step's last ICP (0 if none ran).
  double icp_goodness = 0.0;
  /// Observations inserted into the map in this step.
  unsigned insertions = 0;
  /// Wall time of the step's processing, seconds (reading excluded).
  double seconds = 0.0;
};

/// Something a finished run must tell its user: the map and path were
/// built, but they are not what ICP-SLAM promises.
struct IcpSlamIssue {
  /// "no-icp-accepted" (ICP ran, no result passed the threshold: the path is
  /// the odometry and the map holds the first scans only),
  /// "few-icp-accepted" (under min_accepted_fraction of the ICP runs) or
  /// "map-contradicts-scans" (the keyframes' 2D scans contradict each other:
  /// scan_consistency.h, IcpSlamRunResult::consistency).
  std::string code;
  /// One line for a person, with the counts and the threshold.
  std::string message;
};

/// Options of run_icp_slam.
struct IcpSlamRunOptions {
  /// Steps at the start of the log to skip (MRPT's rawlog_offset).
  std::uint64_t rawlog_offset = 0;
  /// Stop after this many processed steps (all if unset).
  std::optional<std::uint64_t> max_steps;
  /// Options of the log reader.
  AnyRawlogOptions reader;
  /// Called after every processed step (e.g. progress), if set.
  std::function<void(const IcpSlamStep&)> on_step;
  /// A run whose accepted ICP results are fewer than this fraction of its
  /// ICP runs gets the "few-icp-accepted" issue. Default 0.5; in [0, 1].
  double min_accepted_fraction = 0.5;
};

/// Result of run_icp_slam.
struct IcpSlamRunResult {
  /// Every processed step, in order.
  std::vector<IcpSlamStep> steps;
  /// The log's format.
  RawlogFormat format = RawlogFormat::Mrpt;
  /// Entries read from the log.
  std::uint64_t entries = 0;
  /// Sum of the steps' processing times, seconds (the mapping loop).
  double mapping_seconds = 0.0;
  /// Time spent reading and decoding the log, seconds.
  double read_seconds = 0.0;
  /// Observations in the processed steps that ICP-SLAM can match (2D scans,
  /// 3D range images).
  std::uint64_t scans = 0;
  /// The keyframes' 2D scans replayed against each other at their poses
  /// (scan_consistency.h; a 5 cm grid, MRPT's insertion defaults): a path
  /// that drifted through a loop leaves later keyframes seeing through the
  /// walls of earlier ones. Empty without 2D keyframes.
  ScanConsistency consistency;
  /// What the result does not deliver (empty when fine); see IcpSlamIssue.
  std::vector<IcpSlamIssue> issues;
};

/// The issues of a run with these counters (see IcpSlamIssue), e.g. for a
/// run fed by hand rather than by run_icp_slam.
std::vector<IcpSlamIssue> icp_slam_issues(const IcpSlamStats& stats, const IcpSlamOptions& options,
                                          double min_accepted_fraction = 0.5);

/// Feeds the log at `rawlog_path` to `slam`, polling
/// rove::throw_if_interrupted() once per entry. Throws IoError if it cannot
/// be opened, ParseError (file, byte offset or line, class) on malformed data
/// and on an observation ICP-SLAM rejects (the error names the step's
/// offset in the file); SelectionError when rawlog_offset skips every step
/// or the processed steps hold no 2D scan or range image (the message lists
/// what the log holds). The result's `issues` list what a finished run did
/// not deliver (few or no ICP results accepted, keyframes that contradict
/// each other).
IcpSlamRunResult run_icp_slam(IcpSlam& slam, const std::string& rawlog_path,
                              const IcpSlamRunOptions& options = {});

}  // namespace rove
