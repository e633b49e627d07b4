#pragma once
/// \file
/// What `rove map build` (and rove.map_build) do around build_map
/// (metric_map_builder.h): refuse an output folder that would overwrite an
/// input, write the maps (map_* files, occupancy grids also as ROS maps),
/// and tell what a finished build lacks.

#include <string>
#include <string_view>
#include <vector>

#include "rove/maps/multi_metric_map.h"
#include "rove/slam/metric_map_builder.h"

namespace rove {

/// Refuses, before any work, with IoError naming the file: a config file or
/// input that is not a regular file, an output folder that is an existing
/// file, and a config file or input inside the output folder under a name
/// the build writes (map_*).
void check_map_build_outputs(const std::string& config, const std::string& input, const std::string& out_dir);

/// Creates `out_dir` and writes every map of `maps` there (save_metric_map
/// with the prefix "map"), each occupancy grid also as a ROS map_server
/// map (map_<index>_<kind>.png and .yaml, map_saver's trinary image); every
/// file atomically. Returns the files written, in order. Throws IoError.
std::vector<std::string> save_map_build(const std::string& out_dir, const MultiMetricMap& maps);

/// Something a finished build must tell its user: the maps were written,
/// but they are not what was asked for.
struct MapBuildIssue {
  /// "no-observations" (the input holds none), "nothing-inserted" (no map
  /// took any), "empty-map" (one map took none), "velodyne-not-decoded"
  /// (Velodyne scans an octree could not insert).
  std::string code;
  std::string message;  ///< one line for a person, with the counts
};

/// The issues of a build of `maps` from `input` (named in messages).
std::vector<MapBuildIssue> map_build_issues(const MapBuildResult& result, const MultiMetricMap& maps,
                                            std::string_view input);

}  // namespace rove
