#pragma once
/// \file
/// Trajectories and relations as text files, for evaluation (rove eval):
///  - KITTI odometry poses: one pose per line, the 12 numbers of the 3×4
///    matrix [R | t] row by row (T_world_camera), no time; the line index is
///    the time (or the times come from the sequence's `times.txt`);
///  - Freiburg relations (Kümmerle et al., "On measuring the accuracy of
///    SLAM algorithms", Auton. Robots 2009): `t1 t2 x y z roll pitch yaw`,
///    the pose at t2 in the frame of the pose at t1, R = Rz(yaw)·Ry(pitch)·Rx(roll).
/// TUM trajectories are in tum_trajectory.h.

#include <string>
#include <string_view>
#include <vector>

#include "rove/math/se3.h"

namespace rove {

/// A pose at a time (seconds, or an index where the format has no time).
struct StampedPose3 {
  double time = 0.0;  ///< seconds
  SE3d pose;          ///< T_world_body
};

/// Reads KITTI poses: line k (0-based, blank lines excluded) gets time k.
/// The rotation is made orthonormal (the files hold 6–7 digits). Throws
/// IoError if the file cannot be read; ParseError (file, line, field) for a
/// line without 12 finite numbers, or a block farther than 1e-3 from a
/// rotation.
std::vector<StampedPose3> read_kitti_trajectory(const std::string& path);

/// Parses KITTI poses from text; `source` names it in errors.
std::vector<StampedPose3> parse_kitti_trajectory(std::string_view text,
                                                 std::string_view source = "<string>");

/// A relative pose between two times: the pose at t2 seen from the pose at t1.
struct PoseRelation {
  double t1 = 0.0;  ///< seconds
  double t2 = 0.0;  ///< seconds
  SE3d T_1_2;       ///< the relative pose
};

/// Reads a Freiburg relations file; blank and `#` lines are skipped. Throws
/// IoError if the file cannot be read, ParseError (file, line, field) for a
/// line without 8 finite numbers.
std::vector<PoseRelation> read_relations(const std::string& path);

/// Parses relations from text; `source` names it in errors.
std::vector<PoseRelation> parse_relations(std::string_view text,
                                          std::string_view source = "<string>");

/// The fields of the first line that is not blank or a `#` comment (empty
/// for none): 8 numbers for TUM, 12 for KITTI, a record name first for a
/// g2o/TORO graph. For telling the formats apart.
std::vector<std::string> first_row_fields(std::string_view text);

}  // namespace rove
