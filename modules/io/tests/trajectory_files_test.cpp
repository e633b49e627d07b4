#include "rove/io/trajectory_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "rove/core/error.h"

namespace rove {
namespace {

TEST(KittiTrajectory, ReadsPosesWithTheLineIndexAsTime) {
  // The first two poses of a KITTI ground-truth file (6 digits), the second
  // rotated 90 degrees about the camera's y axis.
  const std::string text =
      "1.000000e+00 9.043680e-12 2.326809e-11 5.551115e-17 9.043683e-12 1.000000e+00 "
      "2.392370e-10 3.330669e-16 2.326810e-11 2.392370e-10 9.999999e-01 -4.440892e-16\n"
      "\n"
      "0 0 1 1.5  0 1 0 -0.25  -1 0 0 3\n";
  const auto poses = parse_kitti_trajectory(text, "seq00.txt");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].time, 0.0);
  EXPECT_EQ(poses[1].time, 1.0);
  EXPECT_NEAR((poses[0].pose.rotation_matrix() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-6);
  EXPECT_TRUE(poses[1].pose.translation().isApprox(Eigen::Vector3d(1.5, -0.25, 3)));
  EXPECT_NEAR((poses[1].pose * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(1.5, -0.25, 2)).norm(),
              0.0, 1e-12);
}

TEST(KittiTrajectory, BadRowsNameTheLineAndField) {
  try {
    parse_kitti_trajectory("1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n", "a.txt");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().line, 2u);
    EXPECT_NE(e.problem().find("11 fields, expected 12"), std::string::npos) << e.problem();
  }
  try {
    parse_kitti_trajectory("1 0 0 0 0 1 0 0 0 0 1 nan\n", "a.txt");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "tz");
  }
  // A scaled block is not a rotation.
  EXPECT_THROW(parse_kitti_trajectory("2 0 0 0 0 2 0 0 0 0 2 0\n"), ParseError);
  // A reflection is not a rotation either.
  EXPECT_THROW(parse_kitti_trajectory("-1 0 0 0 0 1 0 0 0 0 1 0\n"), ParseError);
}

TEST(Relations, ReadsTimesAndRelativePoses) {
  const auto r = parse_relations(
      "# t1 t2 x y z roll pitch yaw\n90.239599 90.719599 0.422330 -0.000750 0 0 0 0.5\n");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].t1, 90.239599);
  EXPECT_EQ(r[0].t2, 90.719599);
  EXPECT_TRUE(r[0].T_1_2.translation().isApprox(Eigen::Vector3d(0.42233, -0.00075, 0)));
  const Eigen::Vector3d x = r[0].T_1_2.rotation_matrix() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(x.y(), x.x()), 0.5, 1e-12);
  // Roll about x comes after yaw: R = Rz·Ry·Rx.
  const auto rr = parse_relations("0 1 0 0 0 0.3 0 0\n");
  EXPECT_NEAR((rr[0].T_1_2.rotation_matrix() * Eigen::Vector3d::UnitY()).z(), std::sin(0.3),
              1e-12);
  EXPECT_THROW(parse_relations("0 1 0 0 0 0 0\n", "r.txt"), ParseError);
  EXPECT_TRUE(parse_relations("").empty());
}

TEST(TrajectoryFormats, FieldCountOfTheFirstRow) {
  EXPECT_EQ(first_row_fields("# c\n\n 1 2 3 4 5 6 7 8\n1 2\n").size(), 8u);
  EXPECT_EQ(first_row_fields("1 0 0 0 0 1 0 0 0 0 1 0").size(), 12u);
  EXPECT_EQ(first_row_fields("VERTEX3 0 0 0 0 0 0 0\n")[0], "VERTEX3");
  EXPECT_TRUE(first_row_fields("# only a comment\n").empty());
}

}  // namespace
}  // namespace rove
