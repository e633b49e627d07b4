#pragma once
/// \file
/// Conversions between the MRPT-style pose types and the Lie groups of
/// rove::math (SE2d, SE3d). Same transform, same frames: T_parent_child.
///
/// Uncertainty: algorithms report covariances over the group's right
/// tangent, T·exp(ξ) with ξ = (ρ, ω) (SE2: (ρx, ρy, θ); docs/conventions.md);
/// the Gaussian PDFs hold them over their parameters, Pose3Gaussian (x, y, z,
/// yaw, pitch, roll) and Pose2Gaussian (x, y, phi). The conversions below
/// map one to the other to first order through the Jacobian of the
/// parameters with respect to ξ at the mean.

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"
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

/// E(yaw, pitch): the matrix with ω = E·(ẏaw, ṗitch, ṙoll)ᵀ, ω the rotation
/// rate in the parent frame (left perturbation R ← exp([δω]ₓ)·R) for
/// R = Rz(yaw)·Ry(pitch)·Rx(roll). Its columns are e_z, Rz·e_y, Rz·Ry·e_x.
Eigen::Matrix3d ypr_rate_to_omega(double yaw, double pitch);

/// d(ρ, ω) / d(x, y, z, yaw, pitch, roll) at `pose`: the right-tangent
/// perturbation of to_se3(pose) that a small change of its parameters makes,
/// ρ = Rᵀ·δt, ω = Rᵀ·E·(δyaw, δpitch, δroll), E's columns the parent-frame
/// rotation axes of R = Rz(yaw)·Ry(pitch)·Rx(roll): e_z, Rz·e_y, Rz·Ry·e_x.
Eigen::Matrix<double, 6, 6> right_tangent_from_ypr_jacobian(const Pose3& pose);

/// d(x, y, z, yaw, pitch, roll) / d(ρ, ω) at `T`, the inverse of
/// right_tangent_from_ypr_jacobian. At gimbal lock (|cos pitch| < 1e-9)
/// yaw and roll are not separable: the pseudo-inverse keeps it finite.
Eigen::Matrix<double, 6, 6> ypr_from_right_tangent_jacobian(const SE3d& T);

/// A covariance over Pose3's (x, y, z, yaw, pitch, roll) at `pose` as one
/// over the right tangent (ρ, ω): J·C·Jᵀ (symmetrized).
Eigen::Matrix<double, 6, 6> ypr_to_right_tangent_covariance(const Pose3& pose,
                                                           const Eigen::Matrix<double, 6, 6>& cov);
/// A right-tangent covariance (ρ, ω) at `T` as one over (x, y, z, yaw,
/// pitch, roll).
Eigen::Matrix<double, 6, 6> right_tangent_to_ypr_covariance(const SE3d& T,
                                                           const Eigen::Matrix<double, 6, 6>& cov);
/// (x, y, phi) ↔ (ρx, ρy, θ): ρ = Rᵀ·δt, θ = δphi.
Eigen::Matrix3d xyphi_to_right_tangent_covariance(const Pose2& pose, const Eigen::Matrix3d& cov);
/// The inverse of xyphi_to_right_tangent_covariance.
Eigen::Matrix3d right_tangent_to_xyphi_covariance(const SE2d& T, const Eigen::Matrix3d& cov);

/// An estimate with a right-tangent covariance as MRPT's Gaussian PDF.
/// Precondition (InvalidArgument): `cov` symmetric PSD (check_covariance).
Pose3Gaussian to_pose3_gaussian(const SE3d& T, const Eigen::Matrix<double, 6, 6>& cov);
/// 2D: as to_pose3_gaussian.
Pose2Gaussian to_pose2_gaussian(const SE2d& T, const Eigen::Matrix3d& cov);

}  // namespace rove
