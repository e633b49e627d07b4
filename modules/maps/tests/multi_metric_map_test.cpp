#include "rove/maps/multi_metric_map.h"

#include <algorithm>
#include <filesystem>
#include <cctype>
#include <set>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/maps/beacon_map.h"
#include "rove/maps/landmark_map.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_octree.h"
#include "rove/maps/metric_map_points.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {
namespace {

namespace fs = std::filesystem;

const std::string kMrptConfigs = "/usr/share/mrpt/config_files";

/// MRPT 2.5.8's registered map names (short aliases): a `<name>_count` key
/// marks a section as a multi-metric map declaration. Class names
/// (`C...`, `mrpt::maps::C...`) count too.
bool is_count_key(const std::string& key) {
  auto lower = [](std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  const std::string k = lower(key);
  const std::string suffix = "_count";
  if (k.size() <= suffix.size() || k.compare(k.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  const std::string stem = k.substr(0, k.size() - suffix.size());
  static const std::set<std::string> names = {
      "occupancygrid", "gasgrid",      "landmarksmap",   "beaconmap",     "pointsmap",
      "colourpointsmap", "heightmap",  "dem",            "weightedpointsmap", "octomap",
      "colouroctomap", "coloroctomap", "wifigrid",       "reflectivitymap", "dem_mrf"};
  if (names.count(stem)) return true;
  std::string cls = stem;
  if (cls.rfind("mrpt::maps::", 0) == 0) cls = cls.substr(12);
  if (cls.size() < 2 || cls[0] != 'c') return false;
  return std::all_of(cls.begin() + 1, cls.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

struct Declaration {
  fs::path file;
  std::string section;
  std::uint64_t maps = 0;             // sum of the counts
  std::string unsupported_count_key;  // a `_count` > 0 of a kind rove lacks
};

std::vector<Declaration> find_declarations() {
  std::vector<Declaration> out;
  for (const auto& e : fs::recursive_directory_iterator(kMrptConfigs)) {
    if (!e.is_regular_file() || e.path().extension() != ".ini") continue;
    const IniFile ini = IniFile::load(e.path().string(), IniOptions{.strict = false});
    for (const auto& sec : ini.sections()) {
      Declaration d{e.path(), sec, 0, {}};
      bool found = false;
      for (const auto& key : ini.keys(sec)) {
        if (!is_count_key(key)) continue;
        found = true;
        const auto n = ini.get<std::uint64_t>(sec, key);
        d.maps += n;
        const std::string stem = key.substr(0, key.size() - 6);
        static const std::set<std::string> unsupported = {"gasGrid", "wifiGrid", "reflectivityMap",
                                                          "dem_mrf"};
        if (n > 0 && unsupported.count(stem) && d.unsupported_count_key.empty()) {
          d.unsupported_count_key = key;
        }
      }
      if (found) out.push_back(d);
    }
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.file < b.file; });
  return out;
}

TEST(MultiMetricMapConfig, EveryMrptConfigFileLoads) {
  ASSERT_TRUE(fs::is_directory(kMrptConfigs)) << kMrptConfigs << " missing (Debian mrpt-common)";
  const auto decls = find_declarations();
  // icp-slam (5), rbpf-slam (9), pf-localization (3), hmt-slam, icp-slam-live,
  // icp-graph-slam, grid-matching, ro-localization: 22 declarations.
  ASSERT_GE(decls.size(), 20u);
  std::size_t loaded = 0, rejected = 0;
  for (const auto& d : decls) {
    SCOPED_TRACE(d.file.string() + " [" + d.section + "]");
    const IniFile ini = IniFile::load(d.file.string(), IniOptions{.strict = false});
    if (!d.unsupported_count_key.empty()) {
      // Gas grids: a clear error naming the count key.
      try {
        (void)MultiMetricMap::from_config(ini, d.section);
        ADD_FAILURE() << "expected ConfigError for " << d.unsupported_count_key;
      } catch (const ConfigError& e) {
        EXPECT_EQ(e.key(), d.unsupported_count_key);
        EXPECT_EQ(e.section(), d.section);
        EXPECT_NE(std::string(e.what()).find("not implemented"), std::string::npos);
      }
      ++rejected;
      continue;
    }
    MultiMetricMapLoadReport report;
    MultiMetricMap mm;
    ASSERT_NO_THROW(mm = MultiMetricMap::from_config(ini, d.section, &report));
    EXPECT_EQ(mm.size(), d.maps);
    for (const auto& e : mm.entries()) {
      // Only landmark maps start with content: the beacons their creation
      // section declares (ro-localization-demo: 15).
      if (e.map->kind() == "landmarksMap") continue;
      EXPECT_TRUE(e.map->empty()) << e.map->kind();
    }
    if (d.file.filename() == "icp-slam_demo_with_octomap.ini") {
      const auto* o = dynamic_cast<const OctreeMetricMap*>(mm.find("octoMap"));
      ASSERT_NE(o, nullptr);
      EXPECT_EQ(o->tree().resolution(), 0.15);
      EXPECT_EQ(o->insert_options.max_range, -1.0);
      EXPECT_EQ(o->tree().params().clamping_min, 0.1192);
    }
    if (d.file.filename() == "ro-localization-demo.ini") {
      ASSERT_EQ(mm.size(), 1u);
      EXPECT_EQ(dynamic_cast<const LandmarkMap&>(*mm.entries()[0].map).landmarks().size(), 15u);
    }
    ++loaded;
  }
  EXPECT_GE(loaded, 18u);
  EXPECT_EQ(rejected, 2u);  // icp-gas-mapping, gas_mapping_2lasers_2enoses
}

TEST(MultiMetricMapConfig, ReadsMrptOptionsIntoTheMaps) {
  const IniFile ini =
      IniFile::load(kMrptConfigs + "/rbpf-slam/RO-SLAM_simulatedData_SOG.ini", IniOptions{.strict = false});
  const auto mm = MultiMetricMap::from_config(ini, "MappingApplication");
  ASSERT_EQ(mm.size(), 1u);
  const auto* b = dynamic_cast<const BeaconMap*>(mm.entries()[0].map.get());
  ASSERT_NE(b, nullptr);
  EXPECT_FALSE(b->insert_options.insert_as_monte_carlo);
  EXPECT_DOUBLE_EQ(b->insert_options.sog_max_dist_between_gaussians, 0.6);
  EXPECT_DOUBLE_EQ(b->likelihood_options.range_std, 0.02);
  EXPECT_EQ(mm.entries()[0].section_prefix, "MappingApplication_beaconMap_00");

  const IniFile icp =
      IniFile::load(kMrptConfigs + "/icp-slam/icp-slam_demo_classic.ini", IniOptions{.strict = false});
  const auto m2 = MultiMetricMap::from_config(icp, "MappingApplication");
  ASSERT_EQ(m2.size(), 1u);
  const auto* p = dynamic_cast<const PointsMetricMap*>(m2.entries()[0].map.get());
  ASSERT_NE(p, nullptr);
  EXPECT_FLOAT_EQ(p->points().insertion_options.min_dist_between_points,
                  icp.get<float>("MappingApplication_pointsMap_00_insertOpts",
                                 "minDistBetweenLaserPoints"));
}

TEST(MultiMetricMapConfig, MisspelledKeyIsReportedByName) {
  const auto ini = IniFile::parse(
      "[M]\nbeaconMap_count=1\n[M_beaconMap_00_insertOpts]\ninsertAsMonteCarlo=0\n"
      "SOG_maxDistBetweenGausians=0.5\n",
      "typo.ini");
  try {
    (void)MultiMetricMap::from_config(ini, "M");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "typo.ini");
    EXPECT_EQ(e.section(), "M_beaconMap_00_insertOpts");
    EXPECT_EQ(e.key(), "SOG_maxDistBetweenGausians");
    EXPECT_NE(std::string(e.what()).find("line 5"), std::string::npos) << e.what();
  }
  // A `_count` key that names no map kind.
  const auto bad = IniFile::parse("[M]\npointMap_count=1\n", "kind.ini");
  try {
    (void)MultiMetricMap::from_config(bad, "M");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "pointMap_count");
  }
  // gasGrid: not supported, named.
  const auto gas = IniFile::parse("[M]\ngasGrid_count=2\n", "gas.ini");
  try {
    (void)MultiMetricMap::from_config(gas, "M");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "gasGrid_count");
  }
}

TEST(MultiMetricMapConfig, NamesSectionsAndOrderAsMrpt) {
  // Qualified class names are accepted and name their sections; maps are
  // created in byte order of the names (MRPT's registry order).
  const auto ini = IniFile::parse(
      "[M]\nmrpt::maps::CBeaconMap_count=1\nlandmarksMap_count=1\nCHeightGridMap2D_count=1\n"
      "[M_mrpt::maps::CBeaconMap_00_likelihoodOpts]\nrangeStd=0.3\n"
      "[M_CHeightGridMap2D_00_creationOpts]\nresolution=0.5\nenableObservationInsertion=false\n",
      "names.ini");
  const auto mm = MultiMetricMap::from_config(ini, "M");
  ASSERT_EQ(mm.size(), 3u);
  EXPECT_EQ(mm.entries()[0].map->kind(), "heightMap");     // "CHeightGridMap2D"
  EXPECT_EQ(mm.entries()[1].map->kind(), "landmarksMap");  // "landmarksMap"
  EXPECT_EQ(mm.entries()[2].map->kind(), "beaconMap");     // "mrpt::maps::CBeaconMap"
  EXPECT_FALSE(mm.entries()[0].params.enable_insertion);
  EXPECT_DOUBLE_EQ(dynamic_cast<const BeaconMap&>(*mm.entries()[2].map).likelihood_options.range_std,
                   0.3);
}

TEST(MultiMetricMap, InsertionAndLikelihoodSelection) {
  const auto ini = IniFile::parse(
      "[M]\nbeaconMap_count=1\nlandmarksMap_count=1\nlikelihoodMapSelection=mapBeacon\n"
      "enableInsertion_landmarksMap=0\n"
      "[M_landmarksMap_00_creationOpts]\nnBeacons=1\nbeacon_001_ID=4\nbeacon_001_X=3\n"
      "beacon_001_Y=0\nbeacon_001_Z=0\n",
      "sel.ini");
  auto mm = MultiMetricMap::from_config(ini, "M");
  ASSERT_EQ(mm.size(), 2u);
  ASSERT_TRUE(mm.likelihood_selection.has_value());
  EXPECT_EQ(*mm.likelihood_selection, "beaconMap");
  BeaconRanges o;
  o.min_sensor_distance = 0;
  o.max_sensor_distance = 10;
  o.readings.push_back({4, 3.0f, Eigen::Vector3d::Zero()});
  EXPECT_TRUE(mm.insert(o, Pose3()));
  EXPECT_EQ(mm.entries()[0].observations_inserted, 1u);  // beaconMap
  EXPECT_EQ(mm.entries()[1].observations_inserted, 0u);  // landmarks: disabled
  const double beacon_only = mm.log_likelihood(o, Pose3(0.5, 0, 0, 0, 0, 0));
  EXPECT_EQ(beacon_only, mm.find("beaconMap")->log_likelihood(o, Pose3(0.5, 0, 0, 0, 0, 0)));
  mm.likelihood_selection.reset();  // mapFuseAll: the sum
  EXPECT_NEAR(mm.log_likelihood(o, Pose3(0.5, 0, 0, 0, 0, 0)),
              beacon_only + mm.find("landmarksMap")->log_likelihood(o, Pose3(0.5, 0, 0, 0, 0, 0)),
              1e-12);
  RangeScan2D scan;
  EXPECT_FALSE(mm.can_compute_likelihood(scan));
  mm.clear();
  EXPECT_TRUE(mm.find("beaconMap")->empty());
  EXPECT_EQ(mm.entries()[0].observations_inserted, 0u);
}

}  // namespace
}  // namespace rove
