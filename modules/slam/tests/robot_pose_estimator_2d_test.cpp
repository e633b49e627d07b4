#include "rove/slam/robot_pose_estimator_2d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace rove {
namespace {

Timestamp at(double s) { return Timestamp::from_seconds(1.0e9 + s); }

void expect_pose(const Pose2& a, const Pose2& b, double tol = 1e-12) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
  EXPECT_NEAR((a - b).phi(), 0.0, tol);
}

TEST(RobotPoseEstimator2D, NothingBeforeData) {
  RobotPoseEstimator2D e;
  EXPECT_FALSE(e.latest_pose());
  EXPECT_FALSE(e.estimate_at(at(0)));
}

TEST(RobotPoseEstimator2D, OdometryAloneIsThePose) {
  RobotPoseEstimator2D e;
  e.update_odometry(Pose2(1, 2, 0.3), at(0));
  expect_pose(*e.latest_pose(), Pose2(1, 2, 0.3));
  // No localization yet: no extrapolated estimate (MRPT).
  EXPECT_FALSE(e.estimate_at(at(0.1)));
}

TEST(RobotPoseEstimator2D, OdometryAfterLocalizationIsComposed) {
  RobotPoseEstimator2D e;
  e.update_odometry(Pose2(1, 0, 0), at(0));
  e.update_localization(Pose2(5, 5, std::numbers::pi / 2), at(0.5));
  expect_pose(*e.latest_pose(), Pose2(5, 5, std::numbers::pi / 2));
  e.update_odometry(Pose2(2, 0, 0), at(1.0));
  // One meter forward in the odometry frame is one meter along +y here.
  expect_pose(*e.latest_pose(), Pose2(5, 6, std::numbers::pi / 2));
  expect_pose(*e.estimate_at(at(1.2)), Pose2(5, 6, std::numbers::pi / 2));
  // Old data: no estimate.
  EXPECT_FALSE(e.estimate_at(at(10.0)));
  // Odometry not newer than the localization is not applied.
  e.update_localization(Pose2(0, 0, 0), at(2.0));
  e.update_odometry(Pose2(3, 0, 0), at(2.0));
  expect_pose(*e.latest_pose(), Pose2(0, 0, 0));
}

TEST(RobotPoseEstimator2D, ExtrapolationArcMatchesIntegration) {
  const Twist2 v{0.5, 0.0, 0.4};
  const Pose2 start(1, -1, 0.2);
  const Pose2 arc = RobotPoseEstimator2D::extrapolate(start, v, 2.0);
  Pose2 p = start;
  const int n = 20000;
  for (int i = 0; i < n; ++i) p = p + Pose2(v.vx * 2.0 / n, 0.0, v.omega * 2.0 / n);
  expect_pose(arc, p, 1e-4);
  // Straight motion: no division by a zero turn rate.
  expect_pose(RobotPoseEstimator2D::extrapolate(start, Twist2{1.0, 0.0, 0.0}, 1.0),
              start + Pose2(1.0, 0.0, 0.0));
}

}  // namespace
}  // namespace rove
