#include "rove/io/mrpt_simplemap_writer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <numbers>

#include "rove/io/mrpt_simplemap.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {
namespace {

TEST(MrptSimplemapWriter, RoundTripsThroughTheMrptReader) {
  RangeScan2D scan;
  scan.sensor_label = "LASER_FRONT";
  scan.timestamp = Timestamp::from_seconds(1137846151.25);
  scan.T_robot_sensor = Pose3(0.2, 0.0, 0.3, 0.0, 0.0, 0.0);
  scan.aperture = std::numbers::pi;
  for (int i = 0; i < 361; ++i) {
    scan.ranges.push_back(1.0f + 0.01f * static_cast<float>(i));
    scan.valid.push_back(i % 10 != 3);
  }
  Eigen::Matrix3d cov;
  cov << 0.01, 0.002, 0.0, 0.002, 0.02, 0.001, 0.0, 0.001, 0.003;
  const std::vector<SimpleMapEntry2D> entries = {
      {Pose2(), Eigen::Matrix3d::Zero(), &scan},
      {Pose2(1.5, -2.0, 0.7), cov, &scan},
  };
  const auto path = (std::filesystem::temp_directory_path() / "rove_slam_test.simplemap").string();
  const SimpleMapWriteReport rep = write_mrpt_simplemap(path, entries);
  EXPECT_EQ(rep.keyframes, 2u);
  EXPECT_EQ(rep.skipped, 0u);

  const SimpleMap map = load_mrpt_simplemap(path);
  ASSERT_EQ(map.keyframes.size(), 2u);
  const Pose3 p = map.keyframes[1].pose.mean();
  EXPECT_NEAR(p.x(), 1.5, 1e-12);
  EXPECT_NEAR(p.y(), -2.0, 1e-12);
  EXPECT_NEAR(p.yaw(), 0.7, 1e-12);
  const auto c = map.keyframes[1].pose.covariance();
  EXPECT_DOUBLE_EQ(c(0, 1), 0.002);
  EXPECT_DOUBLE_EQ(c(1, 3), 0.001);
  EXPECT_DOUBLE_EQ(c(3, 3), 0.003);
  EXPECT_DOUBLE_EQ(c(2, 2), 0.0);
  const auto read = map.keyframes[1].frame->find<RangeScan2D>();
  ASSERT_NE(read, nullptr);
  EXPECT_EQ(read->sensor_label, scan.sensor_label);
  EXPECT_EQ(read->ranges, scan.ranges);
  EXPECT_EQ(read->valid, scan.valid);
  EXPECT_EQ(read->timestamp.to_mrpt(), scan.timestamp.to_mrpt());
  EXPECT_NEAR(read->T_robot_sensor.z(), 0.3, 1e-12);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace rove
