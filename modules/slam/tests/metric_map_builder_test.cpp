#include "rove/slam/metric_map_builder.h"

#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/io/rawlog_reader.h"
#include "rove/maps/beacon_map.h"
#include "rove/maps/landmark_map.h"
#include "rove/maps/metric_map_points.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = test_data::bundled_file("mrpt/");

std::string dataset(const std::string& name) {
  const std::string p = kData + name;
  EXPECT_TRUE(std::filesystem::exists(p)) << "dataset missing: " << p;
  return p;
}

/// Rows of numbers of a text file, skipping '%' comments and blank lines.
std::vector<std::vector<double>> numeric_rows(const std::string& path) {
  std::ifstream f(path);
  EXPECT_TRUE(f.good()) << path;
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '%') continue;
    std::istringstream in(line);
    std::vector<double> row;
    double v = 0;
    while (in >> v) row.push_back(v);
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

// RO-SLAM demo: simulated range-only data (odometry noise 1 mm per step, so
// the integrated odometry is the ground-truth path within centimeters).
// Mapping the beacons with MRPT's own SOG configuration must put every
// beacon near RO-SLAM_demo_ground_truth.txt.
void expect_ro_slam_beacons(const std::string& config) {
  const IniFile ini = IniFile::load("/usr/share/mrpt/config_files/rbpf-slam/" + config,
                                    IniOptions{.strict = false});
  MultiMetricMap mm = MultiMetricMap::from_config(ini, "MappingApplication");
  ASSERT_EQ(mm.size(), 1u);
  const MapBuildResult r = build_map(dataset("RO-SLAM_demo.rawlog"), mm);
  EXPECT_EQ(r.input, MapInputKind::Rawlog);
  EXPECT_EQ(r.keyframes, 100u);
  EXPECT_EQ(r.odometry_steps, 100u);
  EXPECT_EQ(mm.entries()[0].observations_inserted, 100u);
  const auto& beacons = dynamic_cast<const BeaconMap&>(*mm.entries()[0].map);
  const auto truth = numeric_rows(dataset("RO-SLAM_demo_ground_truth.txt"));
  ASSERT_EQ(truth.size(), 15u);
  std::size_t seen = 0, gaussian = 0;
  double worst = 0;
  for (const auto& row : truth) {
    const Beacon* b = beacons.find(static_cast<std::int32_t>(row[0]));
    if (b == nullptr) continue;  // never ranged in this log
    ++seen;
    if (b->kind == BeaconPdfKind::Gaussian) ++gaussian;
    const PointGaussian3 g = b->moments();
    const double err = std::hypot(g.mean.x() - row[1], g.mean.y() - row[2]);
    worst = std::max(worst, err);
    EXPECT_LT(err, 0.15) << "beacon " << row[0] << " at " << g.mean.transpose();
  }
  EXPECT_EQ(seen, beacons.beacons().size());
  EXPECT_GE(seen, 10u);
  EXPECT_EQ(gaussian, seen) << "every beacon should have collapsed to one Gaussian";
  ::testing::Test::RecordProperty("worst_beacon_error_m", std::to_string(worst));
}

TEST(MapBuild, RoSlamBeaconsSogNearGroundTruth) { expect_ro_slam_beacons("RO-SLAM_simulatedData_SOG.ini"); }
TEST(MapBuild, RoSlamBeaconsMonteCarloNearGroundTruth) {
  expect_ro_slam_beacons("RO-SLAM_simulatedData_MC.ini");
}

// kf-slam demo: bearing-range landmarks inserted at the ground-truth robot
// path must land on the ground-truth landmarks.
TEST(MapBuild, KfSlamLandmarksAtGroundTruthPath) {
  const auto path = numeric_rows(dataset("kf-slam_demo_ground_truth_robot_path.txt"));
  const auto truth = numeric_rows(dataset("kf-slam_demo_ground_truth.txt"));
  const Rawlog log = load_rawlog(dataset("kf-slam_demo.rawlog"));
  LandmarkMap map;
  std::size_t frame = 0;
  for (const auto& e : log.entries) {
    const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&e);
    if (sf == nullptr) continue;
    ASSERT_LT(frame, path.size());
    const auto& p = path[frame++];
    map.insert(**sf, Pose3(p[0], p[1], p[2], p[3], p[4], p[5]));
  }
  EXPECT_EQ(frame, path.size());
  ASSERT_FALSE(map.empty());
  std::size_t matched = 0;
  for (const auto& l : map.landmarks()) {
    // Nearest ground-truth landmark.
    double best = 1e9;
    for (const auto& t : truth) {
      best = std::min(best, (l.position.mean - Eigen::Vector3d(t[0], t[1], t[2])).norm());
    }
    EXPECT_LT(best, 0.25) << "landmark " << l.id << " at " << l.position.mean.transpose();
    if (best < 0.25) ++matched;
  }
  EXPECT_EQ(matched, map.landmarks().size());
  EXPECT_GE(map.landmarks().size(), 10u);
}

// A CARMEN log is read as a layout #1 rawlog: the first scan at the origin,
// each later one at the odometry increment composed on (laser lines carry
// the odometry); three rays at −90°, 0°, +90°.
TEST(MapBuild, CarmenLogPointsAtOdometryPoses) {
  const auto dir = std::filesystem::temp_directory_path() / "rove_map_build_carmen";
  std::filesystem::create_directories(dir);
  const std::string log = (dir / "two_scans.clf").string();
  {
    std::ofstream f(log);
    f << "# two scans\n"
         "FLASER 3 1 2 3 5 5 0 5 5 0 0.0 host 0.0\n"
         "FLASER 3 1 1 1 6 5 1.5707963267948966 6 5 1.5707963267948966 0.5 host 0.5\n";
  }
  const IniFile ini = IniFile::parse(
      "[Map]\npointsMap_count = 1\n"
      "[Map_pointsMap_00_insertOpts]\nminDistBetweenLaserPoints = 0\nisPlanarMap = 1\n",
      "t.ini");
  MultiMetricMap mm = MultiMetricMap::from_config(ini, "Map");
  const MapBuildResult r = build_map(log, mm);
  EXPECT_EQ(r.input, MapInputKind::Rawlog);
  EXPECT_EQ(r.keyframes, 2u);
  EXPECT_EQ(r.odometry_steps, 1u);
  const auto& cloud = dynamic_cast<const PointsMetricMap&>(*mm.entries()[0].map).points().cloud();
  const std::vector<Eigen::Vector2d> expected = {{0, -1}, {2, 0}, {0, 3},  // at the origin
                                                 {2, 0}, {1, 1}, {0, 0}};  // at (1, 0, 90°)
  ASSERT_EQ(cloud.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(cloud[i].x(), expected[i].x(), 1e-5) << "point " << i;
    EXPECT_NEAR(cloud[i].y(), expected[i].y(), 1e-5) << "point " << i;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rove

namespace rove {
namespace {

// Ctrl-C during `map build` stops at the next rawlog entry or keyframe
// (throw_if_interrupted), before any map is written.
TEST(MapBuild, CtrlCStopsTheBuildAtTheNextEntry) {
  install_interrupt_handler();
  for (const char* input : {"2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog",
                            "localization_demo.simplemap.gz"}) {
    const IniFile ini = IniFile::parse("[M]\npointsMap_count=1\n", "points.ini");
    MapBuildConfig cfg = load_map_build_config(ini);
    std::raise(SIGINT);
    ASSERT_TRUE(interrupted());
    EXPECT_THROW(build_map(dataset(input), cfg.maps), Interrupted) << input;
    reset_interrupted();
    EXPECT_TRUE(cfg.maps.empty()) << input;  // stopped before the first insertion
    // Without a signal the same build runs to its end.
    MapBuildConfig again = load_map_build_config(ini);
    EXPECT_GT(build_map(dataset(input), again.maps).observations_used, 0u) << input;
  }
}

TEST(MapBuild, ConfigWithoutMapsIsAnErrorNamingTheFile) {
  const IniFile none = IniFile::parse("[M]\npointsMap_count=0\n", "none.ini");
  EXPECT_THROW(load_map_build_config(none), ConfigError);
  const IniFile no_section = IniFile::parse("[M]\nx=1\n", "nosec.ini");
  try {
    (void)load_map_build_config(no_section);
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("nosec.ini"), std::string::npos) << e.what();
  }
  EXPECT_EQ(load_map_build_config(IniFile::parse("[A]\nx=1\n[B]\nbeaconMap_count=1\n")).section, "B");
}

}  // namespace
}  // namespace rove
