#pragma once
// Shared helpers of the point/pose tests: random samples and tolerance
// comparisons that report the values on failure.

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "rove/poses/compose.h"

namespace rove::test {

inline constexpr double kDeg = kPi / 180.0;

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline Point2 random_point2(std::mt19937_64& rng) {
  return Point2(uniform(rng, -10, 10), uniform(rng, -10, 10));
}
inline Point3 random_point3(std::mt19937_64& rng) {
  return Point3(uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10));
}
inline Pose2 random_pose2(std::mt19937_64& rng) {
  return Pose2(uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -kPi, kPi));
}
inline Pose3 random_pose3(std::mt19937_64& rng) {
  return Pose3(uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10),
               uniform(rng, -kPi, kPi), uniform(rng, -kPi / 2, kPi / 2), uniform(rng, -kPi, kPi));
}
inline Pose3Quat random_pose3_quat(std::mt19937_64& rng) {
  return Pose3Quat(uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10),
                   uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1),
                   uniform(rng, -1, 1));
}

/// Angular difference wrapped to (-pi, pi].
inline double angle_diff(double a, double b) { return wrap_to_pi(a - b); }

inline ::testing::AssertionResult near(const Point2& a, const Point2& b, double tol) {
  if (std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << to_string(a) << " vs " << to_string(b);
}
inline ::testing::AssertionResult near(const Point3& a, const Point3& b, double tol) {
  if ((a.to_vector() - b.to_vector()).cwiseAbs().maxCoeff() <= tol)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a.as_string() << " vs " << b.as_string();
}
inline ::testing::AssertionResult near(const Pose2& a, const Pose2& b, double tol) {
  if (std::abs(a.x() - b.x()) <= tol && std::abs(a.y() - b.y()) <= tol &&
      std::abs(angle_diff(a.phi(), b.phi())) <= tol)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a.as_string() << " vs " << b.as_string();
}
inline ::testing::AssertionResult near(const Pose3& a, const Pose3& b, double tol) {
  const double dt = (a.translation() - b.translation()).cwiseAbs().maxCoeff();
  const double dr = (a.rotation() - b.rotation()).cwiseAbs().maxCoeff();
  if (dt <= tol && dr <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a.as_string() << " vs " << b.as_string()
                                       << " (|dt| = " << dt << ", |dR| = " << dr << ")";
}
/// Same rigid transform (q and -q are the same rotation).
inline ::testing::AssertionResult near(const Pose3Quat& a, const Pose3Quat& b, double tol) {
  const double dt = (a.translation() - b.translation()).cwiseAbs().maxCoeff();
  const double dq = std::min((a.quaternion().coeffs() - b.quaternion().coeffs()).cwiseAbs().maxCoeff(),
                             (a.quaternion().coeffs() + b.quaternion().coeffs()).cwiseAbs().maxCoeff());
  if (dt <= tol && dq <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a.as_string() << " vs " << b.as_string();
}

/// The reference: a pose as a 4x4 homogeneous matrix built from scratch with
/// Eigen's angle-axis rotations (independent of rove's formulas).
inline Eigen::Matrix4d reference_matrix(double x, double y, double z, double yaw, double pitch,
                                        double roll) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  T.topRightCorner<3, 1>() = Eigen::Vector3d(x, y, z);
  return T;
}

}  // namespace rove::test
