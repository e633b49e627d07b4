#include "rove/maps/height_map.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {
namespace {

TEST(HeightMap, GeometryAndRunningStatistics) {
  HeightMapCreationOptions c;
  c.min_x = -1;
  c.max_x = 1;
  c.min_y = 0;
  c.max_y = 0.5;
  c.resolution = 0.1;
  HeightMap map(c);
  EXPECT_EQ(map.size_x(), 20u);
  EXPECT_EQ(map.size_y(), 5u);
  EXPECT_TRUE(map.empty());
  EXPECT_FALSE(map.insert_point({1.0, 0.2, 0.0}));   // x == max: outside
  EXPECT_FALSE(map.insert_point({0.0, -0.01, 0.0}));  // below min_y
  const double zs[] = {1000.1, 1000.2, 1000.6};       // far from 0: no cancellation
  for (double z : zs) EXPECT_TRUE(map.insert_point({0.05, 0.05, z}));
  const HeightCell* cell = map.cell_at(0.01, 0.01);
  ASSERT_NE(cell, nullptr);
  EXPECT_EQ(cell, &map.cell(10, 0));
  EXPECT_EQ(cell->count, 3u);
  EXPECT_NEAR(cell->mean_z, 1000.3, 1e-3);
  EXPECT_NEAR(cell->variance_z, 0.07, 1e-6);
  EXPECT_FALSE(map.empty());
  const auto st = map.statistics();
  EXPECT_EQ(st.elements, 1u);
  EXPECT_EQ(st.total_cells, 100u);
  map.clear();
  EXPECT_TRUE(map.empty());
  EXPECT_EQ(map.cell(10, 0).count, 0u);
}

TEST(HeightMap, FilterByHeight) {
  HeightMapInsertOptions io;
  io.filter_by_height = true;
  io.z_min = 0.0;
  io.z_max = 1.0;
  HeightMap map({}, io);
  EXPECT_TRUE(map.insert_point({0.0, 0.0, 2.0}));  // inside the grid, filtered
  EXPECT_TRUE(map.empty());
  EXPECT_TRUE(map.insert_point({0.0, 0.0, 0.5}));
  EXPECT_FALSE(map.empty());
}

/// A 2D scan of a wall seen by a scanner mounted at height h.
RangeScan2D wall_scan(double h) {
  RangeScan2D s;
  s.aperture = kPi / 2;
  std::vector<float> r(91);
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double a = -kPi / 4 + static_cast<double>(i) * (kPi / 2) / 90.0;
    r[i] = static_cast<float>(1.55 / std::cos(a));
  }
  s.set_ranges(r);
  s.T_robot_sensor = Pose3(0, 0, h, 0, 0, 0);
  return s;
}

TEST(HeightMap, ScanPointsAtSensorHeightAndLikelihood) {
  HeightMap map;  // MRPT's default: [-2, 2]², 10 cm
  const RangeScan2D scan = wall_scan(0.3);
  ASSERT_TRUE(map.insert(scan, Pose3(0, 0, 0.2, 0, 0, 0)));
  const auto st = map.statistics();
  EXPECT_GT(st.elements, 10u);
  const auto box = map.bounding_box();
  EXPECT_NEAR(box.min.z(), 0.5, 1e-6);
  EXPECT_NEAR(box.max.z(), 0.5, 1e-6);
  EXPECT_NEAR(box.min.x(), 1.5, 1e-9);
  // The same scan fits best where it was taken.
  const double at = map.log_likelihood(scan, Pose3(0, 0, 0.2, 0, 0, 0));
  EXPECT_NEAR(at, 0.0, 1e-9);
  EXPECT_LT(map.log_likelihood(scan, Pose3(0, 0, 0.3, 0, 0, 0)), at - 1.0);
  BeaconRanges other;
  EXPECT_FALSE(map.insert(other, Pose3()));
  EXPECT_EQ(map.log_likelihood(other, Pose3()), 0.0);
}

TEST(HeightMapOptions, LoadAndReject) {
  const auto ini = IniFile::parse(
      "[c]\nmin_x=-5\nmax_x=5\nmin_y=-5\nmax_y=5\nresolution=0.25\nmapType=mrSimpleAverage\n"
      "[i]\nfilterByHeight=true\nz_min=0.1\nz_max=2\ncolorMap=jet\n"
      "[bad]\nmapType=mrSomethingElse\n[bad2]\nresolution=0\n",
      "h.ini");
  std::vector<IgnoredConfigKey> ignored;
  ConfigSection cs(ini, "c", &ignored), is(ini, "i", &ignored);
  HeightMap map(HeightMapCreationOptions::from_config(cs), HeightMapInsertOptions::from_config(is));
  cs.check_all_read();
  is.check_all_read();
  EXPECT_EQ(map.size_x(), 40u);
  EXPECT_TRUE(map.insert_options.filter_by_height);
  ASSERT_EQ(ignored.size(), 1u);
  EXPECT_EQ(ignored[0].key, "colorMap");
  EXPECT_THROW((void)HeightMapCreationOptions::from_config(ConfigSection(ini, "bad")), ConfigError);
  EXPECT_THROW((void)HeightMapCreationOptions::from_config(ConfigSection(ini, "bad2")), ConfigError);
}

}  // namespace
}  // namespace rove
