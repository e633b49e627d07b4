#pragma once
/// \file
/// Reading MRPT's rbpf-slam configuration files unchanged
/// (gridmapping_optimal_sampling.ini, gridmapping_intel.ini,
/// gridmapping_RBPF_grid_ICPbased_malaga.ini, ...), strictly: an unknown
/// key is a ConfigError naming file, section, key and line; a key rove
/// reads but that has no effect is listed in `ignored_keys` with the reason;
/// a setting rove does not implement is a ConfigError saying so.
///
/// [MappingApplication] (MRPT's keys):
/// - `rawlog_file`, `rawlog_offset`;
/// - `insertionLinDistance` (m), `insertionAngDistance_deg`,
///   `localizeLinDistance` (m), `localizeAngDistance_deg`: the robot must
///   have moved this far (by odometry) since the last update to run the
///   filter, and since the last insertion to insert the scan
///   (CMetricMapBuilderRBPF; MRPT's defaults 1 m, 30°, 0.4 m, 10°);
/// - the particle filter: `PF_algorithm` (0 pfStandardProposal, 2
///   pfOptimalProposal = the ICP-based proposal, 3 pfAuxiliaryPFOptimal =
///   the optimal proposal; 1 is refused), `sampleSize`, `BETA`,
///   `resamplingMethod`, `powFactor`,
///   `pfAuxFilterOptimal_MaximumSearchSamples`; `adaptiveSampleSize` must be
///   0 (KLD-sampling is refused; the `KLD_*` keys are then without effect);
///   `max_loglikelihood_dyn_range`, `pfAuxFilterOptimal_MLE` and
///   `pfAuxFilterStandard_FirstStageWeightsMonteCarlo` (auxiliary-PF keys)
///   are without effect;
/// - `pfOptimalProposal_mapSelection`: 0 (the grid) only;
///   `ICPGlobalAlign_MinQuality`; the ICP keys of Icp2dOptions
///   (`ICP_algorithm`, `maxIterations`, `thresholdDist`, ...);
/// - the multi-metric map (`occupancyGrid_count`, ... with its
///   `MappingApplication_occupancyGrid_00_*` sections): exactly one
///   occupancy grid and no other map, whose likelihoodMethod must be 4
///   (lmLikelihoodField_Thrun) with LF_maxCorrsDistance under 32 cells; or
///   exactly one beacon map (`beaconMap_count = 1`, range-only SLAM,
///   rove/slam/ro_slam.h, RO-SLAM_simulatedData_MC.ini / _SOG.ini) with its
///   `_insertOpts` and `_likelihoodOpts`, filtered with PF_algorithm = 0;
/// - MRPT's GUI and log switches (`logOutput_dir`, `SAVE_MAP_IMAGES`,
///   `SHOW_PROGRESS_IN_WINDOW`, `verbosity_level`, ...) are without effect:
///   rove writes its outputs to -o DIR.

#include <cstdint>
#include <string>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/core/ini.h"
#include "rove/slam/rbpf_slam.h"
#include "rove/slam/ro_slam.h"

namespace rove {

/// What the particles of an rbpf-slam configuration map.
enum class RbpfMapKind : std::uint8_t {
  /// One occupancy grid per particle (grid mapping, RbpfSlam).
  OccupancyGrid,
  /// One beacon map per particle (range-only SLAM, RoSlam).
  Beacons,
};

/// An rbpf-slam configuration.
struct RbpfSlamConfig {
  /// What the particles map: selects `options` or `beacons`.
  RbpfMapKind map = RbpfMapKind::OccupancyGrid;
  /// The grid filter's options (seed and threads at their defaults: the
  /// caller's); meaningful when map is OccupancyGrid.
  RbpfSlamOptions options;
  /// The range-only filter's options (seed and threads at their defaults);
  /// meaningful when map is Beacons.
  RoSlamOptions beacons;
  /// (insertionLinDistance) meters. Default 1.
  double insertion_lin_distance = 1.0;
  /// (insertionAngDistance_deg) radians. Default 30°.
  double insertion_ang_distance = 30.0 * 3.14159265358979323846 / 180.0;
  /// (localizeLinDistance) meters. Default 0.4.
  double localize_lin_distance = 0.4;
  /// (localizeAngDistance_deg) radians. Default 10°.
  double localize_ang_distance = 10.0 * 3.14159265358979323846 / 180.0;
  /// (rawlog_file) as written, possibly empty.
  std::string rawlog_file;
  /// (rawlog_offset) steps skipped at the start of the log.
  std::uint64_t rawlog_offset = 0;
  /// The file the configuration came from.
  std::string source;
  /// Keys present that have no effect in rove.
  std::vector<IgnoredConfigKey> ignored_keys;

  /// A path of the configuration as it exists: as written if that exists,
  /// else relative to the configuration's folder. Throws ConfigError naming
  /// [MappingApplication] `key` when neither exists.
  std::string resolve(const std::string& path, const std::string& key) const;
};

/// Reads an rbpf-slam configuration (see the file comment). Throws
/// ConfigError (file, section, key, line) on an unknown key, a malformed or
/// out-of-range value (sampleSize = 0 among them), a missing
/// [MappingApplication] section, or a setting rove does not implement.
RbpfSlamConfig load_rbpf_slam_config(const IniFile& ini);

}  // namespace rove
