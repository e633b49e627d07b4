#pragma once
/// \file
/// Trajectories in the TUM RGB-D benchmark's text format: one pose per line,
/// `t x y z qx qy qz qw` (t in seconds, position in meters, the orientation
/// as a unit quaternion), `#` comment lines.

#include <string>
#include <vector>

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

}  // namespace rove
