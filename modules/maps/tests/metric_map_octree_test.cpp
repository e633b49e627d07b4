// OctreeMetricMap: MRPT's octoMap / colourOctoMap in a multi-metric map.
#include "rove/maps/metric_map_octree.h"
#include "rove/obs/velodyne_decode.h"

#include <cmath>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/velodyne_scan.h"

namespace rove {
namespace {

IniFile ini_of(const std::string& text) { return IniFile::parse(text, "<test>"); }

// A Velodyne-like cloud: a ring of points 4 m around the sensor.
VelodyneScan ring_scan() {
  VelodyneScan v;
  for (int i = 0; i < 720; ++i) {
    const double a = 2.0 * M_PI * i / 720.0;
    v.point_cloud.x.push_back(static_cast<float>(4.03 * std::cos(a)));
    v.point_cloud.y.push_back(static_cast<float>(4.03 * std::sin(a)));
    v.point_cloud.z.push_back(i % 2 == 0 ? 0.33f : -0.33f);
  }
  v.point_cloud.x.push_back(0.0f);  // MRPT's invalid point
  v.point_cloud.y.push_back(0.0f);
  v.point_cloud.z.push_back(0.0f);
  v.T_robot_sensor = Pose3(0.1, 0.0, 1.0, 0.0, 0.0, 0.0);
  return v;
}

TEST(OctreeMetricMap, ConfiguredFromMrptSections) {
  const IniFile ini = ini_of(
      "[M]\noctoMap_count=1\ncolourOctoMap_count=1\n"
      "[M_octoMap_00_creationOpts]\nresolution=0.2\n"
      "[M_octoMap_00_insertOpts]\nmaxrange=3.5\npruning=false\nprobHit=0.8\nclampingThresMax=0.95\n"
      "[M_octoMap_00_likelihoodOpts]\ndecimation=4\n");
  const MultiMetricMap mm = MultiMetricMap::from_config(ini, "M");
  ASSERT_EQ(mm.size(), 2u);
  const auto* o = dynamic_cast<const OctreeMetricMap*>(mm.find("octoMap"));
  const auto* c = dynamic_cast<const OctreeMetricMap*>(mm.find("colourOctoMap"));
  ASSERT_NE(o, nullptr);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(o->tree().resolution(), 0.2);
  EXPECT_EQ(c->tree().resolution(), 0.1);  // MRPT's default
  EXPECT_EQ(o->insert_options.max_range, 3.5);
  EXPECT_FALSE(o->insert_options.pruning);
  EXPECT_EQ(o->tree().params().prob_hit, 0.8);
  EXPECT_EQ(o->tree().params().clamping_max, 0.95);
  EXPECT_EQ(o->likelihood_options.decimation, 4u);
  EXPECT_TRUE(has_channels(c->tree().channels(), OctreeChannels::Color));
}

TEST(OctreeMetricMap, BadConfigValuesNameTheKey) {
  for (const char* bad : {"[M_octoMap_00_insertOpts]\nprobHit=0.3\n", "[M_octoMap_00_insertOpts]\nclampingThresMin=0.99\n",
                          "[M_octoMap_00_creationOpts]\nresolution=0\n", "[M_octoMap_00_likelihoodOpts]\ndecimation=0\n",
                          "[M_octoMap_00_insertOpts]\nmaxDistance=3\n"}) {
    SCOPED_TRACE(bad);
    const IniFile ini = ini_of(std::string("[M]\noctoMap_count=1\n") + bad);
    EXPECT_THROW(MultiMetricMap::from_config(ini, "M"), ConfigError);
  }
}

TEST(OctreeMetricMap, InsertsVelodyneCloudsFromTheSensorOrigin) {
  OctreeMetricMap m(0.1);
  EXPECT_TRUE(m.empty());
  const VelodyneScan v = ring_scan();
  const Pose3 T_map_robot(1.02, 2.04, 0.0, 0.0, 0.0, 0.0);
  EXPECT_TRUE(m.insert(v, T_map_robot));
  // Occupied on the ring (in the map frame: sensor at (1.12, 2.04, 1.0)),
  // free between it and the sensor.
  const auto wall = m.tree().search(Eigen::Vector3d(1.12 + 4.03, 2.04, 1.0 + 0.33));
  ASSERT_TRUE(wall.has_value());
  EXPECT_TRUE(m.tree().is_occupied(wall->log_odds));
  const auto free = m.tree().search(Eigen::Vector3d(1.12 + 2.015, 2.04, 1.165));  // half way to (4.03, 0, 0.33)
  ASSERT_TRUE(free.has_value());
  EXPECT_FALSE(m.tree().is_occupied(free->log_odds));
  // Nothing at (0,0,0) (the invalid point, in the map frame).
  EXPECT_FALSE(m.tree().search(Eigen::Vector3d(0.01, 0.01, 0.01)).has_value());
  const MapStatistics s = m.statistics();
  EXPECT_GT(s.elements, 100u);
  EXPECT_GT(s.total_cells, s.elements);
  EXPECT_NEAR(m.bounding_box().min.x(), 1.12 - 4.03, 0.25);
  // MRPT's likelihood: log p(occupied) summed over the points in known
  // cells; where it was taken, each of the 720 points is in a cell hit once.
  EXPECT_NEAR(m.log_likelihood(v, T_map_robot), 720 * std::log(0.7), 1e-4);
  m.likelihood_options.decimation = 4;
  EXPECT_NEAR(m.log_likelihood(v, T_map_robot), 180 * std::log(0.7), 1e-4);
  // Kinds without points are not inserted.
  VelodyneScan empty;
  EXPECT_FALSE(m.insert(empty, T_map_robot));
  m.clear();
  EXPECT_TRUE(m.empty());
}

// A VLP-16 scan of raw packets only (pseudo-random returns, nominal
// calibration), as rawlogs from MRPT's grabber hold them.
VelodyneScan raw_vlp16_scan() {
  VelodyneScan v;
  v.T_robot_sensor = Pose3(0.1, 0.0, 1.0, 0.0, 0.0, 0.0);
  for (int i = 0; i < 16; ++i) {
    VelodyneLaserCalibration c;
    c.vertical_correction = i % 2 == 0 ? -15.0 + i : i;
    c.sin_vert_correction = std::sin(c.vertical_correction * M_PI / 180.0);
    c.cos_vert_correction = std::cos(c.vertical_correction * M_PI / 180.0);
    v.calibration.push_back(c);
  }
  std::uint64_t x = 7;
  for (int p = 0; p < 20; ++p) {
    VelodynePacket pk{};
    for (int b = 0; b < 12; ++b) {
      const int a = (p * 12 + b) * 150 % 36000;
      pk[static_cast<std::size_t>(100 * b)] = 0xFF, pk[static_cast<std::size_t>(100 * b + 1)] = 0xEE;
      pk[static_cast<std::size_t>(100 * b + 2)] = static_cast<std::uint8_t>(a & 0xFF);
      pk[static_cast<std::size_t>(100 * b + 3)] = static_cast<std::uint8_t>(a >> 8);
      for (int r = 0; r < 32; ++r) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;
        const auto d = static_cast<std::uint16_t>(1000 + (x >> 33) % 2000);  // 2 to 6 m
        const auto at = static_cast<std::size_t>(100 * b + 4 + 3 * r);
        pk[at] = static_cast<std::uint8_t>(d & 0xFF), pk[at + 1] = static_cast<std::uint8_t>(d >> 8);
      }
    }
    pk[1204] = 0x37, pk[1205] = 0x22;
    v.packets.push_back(pk);
  }
  return v;
}

TEST(OctreeMetricMap, DecodesVelodynePacketsWithTheirCalibration) {
  const Pose3 T_map_robot(0.5, -0.3, 0.0, 0.4, 0.0, 0.0);
  VelodyneScan raw = raw_vlp16_scan();
  OctreeMetricMap from_packets(0.1), from_cloud(0.1);
  ASSERT_TRUE(from_packets.insert(raw, T_map_robot));
  EXPECT_EQ(from_packets.undecoded_velodyne_scans(), 0u);
  // The same as inserting the decoded cloud stored in the scan.
  VelodyneScan decoded = raw;
  decoded.point_cloud = decode_velodyne_scan(raw).cloud;
  ASSERT_EQ(decoded.point_cloud.x.size(), 20u * 12u * 32u);
  ASSERT_TRUE(from_cloud.insert(decoded, T_map_robot));
  EXPECT_EQ(from_packets.statistics().elements, from_cloud.statistics().elements);
  EXPECT_EQ(from_packets.statistics().total_cells, from_cloud.statistics().total_cells);
  EXPECT_GT(from_packets.statistics().elements, 1000u);
  // Without its calibration the scan cannot be decoded: not inserted, and
  // the map says why.
  raw.calibration.clear();
  OctreeMetricMap m(0.1);
  EXPECT_FALSE(m.insert(raw, T_map_robot));
  EXPECT_FALSE(m.insert(raw, T_map_robot));
  EXPECT_TRUE(m.empty());
  EXPECT_EQ(m.undecoded_velodyne_scans(), 2u);
  EXPECT_NE(m.undecoded_velodyne_reason().find("calibration"), std::string::npos) << m.undecoded_velodyne_reason();
  m.clear();
  EXPECT_EQ(m.undecoded_velodyne_scans(), 0u);
}

TEST(OctreeMetricMap, Inserts2DScansAndRangeImagePoints) {
  OctreeMetricMap m(0.05);
  RangeScan2D scan;
  scan.aperture = M_PI;
  scan.ranges.assign(181, 2.0f);
  scan.valid.assign(181, true);
  EXPECT_TRUE(m.insert(scan, Pose3()));
  const auto hit = m.tree().search(Eigen::Vector3d(2.02, 0.0, 0.0));
  ASSERT_TRUE(hit.has_value());
  EXPECT_TRUE(m.tree().is_occupied(hit->log_odds));
  RangeImage3D img;
  RangeImagePoints stored;
  stored.p_sensor.emplace_back(1.0f, 0.0f, 0.5f);
  stored.p_sensor.emplace_back(0.0f, 0.0f, 0.0f);  // invalid, skipped
  img.points.emplace(std::move(stored));
  OctreeMetricMap c(0.05, {}, {}, true);
  EXPECT_TRUE(c.insert(img, Pose3()));
  EXPECT_TRUE(c.tree().is_occupied(c.tree().search(Eigen::Vector3d(1.0, 0.0, 0.5))->log_odds));
  EXPECT_EQ(c.kind(), "colourOctoMap");
}

TEST(OctreeMetricMap, ColourMapTakesThePixelEachPointProjectsTo) {
  // Two stored points seen by a 100 x 100 colour camera that coincides with
  // the depth camera: the left half of the image is red, the right blue.
  RangeImage3D img;
  RangeImagePoints stored;
  stored.p_sensor.emplace_back(2.0f, 0.5f, 0.0f);   // left of the optical axis: u < 50
  stored.p_sensor.emplace_back(2.0f, -0.5f, 0.0f);  // right: u > 50
  img.points.emplace(std::move(stored));
  img.intensity_camera = PinholeCamera{100, 100, 50.0, 50.0, 49.5, 49.5, {}};
  Image rgb = Image::zeros(100, 100, 3, PixelType::U8);
  for (std::size_t i = 0; i < 100 * 100; ++i) {
    rgb.data[3 * i + ((i % 100) < 50 ? 0 : 2)] = 200;
  }
  img.intensity = std::move(rgb);
  OctreeMetricMap c(0.05, {}, {}, true);
  const Pose3 T_map_robot(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  ASSERT_TRUE(c.insert(img, T_map_robot));
  const OctreeKey left = c.tree().key_checked(Eigen::Vector3d(3.0, 0.5, 0.0));
  const OctreeKey right = c.tree().key_checked(Eigen::Vector3d(3.0, -0.5, 0.0));
  // A leaf without a colour takes the first measurement as it is (OctoMap).
  EXPECT_EQ(c.tree().color_at(left), (Rgb8{200, 0, 0}));
  EXPECT_EQ(c.tree().color_at(right), (Rgb8{0, 0, 200}));
  // The plain map ignores the image.
  OctreeMetricMap o(0.05);
  ASSERT_TRUE(o.insert(img, T_map_robot));
  EXPECT_FALSE(o.tree().color_at(left).has_value());
  EXPECT_TRUE(o.tree().is_occupied(o.tree().search(left)->log_odds));
}

}  // namespace
}  // namespace rove
