#pragma once
// Synthetic 3D scenes with known geometry for the registration tests.

#include <algorithm>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rove::test {

/// Points on the rectangle origin + u·a + v·b, u, v in [0, 1], every `step`.
inline void add_patch(std::vector<Eigen::Vector3f>& pts, Eigen::Vector3d origin, Eigen::Vector3d a,
                      Eigen::Vector3d b, double step) {
  const int nu = static_cast<int>(a.norm() / step), nv = static_cast<int>(b.norm() / step);
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j <= nv; ++j)
      pts.push_back((origin + a * (double(i) / nu) + b * (double(j) / nv)).cast<float>());
}

/// A 8 × 6 × 3 m room with a table-like box and a pillar: every DoF is
/// constrained.
inline std::vector<Eigen::Vector3f> room_3d(double step) {
  std::vector<Eigen::Vector3f> p;
  const Eigen::Vector3d X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  add_patch(p, {-4, -3, 0}, 8 * X, 6 * Y, step);  // floor
  add_patch(p, {-4, -3, 3}, 8 * X, 6 * Y, step);  // ceiling
  add_patch(p, {-4, -3, 0}, 8 * X, 3 * Z, step);  // walls
  add_patch(p, {-4, 3, 0}, 8 * X, 3 * Z, step);
  add_patch(p, {-4, -3, 0}, 6 * Y, 3 * Z, step);
  add_patch(p, {4, -3, 0}, 6 * Y, 3 * Z, step);
  add_patch(p, {0.5, -1, 0.8}, 1.5 * X, 1.0 * Y, step);  // box top
  add_patch(p, {0.5, -1, 0}, 1.5 * X, 0.8 * Z, step);    // box sides
  add_patch(p, {0.5, 0, 0}, 1.5 * X, 0.8 * Z, step);
  add_patch(p, {0.5, -1, 0}, 1.0 * Y, 0.8 * Z, step);
  add_patch(p, {2, -1, 0}, 1.0 * Y, 0.8 * Z, step);
  add_patch(p, {-2, 1.5, 0}, 0.4 * X, 3 * Z, step);  // pillar
  add_patch(p, {-2, 1.5, 0}, 0.4 * Y, 3 * Z, step);
  return p;
}

/// One 10 × 10 m horizontal plane.
inline std::vector<Eigen::Vector3f> plane_3d(double step) {
  std::vector<Eigen::Vector3f> p;
  add_patch(p, {-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, step);
  return p;
}

/// T⁻¹·p for every point (the scene seen from pose T), with Gaussian noise.
inline std::vector<Eigen::Vector3f> as_seen_from(const std::vector<Eigen::Vector3f>& pts,
                                                 const Eigen::Isometry3d& T, double noise,
                                                 unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, noise);
  const Eigen::Isometry3d inv = T.inverse();
  std::vector<Eigen::Vector3f> out;
  for (const auto& p : pts) {
    Eigen::Vector3d q = inv * p.cast<double>();
    if (noise > 0) q += Eigen::Vector3d(n(rng), n(rng), n(rng));
    out.push_back(q.cast<float>());
  }
  return out;
}

inline Eigen::Isometry3d make_pose(double x, double y, double z, double roll, double pitch,
                                   double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

/// Translation error (m) and rotation error (rad) between two transforms.
inline std::pair<double, double> pose_error(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  const Eigen::Matrix4d d = a.inverse() * b;
  const double c = std::clamp((d.topLeftCorner<3, 3>().trace() - 1) / 2, -1.0, 1.0);
  return {d.topRightCorner<3, 1>().norm(), std::acos(c)};
}

}  // namespace rove::test
