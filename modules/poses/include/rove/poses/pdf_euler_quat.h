#pragma once
/// \file
/// Yaw-pitch-roll ↔ quaternion conversions with their Jacobians, as used to
/// move pose uncertainty between Pose3 (x, y, z, yaw, pitch, roll) and
/// Pose3Quat (x, y, z, qw, qx, qy, qz). Quaternions here are plain 4-vectors
/// ordered (qw, qx, qy, qz), the covariance ordering of Pose3QuatGaussian,
/// Hamilton convention, R = Rz(yaw)·Ry(pitch)·Rx(roll).
///
/// The formulas and the gimbal-lock handling are those of J.L. Blanco,
/// "A tutorial on SE(3) transformation parameterizations and on-manifold
/// optimization" (tech. report, 2010), §2.1-2.2, as implemented by MRPT.

#include <Eigen/Core>

namespace rove {

/// Quaternion (qw, qx, qy, qz) of R = Rz(yaw)·Ry(pitch)·Rx(roll), angles in
/// radians (Blanco 2010, eq. 2.5). The sign is not canonicalized: qw may be
/// negative, as in MRPT, so that the Jacobian below is continuous.
/// If `J_q_ypr` is given it receives d q / d (yaw, pitch, roll), 4×3.
/// Precondition: finite angles.
Eigen::Vector4d ypr_to_quat(double yaw, double pitch, double roll,
                            Eigen::Matrix<double, 4, 3>* J_q_ypr = nullptr);

/// (yaw, pitch, roll) in radians of the rotation of the quaternion `q`
/// (qw, qx, qy, qz), normalized first (Blanco 2010, eq. 2.9). Near gimbal lock
/// (|qw·qy − qx·qz| > 0.49999) pitch is ±π/2, roll 0 and yaw = ∓2·atan2(qx, qw),
/// as MRPT. If `J_ypr_q` is given it receives d (yaw, pitch, roll) / d q, 3×4,
/// including the normalization Jacobian (so it is exact for non-unit q too).
/// Precondition: q finite and non-zero.
Eigen::Vector3d quat_to_ypr(const Eigen::Vector4d& q,
                            Eigen::Matrix<double, 3, 4>* J_ypr_q = nullptr);

/// Jacobian of q ↦ q/|q|, 4×4: (|q|²·I − q·qᵀ)/|q|³. Precondition: q ≠ 0.
Eigen::Matrix4d quat_normalization_jacobian(const Eigen::Vector4d& q);

/// Hamilton product a ⊗ b of quaternions ordered (qw, qx, qy, qz).
Eigen::Vector4d quat_product(const Eigen::Vector4d& a, const Eigen::Vector4d& b);

/// Matrix L(a) with a ⊗ b = L(a)·b (d(a ⊗ b)/db).
Eigen::Matrix4d quat_left_matrix(const Eigen::Vector4d& a);

/// Matrix R(b) with a ⊗ b = R(b)·a (d(a ⊗ b)/da).
Eigen::Matrix4d quat_right_matrix(const Eigen::Vector4d& b);

/// Rotation matrix of a unit quaternion (qw, qx, qy, qz) by the quadratic
/// formula (Blanco 2010, eq. 2.15); for a non-unit q it is not orthogonal.
Eigen::Matrix3d quat_to_rotation(const Eigen::Vector4d& q);

/// d(R(q)·v)/dq, 3×4, of the quadratic formula of quat_to_rotation (not
/// including normalization: multiply by quat_normalization_jacobian for the
/// derivative of R(q/|q|)·v).
Eigen::Matrix<double, 3, 4> quat_rotate_jacobian(const Eigen::Vector4d& q,
                                                  const Eigen::Vector3d& v);

}  // namespace rove
