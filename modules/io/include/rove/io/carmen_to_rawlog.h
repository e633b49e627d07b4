#pragma once
/// \file
/// CARMEN log → rawlog entries, as MRPT's carmen2rawlog turns a CARMEN log
/// into a rawlog, streamed one entry at a time in constant memory.
///
/// Layout #1 (actions + sensory frames; the default): every laser line
/// (FLASER, RLASER, ROBOTLASER1) becomes a sensory frame holding its scan;
/// between two consecutive frames an action collection holds one
/// RobotMovement2D whose odometry increment is the change of the robot's
/// odometry pose between the two laser lines (pose_k ⊖ pose_{k-1}, in the
/// robot frame at k-1), with the motion model of the options (MRPT's
/// Gaussian model with its default parameters unless changed), timestamped
/// with the later scan. The first frame has no action before it. ODOM lines
/// are not needed (the laser lines carry the odometry pose at scan time);
/// they are counted in CarmenRawlogStats::odom_not_used.
///
/// Layout #2 (observations), as MRPT 2.5.8's carmen2rawlog writes: every
/// laser line gives an OdometryObservation (the line's robot pose, labeled
/// with CarmenLogOptions::odometry_label) followed by the scan; ODOM lines
/// give an OdometryObservation with their velocities (vx = tv, omega = rv)
/// unless odom_lines is false.
///
/// TRUEPOS lines (ground truth of simulators) have no rawlog entry: they
/// are counted in truepos_dropped.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "rove/io/carmen_log.h"
#include "rove/io/rawlog_reader.h"
#include "rove/obs/motion_model_options.h"

namespace rove {

/// How CARMEN lines become rawlog entries.
struct CarmenToRawlogOptions {
  /// kActionsSensoryFrames (#1, default) or kObservations (#2).
  RawlogLayout layout = RawlogLayout::ActionsSensoryFrames;
  /// Motion model stored in the layout #1 actions (default: MRPT's
  /// Gaussian model and default parameters).
  MotionModelOptions motion_model;
  /// Layout #2: ODOM lines become OdometryObservations (default true).
  bool odom_lines = true;
  /// How the log is read (labels, max range, malformed lines).
  CarmenLogOptions log;
};

/// What a conversion produced and what it left out. Every line the reader
/// returned is in exactly one of scans, odom_lines_used, odom_not_used and
/// truepos_dropped; the reader's own counts are in `log`.
struct CarmenRawlogStats {
  std::uint64_t scans = 0;             ///< laser lines (each gives one scan)
  std::uint64_t odom_lines_used = 0;   ///< ODOM lines written (layout #2)
  std::uint64_t odom_not_used = 0;     ///< ODOM lines without an entry
  std::uint64_t truepos_dropped = 0;   ///< TRUEPOS lines (no rawlog entry)
  std::uint64_t sensory_frames = 0;    ///< entries written, by kind
  std::uint64_t action_collections = 0;
  std::uint64_t observations = 0;      ///< bare observations (layout #2)
  CarmenLogStats log;                  ///< the reader's line counts
};

/// Streams the rawlog entries of a CARMEN log (see the file comment).
/// Thread-compatible; move-only.
class CarmenRawlogSource {
 public:
  /// Opens `path` (plain or bzip2). Throws IoError if it cannot;
  /// InvalidArgument if options.layout is neither #1 nor #2 or the motion
  /// model options fail their check.
  static CarmenRawlogSource open(const std::string& path, CarmenToRawlogOptions options = {});
  /// Reads a log held in memory; `source` names it in errors.
  static CarmenRawlogSource from_memory(std::string bytes, std::string source = "<memory>",
                                        CarmenToRawlogOptions options = {});

  /// The next entry, or std::nullopt at the end. Throws what
  /// CarmenLogReader::next throws (ParseError with file, line and field).
  std::optional<RawlogEntry> next();
  /// Counts so far (complete after next() returned std::nullopt).
  const CarmenRawlogStats& stats() const noexcept { return stats_; }
  /// The layout the entries follow.
  RawlogLayout layout() const noexcept { return options_.layout; }
  /// Last line number read (1-based), for progress and messages.
  std::uint64_t lines_read() const noexcept { return reader_.stats().lines; }

 private:
  CarmenRawlogSource(CarmenLogReader reader, CarmenToRawlogOptions options);
  void convert(CarmenRecord& record);

  CarmenLogReader reader_;
  CarmenToRawlogOptions options_;
  CarmenRawlogStats stats_;
  std::deque<RawlogEntry> pending_;
  std::optional<Pose2> last_scan_pose_;
  CarmenRecord record_;
};

}  // namespace rove
