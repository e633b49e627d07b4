#pragma once
/// \file
/// Building maps from a dataset, as MRPT's `observations2map`: every
/// observation is inserted into a MetricMap (usually a MultiMetricMap) at
/// the robot pose the dataset gives for it.
///
/// - A simplemap gives each keyframe's pose (its PDF's mean).
/// - A rawlog (MRPT or rove rawlog, or a CARMEN log read as layout #1)
///   gives no poses; they come from odometry. Layout #1: the
///   robot starts at the identity and each action collection's first
///   RobotMovement2D mean is composed onto the pose (T ← T ⊕ Δ); the
///   following sensory frame is inserted at the result. Layout #2: the
///   pose is the latest odometry reading relative to the first one
///   (T = odo_k ⊖ odo₀); every other observation is inserted at the latest
///   pose (the identity before the first odometry reading).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/core/ini.h"
#include "rove/maps/metric_map.h"
#include "rove/maps/multi_metric_map.h"

namespace rove {

/// Where a build takes its input from.
enum class MapInputKind : std::uint8_t {
  Rawlog = 0,     ///< MRPT/rove rawlog or CARMEN log, poses from odometry
  SimpleMap = 1,  ///< MRPT simplemap, poses stored
};

/// Options of build_map().
struct MapBuildOptions {
  /// Called after each keyframe / rawlog entry with the number done so far
  /// (may be empty).
  std::function<void(std::uint64_t done)> on_progress;
};

/// What build_map() did.
struct MapBuildResult {
  MapInputKind input = MapInputKind::Rawlog;  ///< detected input kind
  std::size_t keyframes = 0;         ///< sensory frames / poses visited
  std::size_t observations = 0;      ///< observations offered to the map
  std::size_t observations_used = 0; ///< of those, inserted by some map
  std::size_t odometry_steps = 0;    ///< odometry increments integrated (rawlogs)
  Pose3 final_pose;                  ///< the last robot pose, T_map_robot
  double seconds = 0.0;              ///< wall time of reading and inserting
};

/// The input kind of `path` from its name, as MRPT's tools tell them
/// apart: a simplemap if the file name contains ".simplemap" (also
/// ".simplemap.gz"), else a rawlog.
MapInputKind detect_map_input(const std::string& path);

/// The maps a `rove map build` configuration declares.
struct MapBuildConfig {
  std::string section;  ///< the section holding the `<kind>_count` keys
  MultiMetricMap maps;  ///< the maps, empty and ready to fill
  /// Keys present that have no effect in rove.
  std::vector<IgnoredConfigKey> ignored_keys;
};

/// Reads the multi-metric map of an MRPT application file, as MRPT's
/// observations2map: from `section`, or when it is empty from the first
/// section holding a `<kind>_count` key of a known map kind. Strict as
/// MultiMetricMap::from_config (unknown keys of the map sections, malformed
/// or out-of-range values, sizes beyond the memory budget). Throws
/// ConfigError naming the file and section when no section declares a map,
/// `section` does not exist, or every `_count` is 0.
MapBuildConfig load_map_build_config(const IniFile& ini, std::string_view section = {});

/// Reads `path` (rawlog or simplemap, plain or gzip) and inserts every
/// observation into `map` (see the file comment). Throws IoError /
/// ParseError (file, offset, class) on unreadable input, rove::Interrupted
/// (rove/core/interrupt.h) when Ctrl-C was pressed (checked per entry).
MapBuildResult build_map(const std::string& path, MetricMap& map,
                         const MapBuildOptions& options = {});

}  // namespace rove
