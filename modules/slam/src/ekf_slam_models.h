#pragma once
// The range-bearing sensor model of EKF-SLAM (rove/slam/ekf_slam.h) and the
// robot-pose Jacobians it needs, for the planar and the 3D case.

#include <cmath>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/math/se3.h"

namespace rove::detail {

// Below this distance from the sensor (or, in 3D, from its z axis) a point
// has no bearing derivative.
inline constexpr double kMinBearingRadius = 1e-9;

// (range, yaw) of p_s and d(range, yaw)/dp_s. False when ‖p‖ is ~0.
inline bool spherical(const Eigen::Vector2d& p, Eigen::Vector2d& z, Eigen::Matrix2d* J) {
  const double r2 = p.squaredNorm(), r = std::sqrt(r2);
  if (!(r > kMinBearingRadius)) return false;
  z = Eigen::Vector2d(r, std::atan2(p.y(), p.x()));
  if (J) *J << p.x() / r, p.y() / r, -p.y() / r2, p.x() / r2;
  return true;
}

// (range, yaw, pitch) of p_s, pitch = −atan2(z, ρ) (positive below the XY
// plane), and the Jacobian. False on the z axis (ρ ~ 0).
inline bool spherical(const Eigen::Vector3d& p, Eigen::Vector3d& z, Eigen::Matrix3d* J) {
  const double rho2 = p.x() * p.x() + p.y() * p.y(), rho = std::sqrt(rho2);
  if (!(rho > kMinBearingRadius)) return false;
  const double r2 = rho2 + p.z() * p.z(), r = std::sqrt(r2);
  z = Eigen::Vector3d(r, std::atan2(p.y(), p.x()), -std::atan2(p.z(), rho));
  if (J) {
    *J << p.x() / r, p.y() / r, p.z() / r,                             //
        -p.y() / rho2, p.x() / rho2, 0.0,                              //
        p.x() * p.z() / (rho * r2), p.y() * p.z() / (rho * r2), -rho / r2;
  }
  return true;
}

// The point at (range, yaw) and its Jacobian with respect to the reading.
inline Eigen::Vector2d from_spherical(const Eigen::Vector2d& z, Eigen::Matrix2d& J) {
  const double c = std::cos(z[1]), s = std::sin(z[1]);
  J << c, -z[0] * s, s, z[0] * c;
  return Eigen::Vector2d(z[0] * c, z[0] * s);
}

// The point r·(cos p cos y, cos p sin y, −sin p) and its Jacobian.
inline Eigen::Vector3d from_spherical(const Eigen::Vector3d& z, Eigen::Matrix3d& J) {
  const double r = z[0], cy = std::cos(z[1]), sy = std::sin(z[1]);
  const double cp = std::cos(z[2]), sp = std::sin(z[2]);
  J << cp * cy, -r * cp * sy, -r * sp * cy,  //
      cp * sy, r * cp * cy, -r * sp * sy,    //
      -sp, 0.0, -r * cp;
  return Eigen::Vector3d(r * cp * cy, r * cp * sy, -r * sp);
}

// d(exp(δ)⁻¹·q)/dδ at δ = 0: the change of a point seen from a robot whose
// pose moves by δ on the right. exp(δ)·q ≈ q + ρ + θ·(−q_y, q_x) in 2D,
// q + ρ + ω × q in 3D; the inverse action flips the sign.
inline Eigen::Matrix<double, 2, 3> inverse_action_jacobian(const Eigen::Vector2d& q) {
  Eigen::Matrix<double, 2, 3> J;
  J << -1.0, 0.0, q.y(), 0.0, -1.0, -q.x();
  return J;
}

inline Eigen::Matrix<double, 3, 6> inverse_action_jacobian(const Eigen::Vector3d& q) {
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>() = -Eigen::Matrix3d::Identity();
  J.rightCols<3>() << 0.0, -q.z(), q.y(), q.z(), 0.0, -q.x(), -q.y(), q.x(), 0.0;  // [q]×
  return J;
}

}  // namespace rove::detail
