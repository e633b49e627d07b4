#pragma once
/// \file
/// Yaw/pitch/roll (Z-Y-X Euler angles) as MRPT defines them:
/// R = Rz(yaw) * Ry(pitch) * Rx(roll), angles in radians. A positive pitch
/// turns the x axis below the XY plane (R(2,0) = -sin(pitch)).
/// Conversions to and from rotation matrices and unit quaternions use MRPT's
/// formulas (TPose3D::getRotationMatrix, SO3_to_yaw_pitch_roll,
/// getAsQuaternion; CQuaternion::rotationMatrix), so results match MRPT.

#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rove {

/// Z-Y-X Euler angles in radians.
struct YawPitchRoll {
  double yaw = 0.0;    ///< rotation about z, radians
  double pitch = 0.0;  ///< rotation about the rotated y, radians
  double roll = 0.0;   ///< rotation about the twice-rotated x, radians
};

/// The rotation matrix Rz(yaw) * Ry(pitch) * Rx(roll); any finite angles.
inline Eigen::Matrix3d rotation_from_ypr(double yaw, double pitch, double roll) noexcept {
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cr = std::cos(roll), sr = std::sin(roll);
  Eigen::Matrix3d R;
  R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return R;
}

/// Yaw, pitch and roll of a rotation matrix, with MRPT's formula:
/// pitch = atan2(-R20, hypot(R00, R10)) in [-pi/2, pi/2]; yaw and roll in
/// (-pi, pi]. At gimbal lock (|R21| + |R22| < 10 eps, i.e. pitch = +-90 deg)
/// roll is set to 0 and the whole rotation about z goes into yaw.
/// Precondition (not checked): R is a rotation matrix.
inline YawPitchRoll ypr_from_rotation(const Eigen::Matrix3d& R) noexcept {
  YawPitchRoll a;
  a.pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  if (std::abs(R(2, 1)) + std::abs(R(2, 2)) < 10.0 * std::numeric_limits<double>::epsilon()) {
    a.roll = 0.0;
    a.yaw = a.pitch > 0 ? std::atan2(R(1, 2), R(0, 2)) : std::atan2(-R(1, 2), -R(0, 2));
  } else {
    a.roll = std::atan2(R(2, 1), R(2, 2));
    a.yaw = std::atan2(R(1, 0), R(0, 0));
  }
  return a;
}

/// The unit quaternion (w, x, y, z) of Rz(yaw) * Ry(pitch) * Rx(roll), by
/// MRPT's half-angle formula (TPose3D::getAsQuaternion). As in MRPT, the sign
/// is not normalized: w may be negative (e.g. yaw = roll = 170 deg,
/// pitch = -80 deg).
inline Eigen::Quaterniond quaternion_from_ypr(double yaw, double pitch, double roll) noexcept {
  const double cy = std::cos(yaw * 0.5), sy = std::sin(yaw * 0.5);
  const double cp = std::cos(pitch * 0.5), sp = std::sin(pitch * 0.5);
  const double cr = std::cos(roll * 0.5), sr = std::sin(roll * 0.5);
  return Eigen::Quaterniond(cr * cp * cy + sr * sp * sy,   // w
                            sr * cp * cy - cr * sp * sy,   // x
                            cr * sp * cy + sr * cp * sy,   // y
                            cr * cp * sy - sr * sp * cy);  // z
}

/// The rotation matrix of a unit quaternion, with MRPT's formula
/// (diagonal as w^2 + x^2 - y^2 - z^2, ...). Precondition (not checked):
/// q has unit norm.
inline Eigen::Matrix3d rotation_from_quaternion(const Eigen::Quaterniond& q) noexcept {
  const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
  Eigen::Matrix3d R;
  R << w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (z * x + w * y),  //
      2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),   //
      2 * (z * x - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z;
  return R;
}

}  // namespace rove
