#include "rove/slam/map_build_outputs.h"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/grid_image.h"
#include "rove/io/metric_map_files.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_octree.h"

namespace rove {

namespace fs = std::filesystem;

void check_map_build_outputs(const std::string& config, const std::string& input, const std::string& out_dir) {
  check_regular_input(config, "config file");
  check_regular_input(input, "input");
  std::error_code ec;
  if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec)) {
    throw IoError(printable(out_dir), "the output folder is an existing file, not a folder");
  }
  if (!fs::exists(out_dir, ec)) return;
  const fs::path out = fs::canonical(out_dir, ec);
  for (const auto& in : {config, input}) {
    const fs::path p = fs::canonical(in, ec);
    if (ec) continue;
    if (p.parent_path() == out && p.filename().string().starts_with("map_")) {
      throw IoError(printable(in), fmt::format("is in the output folder {} under a name `map build` writes "
                                               "(map_*); choose another output folder",
                                               printable(out_dir)));
    }
  }
}

std::vector<std::string> save_map_build(const std::string& out_dir, const MultiMetricMap& maps) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw IoError(printable(out_dir), "cannot create the output folder: " + ec.message());
  std::vector<std::string> files = save_metric_map((fs::path(out_dir) / "map").string(), maps);
  // Occupancy grids also as a ROS map_server map (map_saver's trinary PNG + yaml).
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const auto& e = maps.entries()[i];
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
      const RosMapFiles ros =
          save_ros_map((fs::path(out_dir) / fmt::format("map_{:02}_{}", i, e.map->kind())).string(), g->grid());
      files.push_back(ros.image);
      files.push_back(ros.yaml);
    }
  }
  return files;
}

std::vector<MapBuildIssue> map_build_issues(const MapBuildResult& r, const MultiMetricMap& maps,
                                            std::string_view input) {
  std::vector<MapBuildIssue> issues;
  if (r.observations == 0) {
    issues.push_back(
        {"no-observations", fmt::format("{} holds no observation: every map is empty", printable(input))});
  } else if (r.observations_used == 0) {
    issues.push_back({"nothing-inserted",
                      fmt::format("none of the {} observations was inserted into any map", r.observations)});
  } else {
    for (std::size_t i = 0; i < maps.size(); ++i) {
      const auto& e = maps.entries()[i];
      if (e.params.enable_insertion && e.observations_inserted == 0) {
        issues.push_back({"empty-map", fmt::format("map {} ({}) received no observation", i, e.map->kind())});
      }
    }
  }
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const auto* o = dynamic_cast<const OctreeMetricMap*>(maps.entries()[i].map.get());
    if (o == nullptr || o->undecoded_velodyne_scans() == 0) continue;
    issues.push_back({"velodyne-not-decoded",
                      fmt::format("map {} ({}): {} Velodyne scan{} not inserted: {}", i, o->kind(),
                                  o->undecoded_velodyne_scans(), o->undecoded_velodyne_scans() == 1 ? "" : "s",
                                  o->undecoded_velodyne_reason())});
  }
  return issues;
}

}  // namespace rove
