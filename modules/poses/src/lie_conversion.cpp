#include "rove/poses/lie_conversion.h"

#include <cmath>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace rove {
namespace {

template <int N>
Eigen::Matrix<double, N, N> congruent(const Eigen::Matrix<double, N, N>& J,
                                      const Eigen::Matrix<double, N, N>& C) {
  const Eigen::Matrix<double, N, N> out = J * C * J.transpose();
  return 0.5 * (out + out.transpose());
}

}  // namespace

Eigen::Matrix3d ypr_rate_to_omega(double yaw, double pitch) {
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  Eigen::Matrix3d E;
  // Columns: d/dyaw rotates about the parent z; d/dpitch about Rz·y; d/droll
  // about Rz·Ry·x (the chain rule of R = Rz·Ry·Rx under a left perturbation).
  E.col(0) = Eigen::Vector3d(0, 0, 1);
  E.col(1) = Eigen::Vector3d(-sy, cy, 0);
  E.col(2) = Eigen::Vector3d(cy * cp, sy * cp, -sp);
  return E;
}

Eigen::Matrix<double, 6, 6> right_tangent_from_ypr_jacobian(const Pose3& pose) {
  const Eigen::Matrix3d Rt = pose.rotation().transpose();
  Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
  J.topLeftCorner<3, 3>() = Rt;
  J.bottomRightCorner<3, 3>() = Rt * ypr_rate_to_omega(pose.yaw(), pose.pitch());
  return J;
}

Eigen::Matrix<double, 6, 6> ypr_from_right_tangent_jacobian(const SE3d& T) {
  const Pose3 pose = to_pose3(T);
  const Eigen::Matrix3d R = T.rotation_matrix();
  const Eigen::Matrix3d E = ypr_rate_to_omega(pose.yaw(), pose.pitch());
  const Eigen::Matrix3d E_inv =
      std::abs(std::cos(pose.pitch())) >= 1e-9
          ? Eigen::Matrix3d(E.inverse())
          : Eigen::Matrix3d(E.jacobiSvd(Eigen::ComputeFullU | Eigen::ComputeFullV)
                                .solve(Eigen::Matrix3d::Identity()));
  Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
  J.topLeftCorner<3, 3>() = R;
  J.bottomRightCorner<3, 3>() = E_inv * R;
  return J;
}

Eigen::Matrix<double, 6, 6> ypr_to_right_tangent_covariance(const Pose3& pose,
                                                           const Eigen::Matrix<double, 6, 6>& cov) {
  return congruent<6>(right_tangent_from_ypr_jacobian(pose), cov);
}

Eigen::Matrix<double, 6, 6> right_tangent_to_ypr_covariance(const SE3d& T,
                                                           const Eigen::Matrix<double, 6, 6>& cov) {
  return congruent<6>(ypr_from_right_tangent_jacobian(T), cov);
}

Eigen::Matrix3d xyphi_to_right_tangent_covariance(const Pose2& pose, const Eigen::Matrix3d& cov) {
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  J.topLeftCorner<2, 2>() = pose.rotation().transpose();
  return congruent<3>(J, cov);
}

Eigen::Matrix3d right_tangent_to_xyphi_covariance(const SE2d& T, const Eigen::Matrix3d& cov) {
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  J.topLeftCorner<2, 2>() = T.rotation().matrix();
  return congruent<3>(J, cov);
}

Pose3Gaussian to_pose3_gaussian(const SE3d& T, const Eigen::Matrix<double, 6, 6>& cov) {
  return Pose3Gaussian(to_pose3(T), right_tangent_to_ypr_covariance(T, cov));
}

Pose2Gaussian to_pose2_gaussian(const SE2d& T, const Eigen::Matrix3d& cov) {
  return Pose2Gaussian(to_pose2(T), right_tangent_to_xyphi_covariance(T, cov));
}

}  // namespace rove
