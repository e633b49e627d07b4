#pragma once
// Internal building blocks of pdf_jacobians.cpp shared with the Gaussian PDF
// sources: the 7-parameter (x, y, z, qw, qx, qy, qz) maps and conversions on
// raw quaternion 4-vectors.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/poses/pdf_jacobians.h"

namespace rove::detail {

// (qw, qx, qy, qz) of an Eigen quaternion.
Eigen::Vector4d quat_vector(const Eigen::Quaterniond& q);
// Conjugate of (qw, qx, qy, qz).
Eigen::Vector4d quat_conjugate(const Eigen::Vector4d& q);
// Jacobians of (t_a + R(q̂_a) t_b, normalize(q_a ⊗ q_b)) for raw quaternions
// (independent of t_a).
PairJacobians<7> compose7(const Eigen::Vector4d& qa,
                          const Eigen::Vector3d& tb, const Eigen::Vector4d& qb);
// Jacobian of (−R(q̂)ᵀ t, conj(q̂)).
Eigen::Matrix<double, 7, 7> inverse7(const Eigen::Vector3d& t, const Eigen::Vector4d& q);
// [I 0; 0 d q/d ypr] at p's yaw-pitch-roll; q_out receives the raw quaternion.
Eigen::Matrix<double, 7, 6> euler_to_quat7(const Pose3& p, Eigen::Vector4d* q_out);
// [I 0; 0 d ypr/d q] (normalization included) at q.
Eigen::Matrix<double, 6, 7> quat_to_euler7(const Eigen::Vector4d& q);
// Negates rows 3..6 of J when q_result is the negation of q_jacobian, the
// quaternion at which J's quaternion rows were computed.
void align_quaternion_rows(Eigen::Ref<Eigen::MatrixXd> J, const Eigen::Vector4d& q_jacobian,
                           const Eigen::Quaterniond& q_result);

}  // namespace rove::detail
