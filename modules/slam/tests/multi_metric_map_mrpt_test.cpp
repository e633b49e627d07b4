// A multi-metric map built from localization_demo.simplemap.gz with MRPT's
// own configuration files against MRPT 2.5.8's result for the same input
// (tools/mrpt_multimap_reference, which runs what observations2map runs).
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "rove/core/ini.h"
#include "rove/io/mrpt_simplemap.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_points.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/slam/metric_map_builder.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kSimplemap =
    test_data::bundled_file("mrpt/localization_demo.simplemap.gz");
const std::string kRef = ROVE_SOURCE_DIR "/modules/slam/tests/data/";
const std::string kConfigs = "/usr/share/mrpt/config_files/";

MultiMetricMap build(const std::string& config, const std::string& section) {
  EXPECT_TRUE(std::filesystem::exists(kSimplemap)) << "dataset missing: " << kSimplemap;
  const IniFile ini = IniFile::load(kConfigs + config, IniOptions{.strict = false});
  MultiMetricMap mm = MultiMetricMap::from_config(ini, section);
  const MapBuildResult r = build_map(kSimplemap, mm);
  EXPECT_EQ(r.input, MapInputKind::SimpleMap);
  EXPECT_GT(r.keyframes, 0u);
  return mm;
}

TEST(MultiMetricMapVsMrpt, PointCountEqualsMrpt) {
  MultiMetricMap mm = build("icp-slam/icp-slam_demo_classic.ini", "MappingApplication");
  ASSERT_EQ(mm.size(), 1u);
  std::ifstream f(kRef + "mrpt_multimap_localization_demo_points.txt");
  ASSERT_TRUE(f.good());
  std::string line, tag;
  std::size_t mrpt_points = 0;
  while (std::getline(f, line)) {
    std::istringstream in(line);
    if (in >> tag && tag == "points") in >> mrpt_points;
  }
  ASSERT_GT(mrpt_points, 0u);
  const auto& p = dynamic_cast<const PointsMetricMap&>(*mm.entries()[0].map);
  EXPECT_EQ(p.points().size(), mrpt_points);
}

TEST(MultiMetricMapVsMrpt, GridCellClassesAgreeWithMrpt) {
  MultiMetricMap mm = build("pf-localization/localization_demo.ini", "MetricMap");
  ASSERT_EQ(mm.size(), 1u);
  const auto& grid = dynamic_cast<const OccupancyGridMetricMap&>(*mm.entries()[0].map).grid();
  std::ifstream f(kRef + "mrpt_multimap_localization_demo_grid.txt");
  ASSERT_TRUE(f.good());
  std::string line;
  std::uint32_t sx = 0, sy = 0;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0, res = 0;
  while (std::getline(f, line)) {
    std::istringstream in(line);
    std::string tag;
    if (in >> tag && tag == "grid") {
      in >> sx >> sy >> x_min >> x_max >> y_min >> y_max >> res;
      break;
    }
  }
  ASSERT_GT(sx, 0u);
  EXPECT_EQ(grid.size_x(), sx);
  EXPECT_EQ(grid.size_y(), sy);
  EXPECT_NEAR(grid.x_min(), x_min, 1e-4);
  EXPECT_NEAR(grid.y_min(), y_min, 1e-4);
  EXPECT_NEAR(grid.resolution(), res, 1e-6);
  std::size_t same = 0, total = 0, mrpt_known = 0;
  for (std::uint32_t cy = 0; cy < sy && std::getline(f, line); ++cy) {
    ASSERT_EQ(line.size(), sx);
    for (std::uint32_t cx = 0; cx < sx; ++cx) {
      const float p = grid.free_probability(static_cast<int>(cx), static_cast<int>(cy));
      const char c = p < 0.4f ? '#' : (p > 0.6f ? '.' : '?');
      same += c == line[cx];
      mrpt_known += line[cx] != '?';
      ++total;
    }
  }
  ASSERT_EQ(total, static_cast<std::size_t>(sx) * sy);
  EXPECT_GT(mrpt_known, total / 20);  // the map is not trivially unknown
  EXPECT_GE(static_cast<double>(same) / static_cast<double>(total), 0.99)
      << same << " of " << total << " cells agree";
  // The grid's likelihood (MRPT's likelihood field, from the config) peaks
  // at the keyframe pose the scan was inserted from.
  const SimpleMap sm = load_mrpt_simplemap(kSimplemap);
  const auto& kf = sm.keyframes[sm.keyframes.size() / 2];
  const auto scan = kf.frame->find<RangeScan2D>();
  ASSERT_NE(scan, nullptr);
  const Pose3 T = kf.pose.mean();
  ASSERT_TRUE(mm.can_compute_likelihood(*scan));
  const double at = mm.log_likelihood(*scan, T);
  EXPECT_GT(at, mm.log_likelihood(*scan, Pose3(0.3, 0, 0, 0, 0, 0) + T));
  EXPECT_GT(at, mm.log_likelihood(*scan, T + Pose3(0, 0, 0, 0.1, 0, 0)));
}

}  // namespace
}  // namespace rove
