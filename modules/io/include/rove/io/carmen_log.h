#pragma once
/// \file
/// Reading CARMEN log files (the text format of the CARMEN robot toolkit,
/// used by the Radish / Freiburg SLAM datasets such as intel.clf and
/// fr079.clf), plain or bzip2-compressed, streamed one line at a time.
///
/// One message per line, fields separated by spaces or tabs:
///   FLASER n r1..rn x y theta odom_x odom_y odom_theta ipc_ts host logger_ts
///   RLASER (as FLASER, the rear laser)
///   ODOM x y theta tv rv accel ipc_ts host logger_ts
///   ROBOTLASER1 laser_type start_angle fov angular_res max_range accuracy
///     remission_mode n r1..rn m e1..em laser_x laser_y laser_theta
///     robot_x robot_y robot_theta tv rv forward_safety side_safety
///     turn_axis ipc_ts host logger_ts
///   TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta ipc_ts host
///     logger_ts
/// Lines starting with '#' are comments; PARAM, SYNC and any other message
/// type are skipped and counted (PARAM robot_front_laser_max and
/// robot_rear_laser_max set the maximum range of the FLASER / RLASER lines
/// after them). Units: meters, radians, seconds.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"

namespace rove {

/// The CARMEN message types the reader turns into records.
enum class CarmenMessage : std::uint8_t {
  Flaser = 0,       ///< front laser with the odometry pose
  Rlaser = 1,       ///< rear laser with the odometry pose
  Odom = 2,         ///< odometry pose and velocities
  RobotLaser1 = 3,  ///< laser with its geometry, remissions and robot state
  TruePos = 4,      ///< ground-truth pose (simulators) with odometry
};

/// The message's name as written in a log ("FLASER", "ODOM", ...).
std::string_view to_string(CarmenMessage message) noexcept;

/// How CarmenLogReader reads a log. Defaults suit the Radish datasets.
struct CarmenLogOptions {
  /// false: a malformed line throws ParseError (file, line, field).
  /// true: it is counted in CarmenLogStats::malformed and skipped.
  bool skip_malformed = false;
  /// Observation time = start_time + logger_timestamp (the last field,
  /// seconds since the logger started). Default: the Unix epoch, so that
  /// timestamp.to_seconds() equals the logger timestamp.
  Timestamp start_time = Timestamp::from_ns(0);
  /// Maximum range, meters, of FLASER/RLASER scans, which do not state one,
  /// until the log's PARAM robot_front_laser_max (FLASER) or
  /// robot_rear_laser_max (RLASER) line gives it. SICK scanners logged by
  /// CARMEN report about 81.9 m for "no return"; some logs use another value
  /// (ACES: 50.00 m). Readings at or above the maximum (or <= 0) are "no
  /// return" and flagged invalid. Must be finite and > 0.
  float flaser_max_range = 81.0f;
  /// Sensor label of FLASER and ROBOTLASER1 scans.
  std::string front_laser_label = "LASER";
  /// Sensor label of RLASER scans.
  std::string rear_laser_label = "LASER_REAR";
  /// Sensor label of ODOM observations.
  std::string odometry_label = "ODOMETRY";
  /// Longest line accepted, bytes (bounds memory on hostile input); a
  /// longer line is malformed.
  std::size_t max_line_bytes = std::size_t{1} << 20;
};

/// One FLASER, RLASER, ODOM, ROBOTLASER1 or TRUEPOS line, decoded.
///
/// Scans (FLASER, RLASER, ROBOTLASER1) become a RangeScan2D as MRPT's
/// carmen2rawlog builds them: rays ordered right to left (counter-clockwise),
/// T_robot_sensor = laser_pose ⊖ robot_pose. FLASER/RLASER have a 180°
/// aperture (π rad) and max range CarmenLogOptions::flaser_max_range;
/// ROBOTLASER1 uses its own field_of_view and maximum_range, and its
/// T_robot_sensor yaw also turns by start_angle + field_of_view/2 so that
/// ray 0 points at start_angle from the laser's x axis.
struct CarmenRecord {
  /// The message type.
  CarmenMessage type = CarmenMessage::Odom;
  /// 1-based line number in the (decompressed) log.
  std::size_t line = 0;
  /// start_time + logger_timestamp; also set on scan / odometry.
  Timestamp timestamp;
  /// The last field: seconds since the logger started.
  double logger_timestamp = 0.0;
  /// Time the message was published (IPC), seconds.
  double ipc_timestamp = 0.0;
  /// Host that published the message.
  std::string ipc_hostname;
  /// FLASER, RLASER, ROBOTLASER1: the scan; null otherwise.
  std::unique_ptr<RangeScan2D> scan;
  /// ODOM: the odometry observation (pose, velocity tv/rv); null otherwise.
  std::unique_ptr<OdometryObservation> odometry;
  /// FLASER, RLASER, ROBOTLASER1: the laser's pose in the odometry frame
  /// (the "x y theta" fields); identity otherwise.
  Pose2 laser_pose;
  /// The robot's pose in the odometry frame: FLASER/RLASER/TRUEPOS
  /// odom_x/odom_y/odom_theta, ROBOTLASER1 robot pose, ODOM x/y/theta.
  Pose2 robot_pose;
  /// TRUEPOS: the ground-truth pose (true_x, true_y, true_theta) in the
  /// world frame; identity otherwise.
  Pose2 true_pose;
  /// ODOM, ROBOTLASER1: translational velocity, m/s.
  double tv = 0.0;
  /// ODOM, ROBOTLASER1: rotational velocity, rad/s.
  double rv = 0.0;
  /// ODOM: acceleration, m/s².
  double accel = 0.0;
  /// ROBOTLASER1: laser_type as logged.
  double laser_type = 0.0;
  /// ROBOTLASER1: start_angle of ray 0 relative to the laser's x axis, rad.
  double start_angle = 0.0;
  /// ROBOTLASER1: angular_resolution, rad.
  double angular_resolution = 0.0;
  /// ROBOTLASER1: the remission (reflectance) values, as logged.
  std::vector<float> remissions;
};

/// How many lines of each kind a reader has seen so far.
struct CarmenLogStats {
  std::size_t lines = 0;        ///< every line read, including blank ones
  std::size_t flaser = 0;       ///< FLASER records returned
  std::size_t rlaser = 0;       ///< RLASER records returned
  std::size_t odom = 0;         ///< ODOM records returned
  std::size_t robotlaser1 = 0;  ///< ROBOTLASER1 records returned
  std::size_t truepos = 0;      ///< TRUEPOS records returned
  std::size_t comments = 0;     ///< lines starting with '#'
  std::size_t blank = 0;        ///< empty or whitespace-only lines
  std::size_t param = 0;        ///< PARAM lines (skipped)
  std::size_t sync = 0;         ///< SYNC lines (skipped)
  std::size_t other = 0;        ///< lines of any other message type (skipped)
  std::size_t malformed = 0;    ///< malformed lines skipped (skip_malformed)
  /// Maximum range of the FLASER / RLASER scans after the last line read,
  /// meters (CarmenLogOptions::flaser_max_range until a PARAM sets it).
  float front_max_range = 0.0f;
  float rear_max_range = 0.0f;
  /// True once a PARAM line set front_max_range / rear_max_range.
  bool front_max_range_from_log = false;
  bool rear_max_range_from_log = false;

  /// FLASER + RLASER + ODOM + ROBOTLASER1 + TRUEPOS records.
  std::size_t records() const noexcept { return flaser + rlaser + odom + robotlaser1 + truepos; }
};

/// Streaming CARMEN log reader: constant memory whatever the file size
/// (one line and one decompression buffer). Input starting with "BZh" is
/// decompressed as bzip2 (concatenated streams included). Move-only;
/// thread-compatible.
class CarmenLogReader {
 public:
  /// Opens a file. Throws IoError if it cannot be opened; InvalidArgument
  /// if options.max_line_bytes is 0 or options.start_time is invalid.
  static CarmenLogReader open(const std::string& path, CarmenLogOptions options = {});
  /// Reads a log held in memory; `source` names it in errors. Same
  /// preconditions on `options` as open().
  static CarmenLogReader from_memory(std::string bytes, std::string source = "<memory>",
                                     CarmenLogOptions options = {});

  /// Move-constructs.
  CarmenLogReader(CarmenLogReader&&) noexcept;
  /// Move-assigns.
  CarmenLogReader& operator=(CarmenLogReader&&) noexcept;
  /// Closes the input.
  ~CarmenLogReader();

  /// Reads up to the next FLASER/RLASER/ODOM/ROBOTLASER1/TRUEPOS line and
  /// fills `record` (every field reset). Returns false at the end of input
  /// (`record` then holds nothing meaningful).
  /// Throws ParseError (source, line, field) on a malformed line unless
  /// skip_malformed; ParseError (source, byte offset, "bzip2") on corrupt
  /// compressed data; IoError on a read failure.
  bool next(CarmenRecord& record);

  /// Counts so far (complete once next() returned false).
  const CarmenLogStats& stats() const noexcept;

 private:
  struct Impl;
  explicit CarmenLogReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// True if `name` is the name of a CARMEN message (the records above, PARAM,
/// SYNC, and the other messages CARMEN's logger writes: RAWLASER1..4,
/// ROBOTLASER2, NMEAGGA, NMEARMC).
bool is_carmen_message_name(std::string_view name) noexcept;

/// Whether the file at `path` (plain or bzip2) looks like a CARMEN log: one
/// of its lines within the first `max_bytes` (decompressed) starts with a
/// CARMEN message name (comments and blank lines aside). Throws IoError if
/// it cannot be read, ParseError on corrupt bzip2 data.
bool looks_like_carmen_log(const std::string& path, std::size_t max_bytes = std::size_t{1} << 18);

/// Reads a whole log and returns its counts (records are decoded and
/// dropped). Same errors as CarmenLogReader::next.
CarmenLogStats count_carmen_log(const std::string& path, const CarmenLogOptions& options = {});

}  // namespace rove
