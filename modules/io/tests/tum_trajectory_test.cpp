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

TEST(TumTrajectory, UnwritablePathIsAnIoError) {
  EXPECT_THROW(write_tum_trajectory("/nonexistent-dir/path.tum", {}), IoError);
}

}  // namespace
}  // namespace rove
