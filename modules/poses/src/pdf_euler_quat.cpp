#include "rove/poses/pdf_euler_quat.h"

#include <cmath>
#include <numbers>

#include "rove/core/check.h"

namespace rove {

Eigen::Vector4d ypr_to_quat(double yaw, double pitch, double roll,
                            Eigen::Matrix<double, 4, 3>* J_q_ypr) {
  ROVE_CHECK_FINITE(yaw);
  ROVE_CHECK_FINITE(pitch);
  ROVE_CHECK_FINITE(roll);
  const double cy = std::cos(0.5 * yaw), sy = std::sin(0.5 * yaw);
  const double cp = std::cos(0.5 * pitch), sp = std::sin(0.5 * pitch);
  const double cr = std::cos(0.5 * roll), sr = std::sin(0.5 * roll);
  const Eigen::Vector4d q(cr * cp * cy + sr * sp * sy,   // w
                          sr * cp * cy - cr * sp * sy,   // x
                          cr * sp * cy + sr * cp * sy,   // y
                          cr * cp * sy - sr * sp * cy);  // z
  if (J_q_ypr) {
    auto& J = *J_q_ypr;
    // d/d yaw: the half-angle derivative rotates (w,x,y,z) -> (-z,-y,x,w)/2.
    J.col(0) << -0.5 * q[3], -0.5 * q[2], 0.5 * q[1], 0.5 * q[0];
    J.col(1) << 0.5 * (-cr * sp * cy + sr * cp * sy), 0.5 * (-sr * sp * cy - cr * cp * sy),
        0.5 * (cr * cp * cy - sr * sp * sy), 0.5 * (-cr * sp * sy - sr * cp * cy);
    J.col(2) << -0.5 * q[1], 0.5 * q[0], 0.5 * q[3], -0.5 * q[2];
  }
  return q;
}

Eigen::Matrix4d quat_normalization_jacobian(const Eigen::Vector4d& q) {
  const double n2 = q.squaredNorm();
  ROVE_CHECK_MSG(n2 > 0.0 && std::isfinite(n2), "quaternion must be finite and non-zero");
  const double inv_n3 = 1.0 / (n2 * std::sqrt(n2));
  return (n2 * Eigen::Matrix4d::Identity() - q * q.transpose()) * inv_n3;
}

Eigen::Vector3d quat_to_ypr(const Eigen::Vector4d& q_in, Eigen::Matrix<double, 3, 4>* J_ypr_q) {
  ROVE_CHECK_FINITE(q_in);
  const double norm = q_in.norm();
  ROVE_CHECK_MSG(norm > 0.0, "quaternion must be non-zero");
  const Eigen::Vector4d q = q_in / norm;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double discr = w * y - x * z;
  Eigen::Vector3d ypr;
  Eigen::Matrix<double, 3, 4> J_raw = Eigen::Matrix<double, 3, 4>::Zero();
  if (discr > 0.49999 || discr < -0.49999) {
    // Gimbal lock: only yaw ∓ roll is observable; MRPT sets roll = 0.
    const double sign = discr > 0 ? 1.0 : -1.0;
    ypr << -2.0 * sign * std::atan2(x, w), sign * 0.5 * std::numbers::pi, 0.0;
    const double d = w * w + x * x;
    J_raw(0, 0) = sign * 2.0 * x / d;
    J_raw(0, 1) = -sign * 2.0 * w / d;
  } else {
    const double a_y = 2.0 * (w * z + x * y), b_y = 1.0 - 2.0 * (y * y + z * z);
    const double s = 2.0 * discr;
    const double a_r = 2.0 * (w * x + y * z), b_r = 1.0 - 2.0 * (x * x + y * y);
    ypr << std::atan2(a_y, b_y), std::asin(s), std::atan2(a_r, b_r);
    // d atan2(a, b) = (b·da − a·db) / (a² + b²); d asin(s) = ds / sqrt(1 − s²).
    const Eigen::RowVector4d da_y(2 * z, 2 * y, 2 * x, 2 * w), db_y(0, 0, -4 * y, -4 * z);
    const Eigen::RowVector4d ds(2 * y, -2 * z, 2 * w, -2 * x);
    const Eigen::RowVector4d da_r(2 * x, 2 * w, 2 * z, 2 * y), db_r(0, -4 * x, -4 * y, 0);
    J_raw.row(0) = (b_y * da_y - a_y * db_y) / (a_y * a_y + b_y * b_y);
    J_raw.row(1) = ds / std::sqrt(1.0 - s * s);
    J_raw.row(2) = (b_r * da_r - a_r * db_r) / (a_r * a_r + b_r * b_r);
  }
  if (J_ypr_q) *J_ypr_q = J_raw * quat_normalization_jacobian(q_in);
  return ypr;
}

Eigen::Matrix4d quat_left_matrix(const Eigen::Vector4d& a) {
  Eigen::Matrix4d L;
  L << a[0], -a[1], -a[2], -a[3],  //
      a[1], a[0], -a[3], a[2],     //
      a[2], a[3], a[0], -a[1],     //
      a[3], -a[2], a[1], a[0];
  return L;
}

Eigen::Matrix4d quat_right_matrix(const Eigen::Vector4d& b) {
  Eigen::Matrix4d R;
  R << b[0], -b[1], -b[2], -b[3],  //
      b[1], b[0], b[3], -b[2],     //
      b[2], -b[3], b[0], b[1],     //
      b[3], b[2], -b[1], b[0];
  return R;
}

Eigen::Vector4d quat_product(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return quat_left_matrix(a) * b;
}

Eigen::Matrix3d quat_to_rotation(const Eigen::Vector4d& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Matrix3d R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return R;
}

Eigen::Matrix<double, 3, 4> quat_rotate_jacobian(const Eigen::Vector4d& q,
                                                  const Eigen::Vector3d& v) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double a = v[0], b = v[1], c = v[2];
  Eigen::Matrix<double, 3, 4> J;
  J << -z * b + y * c, y * b + z * c, -2 * y * a + x * b + w * c, -2 * z * a - w * b + x * c,
      z * a - x * c, y * a - 2 * x * b - w * c, x * a + z * c, w * a - 2 * z * b + y * c,
      -y * a + x * b, z * a + w * b - 2 * x * c, -w * a + z * b - 2 * y * c, x * a + y * b;
  return 2.0 * J;
}

}  // namespace rove
