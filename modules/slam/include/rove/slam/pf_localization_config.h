#pragma once
/// \file
/// Reading MRPT's pf-localization configuration files unchanged
/// (localization_demo.ini, ro-localization-demo.ini, ...), strictly: an
/// unknown key is a ConfigError naming file, section, key and line, and
/// keys that only steer MRPT's GUI or logs are listed as without effect.
///
/// Sections and keys (MRPT's names; "rove" marks additions):
/// - [LocalizationExperiment]: `map_file` (a .simplemap, .gridmap or ROS
///   map.yaml, plain or .gz), `rawlog_file`, `rawlog_offset`,
///   `particles_count` (one value), `init_PDF_mode` (0: free cells in the
///   box, 1: uniform in the box; rove: 2 free space of the whole map, 3
///   Gaussian around init_PDF_mean_*), `init_PDF_min_x`/`max_x`/`min_y`/
///   `max_y` (m), `init_PDF_min_yaw_deg`/`max_yaw_deg`, rove's
///   `init_PDF_mean_x`/`_y`/`_yaw_deg`, `init_PDF_std_xy`,
///   `init_PDF_std_yaw_deg`, `ground_truth_path_file`, `initial_odo_x`/
///   `_y`/`_phi` (rad), `use_3D_poses` (false only), rove's
///   `recovery_alpha_slow`/`_fast`, `converged_radius` (m),
///   `converged_heading_radius_deg`, `converged_min_mass`, `converged_min_steps`,
///   `converged_min_scan_fit`, `converged_fit_distance` (m),
///   `converged_max_range_residual`; MRPT's GUI and logging switches
///   (`logOutput_dir`, `3DSceneFrequency`, `SHOW_PROGRESS_3D_REAL_TIME`,
///   ...) are without effect.
/// - [PF_options] (ParticleFilterOptions::from_config), [KLD_options]
///   (KldOptions::from_config), [MetricMap] (MultiMetricMap::from_config),
///   [DummyOdometryParams] (`minStdXY` m, `minStdPHI` deg), and rove's
///   optional [MotionModel] (MotionModelOptions keys) replacing the motion
///   model of the log's odometry.
/// MRPT's pf-localization takes the particle count from particles_count and
/// ignores [PF_options] sampleSize; so does rove.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/core/ini.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/poses/pose2.h"
#include "rove/slam/mcl_options.h"

namespace rove {

/// A pf-localization configuration.
struct PfLocalizationConfig {
  /// The filter's options (seed and threads at their defaults: the caller's).
  MclOptions options;
  /// The maps [MetricMap] declares, empty (map_file fills them).
  MultiMetricMap map;
  /// `map_file` as written (empty: the map is the configuration's alone,
  /// e.g. beacons declared in [MetricMap]).
  std::string map_file;
  /// `rawlog_file` as written, possibly empty.
  std::string rawlog_file;
  /// `ground_truth_path_file` as written, possibly empty.
  std::string ground_truth_file;
  /// `rawlog_offset`: steps skipped at the start of the log.
  std::uint64_t rawlog_offset = 0;
  /// `initial_odo_x`, `_y`, `_phi`: where the odometry path starts.
  Pose2 initial_odometry;
  /// The file the configuration came from (IniFile::source()).
  std::string source;
  /// Keys present that have no effect in rove.
  std::vector<IgnoredConfigKey> ignored_keys;

  /// A path of the configuration (map_file, rawlog_file, ...) as it exists:
  /// as written if that exists (MRPT reads it from the working folder),
  /// else relative to the configuration's folder (where MRPT's own files
  /// expect them). Empty `path` gives empty. Throws ConfigError naming
  /// [LocalizationExperiment] `key` when neither exists.
  std::string resolve(const std::string& path, const std::string& key) const;
};

/// Reads a pf-localization configuration (see the file comment). Throws
/// ConfigError (file, section, key, line) on an unknown key, a malformed or
/// out-of-range value, several particle counts, use_3D_poses = true, a
/// missing mandatory key (particles_count, init_PDF_mode, as MRPT), a
/// free-space initialization without an occupancy grid in [MetricMap], or
/// a map file given for a configuration without a grid.
PfLocalizationConfig load_pf_localization_config(const IniFile& ini);

}  // namespace rove
