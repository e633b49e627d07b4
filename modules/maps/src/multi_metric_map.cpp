#include "rove/maps/multi_metric_map.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/maps/beacon_map.h"
#include "rove/maps/height_map.h"
#include "rove/maps/landmark_map.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_octree.h"
#include "rove/maps/metric_map_points.h"

namespace rove {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool ends_with_icase(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && lower(s.substr(s.size() - suffix.size())) == lower(suffix);
}

/// Sections a map of some kind reads, and its factory.
using Factory = std::function<std::unique_ptr<MetricMap>(
    const IniFile&, const std::string& prefix, std::vector<IgnoredConfigKey>*)>;

struct KindInfo {
  std::string_view canonical;
  std::vector<std::string_view> names;  // every name MRPT 2.5.8 registers
  Factory factory;                      // empty: not implemented in rove
};

std::unique_ptr<MetricMap> make_beacon_map(const IniFile& ini, const std::string& p,
                                           std::vector<IgnoredConfigKey>* ign) {
  ConfigSection is(ini, p + "_insertOpts", ign), ls(ini, p + "_likelihoodOpts", ign);
  auto m = std::make_unique<BeaconMap>(BeaconMapInsertOptions::from_config(is),
                                       BeaconMapLikelihoodOptions::from_config(ls));
  is.check_all_read();
  ls.check_all_read();
  return m;
}

/// A map built from its _creationOpts, _insertOpts and _likelihoodOpts
/// sections (the creation section is checked by create_metric_map, which
/// also reads the generic keys from it).
template <class Map, class Creation, class Insert, class Likelihood>
std::unique_ptr<MetricMap> make_created_map(const IniFile& ini, const std::string& p,
                                            std::vector<IgnoredConfigKey>* ign) {
  ConfigSection cs(ini, p + "_creationOpts", ign), is(ini, p + "_insertOpts", ign),
      ls(ini, p + "_likelihoodOpts", ign);
  auto m = std::make_unique<Map>(Creation::from_config(cs), Insert::from_config(is),
                                 Likelihood::from_config(ls));
  is.check_all_read();
  ls.check_all_read();
  return m;
}

const std::vector<KindInfo>& kinds() {
  static const std::vector<KindInfo> table = {
      {"occupancyGrid",
       {"mrpt::maps::COccupancyGridMap2D", "COccupancyGridMap2D", "occupancyGrid"},
       make_occupancy_grid_metric_map},
      {"pointsMap",
       {"mrpt::maps::CSimplePointsMap", "CSimplePointsMap", "pointsMap"},
       [](const IniFile& i, const std::string& p, std::vector<IgnoredConfigKey>* g) {
         return make_points_metric_map(i, p, PointsMapFlavor::Simple, g);
       }},
      {"colourPointsMap",
       {"mrpt::maps::CColouredPointsMap", "CColouredPointsMap", "colourPointsMap"},
       [](const IniFile& i, const std::string& p, std::vector<IgnoredConfigKey>* g) {
         return make_points_metric_map(i, p, PointsMapFlavor::Coloured, g);
       }},
      {"weightedPointsMap",
       {"mrpt::maps::CWeightedPointsMap", "CWeightedPointsMap", "weightedPointsMap"},
       [](const IniFile& i, const std::string& p, std::vector<IgnoredConfigKey>* g) {
         return make_points_metric_map(i, p, PointsMapFlavor::Weighted, g);
       }},
      {"pointsMapXYZI",
       {"mrpt::maps::CPointsMapXYZI", "CPointsMapXYZI"},
       [](const IniFile& i, const std::string& p, std::vector<IgnoredConfigKey>* g) {
         return make_points_metric_map(i, p, PointsMapFlavor::Intensity, g);
       }},
      {"beaconMap", {"mrpt::maps::CBeaconMap", "CBeaconMap", "beaconMap"}, make_beacon_map},
      {"landmarksMap",
       {"mrpt::maps::CLandmarksMap", "CLandmarksMap", "landmarksMap"},
       make_created_map<LandmarkMap, LandmarkMapCreationOptions, LandmarkMapInsertOptions,
                        LandmarkMapLikelihoodOptions>},
      {"heightMap",
       {"mrpt::maps::CHeightGridMap2D", "CHeightGridMap2D", "heightMap", "dem"},
       make_created_map<HeightMap, HeightMapCreationOptions, HeightMapInsertOptions,
                        HeightMapLikelihoodOptions>},
      // Registered by MRPT 2.5.8, not implemented in rove.
      {"gasGrid",
       {"mrpt::maps::CGasConcentrationGridMap2D", "CGasConcentrationGridMap2D", "gasGrid"},
       {}},
      {"wifiGrid", {"mrpt::maps::CWirelessPowerGridMap2D", "CWirelessPowerGridMap2D", "wifiGrid"}, {}},
      {"reflectivityMap",
       {"mrpt::maps::CReflectivityGridMap2D", "CReflectivityGridMap2D", "reflectivityMap"},
       {}},
      {"octoMap",
       {"mrpt::maps::COctoMap", "COctoMap", "octoMap"},
       [](const IniFile& i, const std::string& p, std::vector<IgnoredConfigKey>* g) {
         return make_octree_metric_map(i, p, false, g);
       }},
      {"colourOctoMap",
       {"mrpt::maps::CColouredOctoMap", "CColouredOctoMap", "colourOctoMap", "colorOctoMap"},
       [](const IniFile& i, const std::string& p, std::vector<IgnoredConfigKey>* g) {
         return make_octree_metric_map(i, p, true, g);
       }},
      {"dem_mrf", {"mrpt::maps::CHeightGridMap2D_MRF", "CHeightGridMap2D_MRF", "dem_mrf"}, {}},
      {"occupancyGrid3D", {"mrpt::maps::COccupancyGridMap3D", "COccupancyGridMap3D"}, {}},
  };
  return table;
}

const KindInfo* kind_by_name(std::string_view name) {
  const std::string l = lower(name);
  for (const auto& k : kinds()) {
    for (auto n : k.names) {
      if (lower(n) == l) return &k;
    }
  }
  return nullptr;
}

GenericMapParams load_generic(const ConfigSection& cs) {
  GenericMapParams g;
  g.enable_save_3d = cs.get<bool>("enableSaveAs3DObject", g.enable_save_3d);
  g.enable_likelihood = cs.get<bool>("enableObservationLikelihood", g.enable_likelihood);
  g.enable_insertion = cs.get<bool>("enableObservationInsertion", g.enable_insertion);
  cs.ignore({"disableSaveAs3DObject"},
            "MRPT 1.x key, not read by MRPT 2.x (use enableSaveAs3DObject); rove draws no 3D view");
  return g;
}

}  // namespace

std::vector<std::string> supported_metric_map_kinds() {
  std::vector<std::string> out;
  for (const auto& k : kinds()) {
    if (k.factory) out.emplace_back(k.canonical);
  }
  return out;
}

std::unique_ptr<MetricMap> create_metric_map(const IniFile& ini, std::string_view name,
                                             const std::string& prefix, GenericMapParams& params,
                                             std::vector<IgnoredConfigKey>* ignored) {
  const KindInfo* k = kind_by_name(name);
  ROVE_CHECK_MSG(k != nullptr, "'{}' is not a metric map kind", name);
  ROVE_CHECK_MSG(static_cast<bool>(k->factory), "map kind '{}' is not implemented in rove",
                 k->canonical);
  ConfigSection cs(ini, prefix + "_creationOpts", ignored);
  params = load_generic(cs);
  auto map = k->factory(ini, prefix, ignored);
  cs.check_all_read();
  return map;
}

MultiMetricMap MultiMetricMap::from_config(const IniFile& ini, std::string_view section_view,
                                           MultiMetricMapLoadReport* report) {
  const std::string section(section_view);
  std::vector<IgnoredConfigKey> local_ignored;
  std::vector<IgnoredConfigKey>* ignored = report ? &report->ignored_keys : &local_ignored;
  const ConfigSection top(ini, section, ignored);

  // Every `*_count` key must name a map kind.
  for (const auto& key : ini.keys(section)) {
    if (!ends_with_icase(key, "_count")) continue;
    const std::string stem = key.substr(0, key.size() - 6);
    if (kind_by_name(stem) == nullptr) {
      std::string known;
      for (const auto& k : kinds()) known += (known.empty() ? "" : ", ") + std::string(k.names.back());
      top.fail(key, fmt::format("'{}' is not a metric map kind (line {}); known kinds: {}", stem,
                                ini.line(section, key).value_or(0), known));
    }
  }

  MultiMetricMap mm;
  // MRPT 1.x selection keys (MRPT 2.x ignores them; rove applies them).
  if (top.has("likelihoodMapSelection")) {
    const std::string v = top.get<std::string>("likelihoodMapSelection", "");
    static const std::pair<std::string_view, std::string_view> sel[] = {
        {"-1", ""},          {"mapFuseAll", ""},         {"0", "occupancyGrid"},
        {"mapGrid", "occupancyGrid"}, {"1", "pointsMap"}, {"mapPoints", "pointsMap"},
        {"2", "landmarksMap"}, {"mapLandmarks", "landmarksMap"}, {"3", "gasGrid"},
        {"mapGasGrid", "gasGrid"}, {"4", "wifiGrid"}, {"mapWifiGrid", "wifiGrid"},
        {"5", "beaconMap"},  {"mapBeacon", "beaconMap"}};
    bool found = false;
    for (const auto& [name, kind] : sel) {
      if (lower(name) != lower(v)) continue;
      found = true;
      if (kind == "gasGrid" || kind == "wifiGrid") {
        top.fail("likelihoodMapSelection",
                 fmt::format("selects {} maps, which rove does not implement", kind));
      }
      if (!kind.empty()) mm.likelihood_selection = std::string(kind);
    }
    if (!found) {
      top.fail("likelihoodMapSelection",
               fmt::format("'{}' is not one of mapFuseAll (-1), mapGrid (0), mapPoints (1), "
                           "mapLandmarks (2), mapGasGrid (3), mapWifiGrid (4), mapBeacon (5)",
                           v));
    }
  }
  struct InsertionSwitch {
    std::string_view key;
    std::vector<std::string_view> kinds;
  };
  const InsertionSwitch switches[] = {
      {"enableInsertion_pointsMap", {"pointsMap", "colourPointsMap", "weightedPointsMap", "pointsMapXYZI"}},
      {"enableInsertion_landmarksMap", {"landmarksMap"}},
      {"enableInsertion_gridMaps", {"occupancyGrid"}},
      {"enableInsertion_beaconMap", {"beaconMap"}},
      {"enableInsertion_gasGridMaps", {"gasGrid"}},
      {"enableInsertion_wifiGridMaps", {"wifiGrid"}},
  };
  std::vector<std::string_view> insertion_disabled;
  for (const auto& s : switches) {
    if (!top.get<bool>(s.key, true)) {
      insertion_disabled.insert(insertion_disabled.end(), s.kinds.begin(), s.kinds.end());
    }
  }

  // MRPT walks its registry (a std::map keyed by every name) in byte order.
  std::map<std::string, const KindInfo*> registry;
  for (const auto& k : kinds()) {
    for (auto n : k.names) registry.emplace(std::string(n), &k);
  }
  for (const auto& [name, kind] : registry) {
    const std::string count_key = name + "_count";
    if (!ini.has(section, count_key)) continue;
    const auto n = top.get<std::uint64_t>(count_key, 0);
    if (n == 0) continue;
    if (!kind->factory) {
      top.fail(count_key, fmt::format("{} map{} requested, but map kind '{}' is not implemented "
                                      "in rove (supported: {})",
                                      n, n > 1 ? "s" : "", name,
                                      fmt::join(supported_metric_map_kinds(), ", ")));
    }
    if (n > 100) top.fail(count_key, fmt::format("{} maps requested; at most 100 are supported", n));
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::string prefix = fmt::format("{}_{}_{:02}", section, name, i);
      GenericMapParams params;
      auto map = create_metric_map(ini, name, prefix, params, ignored);
      if (std::find(insertion_disabled.begin(), insertion_disabled.end(), kind->canonical) !=
          insertion_disabled.end()) {
        params.enable_insertion = false;
      }
      mm.add(std::move(map), params, prefix);
    }
  }
  return mm;
}

void MultiMetricMap::add(std::unique_ptr<MetricMap> map, GenericMapParams params,
                         std::string section_prefix) {
  ROVE_CHECK(map != nullptr);
  entries_.push_back({std::move(map), params, std::move(section_prefix), 0});
}

MetricMap* MultiMetricMap::find(std::string_view kind) noexcept {
  for (auto& e : entries_) {
    if (e.map->kind() == kind) return e.map.get();
  }
  return nullptr;
}

const MetricMap* MultiMetricMap::find(std::string_view kind) const noexcept {
  for (const auto& e : entries_) {
    if (e.map->kind() == kind) return e.map.get();
  }
  return nullptr;
}

bool MultiMetricMap::insert(const Observation& observation, const Pose3& T_map_robot) {
  bool any = false;
  for (auto& e : entries_) {
    if (!e.params.enable_insertion) continue;
    if (e.map->insert(observation, T_map_robot)) {
      ++e.observations_inserted;
      any = true;
    }
  }
  return any;
}

bool MultiMetricMap::can_compute_likelihood(const Observation& observation) const {
  for (const auto& e : entries_) {
    if (!e.params.enable_likelihood) continue;
    if (likelihood_selection && e.map->kind() != *likelihood_selection) continue;
    if (e.map->can_compute_likelihood(observation)) return true;
  }
  return false;
}

double MultiMetricMap::log_likelihood(const Observation& observation,
                                      const Pose3& T_map_robot) const {
  double sum = 0.0;
  for (const auto& e : entries_) {
    if (!e.params.enable_likelihood) continue;
    if (likelihood_selection && e.map->kind() != *likelihood_selection) continue;
    if (!e.map->can_compute_likelihood(observation)) continue;
    sum += e.map->log_likelihood(observation, T_map_robot);
  }
  return sum;
}

bool MultiMetricMap::empty() const {
  return std::all_of(entries_.begin(), entries_.end(),
                     [](const MetricMapEntry& e) { return e.map->empty(); });
}

void MultiMetricMap::clear() {
  for (auto& e : entries_) {
    e.map->clear();
    e.observations_inserted = 0;
  }
}

MapBounds MultiMetricMap::bounding_box() const {
  MapBounds b;
  for (const auto& e : entries_) b.extend(e.map->bounding_box());
  return b;
}

MapStatistics MultiMetricMap::statistics() const {
  MapStatistics s;
  s.unit = "elements";
  for (const auto& e : entries_) {
    const auto m = e.map->statistics();
    s.elements += m.elements;
    s.total_cells += m.total_cells;
    s.bounds.extend(m.bounds);
  }
  return s;
}

}  // namespace rove
