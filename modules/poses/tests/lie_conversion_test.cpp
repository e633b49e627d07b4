// Pose ↔ Lie group conversions and the covariance conversion between
// Pose3's (x, y, z, yaw, pitch, roll) and the right tangent (ρ, ω) of SE(3):
// the Jacobian against numeric differentiation, round trips, gimbal lock.

#include "rove/poses/lie_conversion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace rove {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

Pose3 pose_of(const Vector6& p) { return Pose3(p(0), p(1), p(2), p(3), p(4), p(5)); }

// Column i: log(T⁻¹·T(p + h·eᵢ)) by central differences.
Matrix6 numeric_right_from_ypr(const Vector6& p) {
  const double h = 1e-6;
  const SE3d T = to_se3(pose_of(p));
  Matrix6 J;
  for (int i = 0; i < 6; ++i) {
    const Vector6 e = Vector6::Unit(i) * h;
    const SE3d plus = to_se3(pose_of(p + e)), minus = to_se3(pose_of(p - e));
    J.col(i) = ((T.inverse() * plus).log() - (T.inverse() * minus).log()) / (2 * h);
  }
  return J;
}

TEST(LieConversion, RightTangentJacobianMatchesNumericDifferentiation) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> t(-5, 5), a(-3, 3), pitch(-1.4, 1.4);
  for (int k = 0; k < 50; ++k) {
    const Vector6 p(t(rng), t(rng), t(rng), a(rng), pitch(rng), a(rng));
    const Matrix6 J = right_tangent_from_ypr_jacobian(pose_of(p));
    EXPECT_LT((J - numeric_right_from_ypr(p)).cwiseAbs().maxCoeff(), 1e-7) << p.transpose();
    // And the inverse is its inverse.
    const Matrix6 Ji = ypr_from_right_tangent_jacobian(to_se3(pose_of(p)));
    EXPECT_LT((Ji * J - Matrix6::Identity()).cwiseAbs().maxCoeff(), 1e-9) << p.transpose();
  }
}

TEST(LieConversion, CovarianceRoundTripsAndKeepsTheDistribution) {
  const Pose3 pose(1, -2, 0.5, 0.7, -0.3, 2.1);
  Matrix6 A = Matrix6::Random();
  const Matrix6 C = A * A.transpose() * 0.01 + Matrix6::Identity() * 1e-4;
  const Matrix6 Cr = ypr_to_right_tangent_covariance(pose, C);
  EXPECT_LT((right_tangent_to_ypr_covariance(to_se3(pose), Cr) - C).cwiseAbs().maxCoeff(), 1e-12);
  // The translation block is the same uncertainty in the body frame.
  const Eigen::Matrix3d R = pose.rotation();
  EXPECT_LT((R * Cr.topLeftCorner<3, 3>() * R.transpose() - C.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff(),
            1e-12);
  const Pose3Gaussian g = to_pose3_gaussian(to_se3(pose), Cr);
  EXPECT_LT((g.covariance() - C).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(g.mean().distance_to(pose), 1e-12);

  const Pose2 p2(1, 2, 0.8);
  const Eigen::Matrix3d C2 = (Eigen::Matrix3d() << 0.04, 0.01, 0.002, 0.01, 0.09, -0.001, 0.002,
                              -0.001, 0.01).finished();
  const Eigen::Matrix3d C2r = xyphi_to_right_tangent_covariance(p2, C2);
  EXPECT_LT((right_tangent_to_xyphi_covariance(to_se2(p2), C2r) - C2).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(C2r(2, 2), C2(2, 2), 1e-15);
  EXPECT_NEAR((C2r.topLeftCorner<2, 2>().trace()), (C2.topLeftCorner<2, 2>().trace()), 1e-15);
  EXPECT_LT((to_pose2_gaussian(to_se2(p2), C2r).covariance() - C2).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(LieConversion, GimbalLockStaysFinite) {
  const SE3d T = to_se3(Pose3(0, 0, 0, 0.3, std::numbers::pi / 2, 0.1));
  const Matrix6 J = ypr_from_right_tangent_jacobian(T);
  EXPECT_TRUE(J.allFinite());
}

}  // namespace
}  // namespace rove
