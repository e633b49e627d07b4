#pragma once
/// \file
/// Trajectories in the TUM RGB-D benchmark's text format: one pose per line,
/// `t x y z qx qy qz qw` (t in seconds, position in meters, the orientation
/// as a unit quaternion), `#` comment lines.

#include <string>
#include <string_view>
#include <vector>

#include "rove/io/trajectory_files.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"

namespace rove {

/// A planar pose at a time.
struct TimedPose2 {
  Timestamp time;  ///< when (invalid: unknown)
  Pose2 pose;      ///< T_world_robot
};

/// Writes a `# t x y z qx qy qz qw` header and one line per pose: t in
/// seconds since the Unix epoch with 6 decimals, x and y with 6, z = 0, the
/// quaternion of a rotation by phi about z (qx = qy = 0) with 9. A pose
/// with an invalid time gets its index as time. Written atomically
/// (rove/core/files.h); throws IoError if the file cannot be written.
void write_tum_trajectory(const std::string& path, const std::vector<TimedPose2>& poses);

/// A 3D pose at a time.
struct TimedPose3 {
  Timestamp time;  ///< when (invalid: unknown)
  SE3d pose;       ///< T_world_robot
};

/// As the planar overload, for 3D poses: x, y, z with 6 decimals and the
/// pose's unit quaternion (made qw >= 0) with 9.
void write_tum_trajectory(const std::string& path, const std::vector<TimedPose3>& poses);

/// Reads a TUM trajectory: blank and `#` lines are skipped, every other line
/// holds 8 numbers. Throws IoError if the file cannot be read, ParseError
/// (file, line, field) for a line with another count of fields, a number
/// that does not parse or is not finite, or a quaternion of norm 0.
std::vector<StampedPose3> read_tum_trajectory(const std::string& path);

/// Parses a TUM trajectory from text; `source` names it in errors.
std::vector<StampedPose3> parse_tum_trajectory(std::string_view text,
                                               std::string_view source = "<string>");

}  // namespace rove
