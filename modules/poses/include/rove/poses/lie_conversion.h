#pragma once
/// \file
/// Conversions between the MRPT-style pose types and the Lie groups of
/// rove::math (SE2d, SE3d). Same transform, same frames: T_parent_child.

#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/poses/pose3_quat.h"

namespace rove {

/// Pose2 (x, y, phi) as an SE2d.
inline SE2d to_se2(const Pose2& p) { return SE2d(p.x(), p.y(), p.phi()); }

/// SE2d as a Pose2 (phi = the rotation angle, in (-pi, pi]).
inline Pose2 to_pose2(const SE2d& T) {
  return Pose2(T.translation().x(), T.translation().y(), T.rotation().angle());
}

/// Pose3 as an SE3d. Throws InvalidArgument if the rotation matrix is farther
/// from orthonormal than SO3 accepts (kUnitTolerance, 1e-6).
inline SE3d to_se3(const Pose3& p) { return SE3d(p.rotation(), p.translation()); }

/// Pose3Quat as an SE3d (same unit quaternion).
inline SE3d to_se3(const Pose3Quat& p) { return SE3d(p.quaternion(), p.translation()); }

/// SE3d as a Pose3 (rotation matrix of the SE3d's quaternion).
inline Pose3 to_pose3(const SE3d& T) {
  return Pose3(detail::kUnchecked, T.rotation_matrix(), T.translation());
}

/// SE3d as a Pose3Quat (its quaternion, made w >= 0).
inline Pose3Quat to_pose3_quat(const SE3d& T) { return Pose3Quat(T.translation(), T.quaternion()); }

}  // namespace rove
