#pragma once
/// \file
/// Exact analytic Jacobians of pose composition (⊕), inverse composition (⊖)
/// and inversion, in the parameterizations whose covariances rove's Gaussian
/// PDFs carry (orderings as MRPT):
///  - Pose2: (x, y, phi);
///  - Pose3: (x, y, z, yaw, pitch, roll);
///  - Pose3Quat: (x, y, z, qw, qx, qy, qz).
///
/// Pose3Quat functions differentiate the 7-vector maps in which the quaternion
/// is normalized, so their Jacobians are exact for non-unit perturbations too:
///   a ⊕ b = (t_a + R(q̂_a)·t_b, normalize(q_a ⊗ q_b)),
///   a⁻¹   = (−R(q̂_a)ᵀ·t_a, conj(normalize(q_a))),
/// with q̂ = q/|q| (J.L. Blanco, "A tutorial on SE(3) transformation
/// parameterizations and on-manifold optimization", 2010, §5.1-5.3, and MRPT's
/// CPose3DQuatPDF::jacobiansPoseComposition). The quaternion rows follow the
/// sign of the returned pose: if its quaternion is the negated product (a
/// pose type that keeps qw ≥ 0), the rows are negated too.
///
/// Pose3 Jacobians are the chain rule through the quaternion path, as MRPT's
/// CPose3DPDF::jacobiansPoseComposition:
///   J = J_{ypr←quat}(result) · J_{quat ⊕} · J_{quat←ypr}(operand),
/// which is the exact derivative of the yaw-pitch-roll map away from gimbal
/// lock (|pitch| → π/2); there the yaw-pitch-roll Jacobian is MRPT's
/// degenerate one (see quat_to_ypr).

#include <Eigen/Core>

#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/poses/pose3_quat.h"

namespace rove {

/// The two Jacobians of a binary pose operation f(a, b): d f/d a and d f/d b,
/// each N×N in the parameterization of the pose type.
template <int N>
struct PairJacobians {
  Eigen::Matrix<double, N, N> d_a;  ///< d f / d a
  Eigen::Matrix<double, N, N> d_b;  ///< d f / d b
};

/// Jacobians of a ⊕ b for Pose2 (x, y, phi) (MRPT's
/// CPosePDF::jacobiansPoseComposition).
PairJacobians<3> jacobians_compose(const Pose2& a, const Pose2& b);
/// Jacobians of a ⊕ b for Pose3 (x, y, z, yaw, pitch, roll).
PairJacobians<6> jacobians_compose(const Pose3& a, const Pose3& b);
/// Jacobians of a ⊕ b for Pose3Quat (x, y, z, qw, qx, qy, qz).
PairJacobians<7> jacobians_compose(const Pose3Quat& a, const Pose3Quat& b);

/// Jacobians of a ⊖ b = b⁻¹ ⊕ a ("a as seen from b") for Pose2.
PairJacobians<3> jacobians_inverse_compose(const Pose2& a, const Pose2& b);
/// Jacobians of a ⊖ b = b⁻¹ ⊕ a for Pose3.
PairJacobians<6> jacobians_inverse_compose(const Pose3& a, const Pose3& b);
/// Jacobians of a ⊖ b = b⁻¹ ⊕ a for Pose3Quat.
PairJacobians<7> jacobians_inverse_compose(const Pose3Quat& a, const Pose3Quat& b);

/// Jacobian d(a⁻¹)/da for Pose2.
Eigen::Matrix3d jacobian_inverse(const Pose2& a);
/// Jacobian d(a⁻¹)/da for Pose3.
Eigen::Matrix<double, 6, 6> jacobian_inverse(const Pose3& a);
/// Jacobian d(a⁻¹)/da for Pose3Quat (MRPT's
/// CPose3DQuatPDFGaussian::inverseJacobian).
Eigen::Matrix<double, 7, 7> jacobian_inverse(const Pose3Quat& a);

/// Jacobian of the Pose3 → Pose3Quat conversion, d(x, y, z, qw, qx, qy, qz) /
/// d(x, y, z, yaw, pitch, roll), 7×6, for the quaternion of ypr_to_quat
/// (not sign-canonicalized).
Eigen::Matrix<double, 7, 6> jacobian_pose3_to_quat(const Pose3& p);

/// Jacobian of the Pose3Quat → Pose3 conversion, d(x, y, z, yaw, pitch, roll) /
/// d(x, y, z, qw, qx, qy, qz), 6×7, including the quaternion normalization
/// Jacobian (as MRPT's CPose3DPDFGaussian::copyFrom(CPose3DQuatPDFGaussian)).
Eigen::Matrix<double, 6, 7> jacobian_quat_to_pose3(const Pose3Quat& p);

}  // namespace rove
