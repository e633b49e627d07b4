#include "rove/io/metric_map_files.h"

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/io/gray_image.h"
#include "rove/io/octree_files.h"
#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/maps/beacon_map.h"
#include "rove/maps/height_map.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_octree.h"
#include "rove/maps/metric_map_points.h"
#include "rove/maps/multi_metric_map.h"

namespace rove {
namespace {

class MetricMapFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rove_metric_map_files_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string prefix(const std::string& name) const { return (dir_ / name).string(); }
  static std::string text_of(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }

 private:
  std::filesystem::path dir_;
};

TEST_F(MetricMapFiles, HeightMapWritesMrptMatrixLayout) {
  HeightMapCreationOptions c;
  c.min_x = 0;
  c.max_x = 0.3;
  c.min_y = 0;
  c.max_y = 0.2;
  c.resolution = 0.1;
  HeightMap map(c);
  map.insert_point({0.25, 0.15, 2.0});
  const auto files = save_metric_map(prefix("h"), map);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0], prefix("h") + "_mean.txt");
  EXPECT_EQ(text_of(files[0]), "0 0 0\n0 0 2\n");
  EXPECT_EQ(text_of(files[1]), "0 0 0\n0 0 1\n");
}

TEST_F(MetricMapFiles, GridImageHasTheTopRowFirstAndFreeWhite) {
  OccupancyGridCreationOptions c;
  c.min_x = 0;
  c.max_x = 0.4f;
  c.min_y = 0;
  c.max_y = 0.2f;
  c.resolution = 0.1f;
  OccupancyGridMetricMap map(c);
  map.grid().set_free_probability(3, 1, 0.0f);  // occupied, top row, right
  map.grid().set_free_probability(0, 0, 1.0f);  // free, bottom row, left
  const auto files = save_metric_map(prefix("g"), map);
  ASSERT_EQ(files.size(), 2u);
  const GrayImage img = read_gray_image(files[0]);
  ASSERT_EQ(img.width, 4u);
  ASSERT_EQ(img.height, 2u);
  EXPECT_EQ(img.at(3, 0), 0);
  EXPECT_EQ(img.at(0, 1), 255);
  EXPECT_EQ(img.at(1, 1), 128);  // round(255 · 0.5)
  EXPECT_EQ(text_of(files[1]),
            "% Grid limits: [x_min x_max y_min y_max]\n0.000000 0.400000 0.000000 0.200000\n");
}

TEST_F(MetricMapFiles, PointMapReadsBackFromPlyAndPcd) {
  PointsMetricMap map;
  map.points().insert_point({1.0f, 2.0f, 3.0f});
  map.points().insert_point({-4.5f, 0.25f, 8.0f});
  const auto files = save_metric_map(prefix("p"), map);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(read_ply(files[0]), map.points().cloud());
  EXPECT_EQ(read_pcd(files[1]), map.points().cloud());
}

TEST_F(MetricMapFiles, MultiMapNumbersEachMapAndNamesItsKind) {
  MultiMetricMap multi;
  auto beacons = std::make_unique<BeaconMap>();
  Beacon b;
  b.id = 7;
  b.gaussian.mean = {1.0, 2.0, 0.5};
  b.gaussian.covariance = Eigen::Vector3d(0.25, 1.0, 4.0).asDiagonal();
  beacons->add(b);
  multi.add(std::move(beacons));
  multi.add(std::make_unique<PointsMetricMap>());
  const auto files = save_metric_map(prefix("m"), multi);
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[0], prefix("m") + "_00_beaconMap_beacons.txt");
  EXPECT_EQ(files[1], prefix("m") + "_01_pointsMap.ply");
  EXPECT_EQ(files[2], prefix("m") + "_01_pointsMap.pcd");
  std::istringstream beacon_rows(text_of(files[0]));
  std::string header, row;
  std::getline(beacon_rows, header);
  std::getline(beacon_rows, row);
  EXPECT_EQ(row,
            "7 1.000000 2.000000 0.500000 2.500000e-01 1.000000e+00 4.000000e+00 2.500000e-01 "
            "1.000000e+00 0.000000e+00 0.000000e+00 0.000000e+00 gaussian");
}

TEST_F(MetricMapFiles, OctreeMapsWriteOctoMapFilesAndTheirOccupiedCells) {
  for (const bool colour : {false, true}) {
    OctreeMetricMap map(0.1, {}, {}, colour);
    const std::vector<Eigen::Vector3f> wall = {{2.0f, 0.0f, 0.0f}, {2.0f, 0.5f, 0.0f}, {2.0f, -0.5f, 0.2f}};
    map.tree().insert_point_cloud(wall, Eigen::Vector3d(0.05, 0.05, 0.05));
    const auto files = save_metric_map(prefix(colour ? "c" : "o"), map);
    ASSERT_EQ(files.size(), colour ? 3u : 2u);
    EXPECT_EQ(files[0], prefix(colour ? "c" : "o") + ".bt");
    EXPECT_EQ(read_octree(files[0]).num_nodes(), map.tree().num_nodes());
    if (colour) {
      EXPECT_EQ(read_octree(files[1]).channels(), OctreeChannels::Color);
    }
    const PointCloud occupied = read_ply(files.back());
    EXPECT_EQ(occupied.size(), 3u);
    EXPECT_NEAR(occupied.points()[0].x(), 2.05f, 1e-6f);
  }
}

TEST_F(MetricMapFiles, UnwritableFolderIsAnIoError) {
  PointsMetricMap map;
  EXPECT_THROW((void)save_metric_map("/nonexistent-dir/p", map), IoError);
}

}  // namespace
}  // namespace rove
