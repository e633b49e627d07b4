// Building the map of a pf-localization run from its map file.

#include <algorithm>
#include <cctype>
#include <string>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/grid_image.h"
#include "rove/io/mrpt_gridmap.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/slam/metric_map_builder.h"
#include "rove/slam/pf_localization_run.h"

namespace rove {
namespace {

constexpr const char* kSec = "LocalizationExperiment";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

OccupancyGridMetricMap* first_grid(MultiMetricMap& map) {
  for (const auto& e : map.entries()) {
    if (auto* g = dynamic_cast<OccupancyGridMetricMap*>(e.map.get())) return g;
  }
  return nullptr;
}

OccupancyGridMetricMap& grid_for_file(const PfLocalizationConfig& config, MultiMetricMap& map,
                                      const std::string& kind) {
  OccupancyGridMetricMap* g = first_grid(map);
  if (g == nullptr) {
    throw ConfigError(config.source, kSec, "map_file",
                      fmt::format("'{}' is a {} (an occupancy grid), but [MetricMap] declares no "
                                  "occupancy grid to hold it (occupancyGrid_count = 1)",
                                  printable(config.map_file), kind));
  }
  return *g;
}

}  // namespace

LocalizationMapInfo load_localization_map(const PfLocalizationConfig& config, MultiMetricMap& map) {
  LocalizationMapInfo info;
  if (!config.map_file.empty()) {
    const std::string path = config.resolve(config.map_file, "map_file");
    check_regular_input(path, "map file");
    info.file = path;
    const std::string name = lower(path);
    if (name.find(".simplemap") != std::string::npos) {
      // MRPT's loadFromProbabilisticPosesAndObservations: every keyframe's
      // observations inserted at its pose's mean.
      info.kind = "simplemap";
      const MapBuildResult built = build_map(path, map);
      info.keyframes = built.keyframes;
      info.observations_used = built.observations_used;
      if (map.empty()) {
        throw ConfigError(config.source, kSec, "map_file",
                          fmt::format("no observation of the simplemap '{}' ({} keyframes) could "
                                      "be inserted into the maps [MetricMap] declares",
                                      printable(path), built.keyframes));
      }
    } else if (ends_with(name, ".gridmap") || ends_with(name, ".gridmap.gz")) {
      // MRPT deserializes the whole grid object, its stored insertion and
      // likelihood options included: they replace the configuration's.
      info.kind = "gridmap";
      OccupancyGridMetricMap& g = grid_for_file(config, map, "MRPT .gridmap");
      MrptGridmap loaded = load_mrpt_gridmap(path);
      g.grid() = std::move(loaded.grid);
      g.insert_options = loaded.insertion;
      if (loaded.version >= 1) g.likelihood_options = loaded.likelihood;
    } else if (ends_with(name, ".yaml") || ends_with(name, ".yml")) {
      info.kind = "ros-map-yaml";
      OccupancyGridMetricMap& g = grid_for_file(config, map, "ROS map.yaml");
      g.grid() = load_ros_map(path).grid;
    } else {
      throw ConfigError(config.source, kSec, "map_file",
                        fmt::format("'{}' is neither a .simplemap, a .gridmap (plain or .gz) nor a "
                                    "ROS map .yaml",
                                    printable(path)));
    }
  }
  if (const OccupancyGridMetricMap* g = first_grid(map)) {
    info.grid_size_x = g->grid().size_x();
    info.grid_size_y = g->grid().size_y();
    info.grid_resolution = g->grid().resolution();
  }
  return info;
}

}  // namespace rove
