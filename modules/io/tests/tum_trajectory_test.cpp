#include "rove/io/tum_trajectory.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

std::string text_of(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(TumTrajectory, WritesTimeTranslationAndTheYawQuaternion) {
  const auto file = (std::filesystem::temp_directory_path() / "rove_tum_trajectory.tum").string();
  const std::vector<TimedPose2> poses = {
      {Timestamp::from_ns(1'700'000'000'250'000'000), Pose2(1.5, -2.0, std::numbers::pi / 2)},
      {Timestamp::invalid(), Pose2(0.0, 0.0, 0.0)},  // no time: its index
  };
  write_tum_trajectory(file, poses);
  const std::string text = text_of(file);
  std::filesystem::remove(file);
  // A rotation by 90° about z: (qx, qy, qz, qw) = (0, 0, sin 45°, cos 45°).
  EXPECT_EQ(text,
            "# t x y z qx qy qz qw\n"
            "1700000000.250000 1.500000 -2.000000 0 0 0 0.707106781 0.707106781\n"
            "1.000000 0.000000 0.000000 0 0 0 0.000000000 1.000000000\n");
}

// 3D poses round-trip through the reader (the quaternion made qw >= 0).
TEST(TumTrajectory, WritesAndReadsThreeDimensionalPoses) {
  const auto file = (std::filesystem::temp_directory_path() / "rove_tum_trajectory_3d.tum").string();
  SE3d::Tangent xi;
  xi << 1.0, -2.0, 0.5, 0.4, -0.3, 2.9;
  const std::vector<TimedPose3> poses = {{Timestamp::from_ns(2'000'000'000), SE3d::exp(xi)},
                                         {Timestamp::invalid(), SE3d()}};
  write_tum_trajectory(file, poses);
  const std::vector<StampedPose3> back = read_tum_trajectory(file);
  std::filesystem::remove(file);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_DOUBLE_EQ(back[0].time, 2.0);
  EXPECT_DOUBLE_EQ(back[1].time, 1.0);
  EXPECT_TRUE(back[0].pose.is_approx(poses[0].pose, 1e-6));
  EXPECT_TRUE(back[1].pose.is_approx(SE3d(), 1e-9));
}

TEST(TumTrajectory, ReadsPosesAndRejectsBadLines) {
  const std::string file = ::testing::TempDir() + "/rove_tum_read.txt";
  std::ofstream(file) << "# t x y z qx qy qz qw\n\n1.5 1 2 3 0 0 0.7071067811865476 0.7071067811865476\n"
                         "  2.0 -1 0 0.5 0 0 0 2\n";
  const auto poses = read_tum_trajectory(file);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].time, 1.5);
  EXPECT_TRUE(poses[0].pose.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_NEAR((poses[0].pose.rotation() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0, 1e-12);
  EXPECT_TRUE(poses[1].pose.rotation().matrix().isApprox(Eigen::Matrix3d::Identity()));  // normalized
  for (const char* bad : {"1 2 3\n", "1 2 3 4 5 6 7 8 9\n", "1 2 3 4 0 0 0 0\n", "1 2 x 4 0 0 0 1\n", "1 2 nan 4 0 0 0 1\n"}) {
    std::ofstream(file) << "# header\n" << bad;
    try {
      (void)read_tum_trajectory(file);
      ADD_FAILURE() << bad;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().line, 2u) << e.what();
    }
  }
  std::filesystem::remove(file);
  EXPECT_THROW((void)read_tum_trajectory(file), IoError);
}

TEST(TumTrajectory, UnwritablePathIsAnIoError) {
  EXPECT_THROW(write_tum_trajectory("/nonexistent-dir/path.tum", std::vector<TimedPose2>{}), IoError);
}

}  // namespace
}  // namespace rove
