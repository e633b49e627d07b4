#include "rove/poses/pdf_jacobians.h"

#include <cmath>

#include "rove/poses/pdf_euler_quat.h"
#include "pdf_jacobians_detail.h"

namespace rove {
namespace detail {

Eigen::Vector4d quat_vector(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

Eigen::Vector4d quat_conjugate(const Eigen::Vector4d& q) { return {q[0], -q[1], -q[2], -q[3]}; }

PairJacobians<7> compose7(const Eigen::Vector4d& qa,
                          const Eigen::Vector3d& tb, const Eigen::Vector4d& qb) {
  // F(a, b) = (t_a + R(q̂_a)·t_b, normalize(q_a ⊗ q_b)); Blanco (2010) §5.1.
  const Eigen::Vector4d p = quat_product(qa, qb);
  const Eigen::Matrix4d N_p = quat_normalization_jacobian(p);
  PairJacobians<7> J;
  J.d_a.setZero();
  J.d_a.topLeftCorner<3, 3>().setIdentity();
  J.d_a.topRightCorner<3, 4>() = quat_rotate_jacobian(qa, tb) * quat_normalization_jacobian(qa);
  J.d_a.bottomRightCorner<4, 4>() = N_p * quat_right_matrix(qb);
  J.d_b.setZero();
  J.d_b.topLeftCorner<3, 3>() = quat_to_rotation(qa / qa.norm());
  J.d_b.bottomRightCorner<4, 4>() = N_p * quat_left_matrix(qa);
  return J;
}

Eigen::Matrix<double, 7, 7> inverse7(const Eigen::Vector3d& t, const Eigen::Vector4d& q) {
  // G(a) = (−R(q̂)ᵀ·t, conj(q̂)); R(q)ᵀ·v = R(conj(q))·v. Blanco (2010) §5.3.
  const Eigen::Matrix4d N = quat_normalization_jacobian(q);
  const Eigen::Vector4d qn = q / q.norm();
  const Eigen::Vector4d conj_signs(1.0, -1.0, -1.0, -1.0);
  Eigen::Matrix<double, 7, 7> J = Eigen::Matrix<double, 7, 7>::Zero();
  J.topLeftCorner<3, 3>() = -quat_to_rotation(qn).transpose();
  J.topRightCorner<3, 4>() =
      quat_rotate_jacobian(quat_conjugate(qn), -t) * conj_signs.asDiagonal() * N;
  J.bottomRightCorner<4, 4>() = conj_signs.asDiagonal() * N;
  return J;
}

Eigen::Matrix<double, 7, 6> euler_to_quat7(const Pose3& p, Eigen::Vector4d* q_out) {
  const YawPitchRoll a = p.yaw_pitch_roll();
  Eigen::Matrix<double, 4, 3> E;
  const Eigen::Vector4d q = ypr_to_quat(a.yaw, a.pitch, a.roll, &E);
  if (q_out) *q_out = q;
  Eigen::Matrix<double, 7, 6> J = Eigen::Matrix<double, 7, 6>::Zero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<4, 3>() = E;
  return J;
}

Eigen::Matrix<double, 6, 7> quat_to_euler7(const Eigen::Vector4d& q) {
  Eigen::Matrix<double, 3, 4> Q;
  quat_to_ypr(q, &Q);
  Eigen::Matrix<double, 6, 7> J = Eigen::Matrix<double, 6, 7>::Zero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<3, 4>() = Q;
  return J;
}

void align_quaternion_rows(Eigen::Ref<Eigen::MatrixXd> J, const Eigen::Vector4d& q_jacobian,
                           const Eigen::Quaterniond& q_result) {
  if (q_jacobian.dot(quat_vector(q_result)) < 0.0) J.middleRows<4>(3) *= -1.0;
}

}  // namespace detail

PairJacobians<3> jacobians_compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  PairJacobians<3> J;
  J.d_a << 1.0, 0.0, -s * b.x() - c * b.y(),  //
      0.0, 1.0, c * b.x() - s * b.y(),        //
      0.0, 0.0, 1.0;
  J.d_b << c, -s, 0.0,  //
      s, c, 0.0,        //
      0.0, 0.0, 1.0;
  return J;
}

Eigen::Matrix3d jacobian_inverse(const Pose2& a) {
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  Eigen::Matrix3d J;
  J << -c, -s, a.x() * s - a.y() * c,  //
      s, -c, a.x() * c + a.y() * s,    //
      0.0, 0.0, -1.0;
  return J;
}

PairJacobians<3> jacobians_inverse_compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(b.phi()), s = std::sin(b.phi());
  const double dx = a.x() - b.x(), dy = a.y() - b.y();
  PairJacobians<3> J;
  J.d_a << c, s, 0.0,  //
      -s, c, 0.0,      //
      0.0, 0.0, 1.0;
  J.d_b << -c, -s, -dx * s + dy * c,  //
      s, -c, -dx * c - dy * s,        //
      0.0, 0.0, -1.0;
  return J;
}

PairJacobians<7> jacobians_compose(const Pose3Quat& a, const Pose3Quat& b) {
  const Eigen::Vector4d qa = detail::quat_vector(a.quaternion());
  const Eigen::Vector4d qb = detail::quat_vector(b.quaternion());
  PairJacobians<7> J = detail::compose7(qa, b.translation(), qb);
  const Pose3Quat r = a + b;
  const Eigen::Vector4d p = quat_product(qa, qb);
  detail::align_quaternion_rows(J.d_a, p, r.quaternion());
  detail::align_quaternion_rows(J.d_b, p, r.quaternion());
  return J;
}

Eigen::Matrix<double, 7, 7> jacobian_inverse(const Pose3Quat& a) {
  const Eigen::Vector4d qa = detail::quat_vector(a.quaternion());
  Eigen::Matrix<double, 7, 7> J = detail::inverse7(a.translation(), qa);
  detail::align_quaternion_rows(J, detail::quat_conjugate(qa), a.inverse().quaternion());
  return J;
}

PairJacobians<7> jacobians_inverse_compose(const Pose3Quat& a, const Pose3Quat& b) {
  // a ⊖ b = b⁻¹ ⊕ a, chain rule through the inverse.
  const Eigen::Vector4d qa = detail::quat_vector(a.quaternion());
  const Eigen::Vector4d qb = detail::quat_vector(b.quaternion());
  const Eigen::Vector4d qbi = detail::quat_conjugate(qb);
  const PairJacobians<7> Jc = detail::compose7(qbi, a.translation(), qa);
  PairJacobians<7> J;
  J.d_a = Jc.d_b;
  J.d_b = Jc.d_a * detail::inverse7(b.translation(), qb);
  const Pose3Quat r = a - b;
  const Eigen::Vector4d p = quat_product(qbi, qa);
  detail::align_quaternion_rows(J.d_a, p, r.quaternion());
  detail::align_quaternion_rows(J.d_b, p, r.quaternion());
  return J;
}

PairJacobians<6> jacobians_compose(const Pose3& a, const Pose3& b) {
  Eigen::Vector4d qa, qb;
  const Eigen::Matrix<double, 7, 6> Ea = detail::euler_to_quat7(a, &qa);
  const Eigen::Matrix<double, 7, 6> Eb = detail::euler_to_quat7(b, &qb);
  const PairJacobians<7> Jc = detail::compose7(qa, b.translation(), qb);
  const Eigen::Matrix<double, 6, 7> Q = detail::quat_to_euler7(quat_product(qa, qb));
  PairJacobians<6> J;
  J.d_a = Q * Jc.d_a * Ea;
  J.d_b = Q * Jc.d_b * Eb;
  return J;
}

Eigen::Matrix<double, 6, 6> jacobian_inverse(const Pose3& a) {
  Eigen::Vector4d qa;
  const Eigen::Matrix<double, 7, 6> Ea = detail::euler_to_quat7(a, &qa);
  const Eigen::Matrix<double, 6, 7> Q = detail::quat_to_euler7(detail::quat_conjugate(qa));
  return Q * detail::inverse7(a.translation(), qa) * Ea;
}

PairJacobians<6> jacobians_inverse_compose(const Pose3& a, const Pose3& b) {
  Eigen::Vector4d qa, qb;
  const Eigen::Matrix<double, 7, 6> Ea = detail::euler_to_quat7(a, &qa);
  const Eigen::Matrix<double, 7, 6> Eb = detail::euler_to_quat7(b, &qb);
  const Eigen::Vector4d qbi = detail::quat_conjugate(qb);
  const PairJacobians<7> Jc = detail::compose7(qbi, a.translation(), qa);
  const Eigen::Matrix<double, 6, 7> Q = detail::quat_to_euler7(quat_product(qbi, qa));
  PairJacobians<6> J;
  J.d_a = Q * Jc.d_b * Ea;
  J.d_b = Q * Jc.d_a * detail::inverse7(b.translation(), qb) * Eb;
  return J;
}

Eigen::Matrix<double, 7, 6> jacobian_pose3_to_quat(const Pose3& p) {
  Eigen::Vector4d q;
  Eigen::Matrix<double, 7, 6> J = detail::euler_to_quat7(p, &q);
  detail::align_quaternion_rows(J, q, Pose3Quat(p).quaternion());
  return J;
}

Eigen::Matrix<double, 6, 7> jacobian_quat_to_pose3(const Pose3Quat& p) {
  return detail::quat_to_euler7(detail::quat_vector(p.quaternion()));
}

}  // namespace rove
