#pragma once
/// \file
/// MultiMetricMap: several metric maps of different kinds updated together
/// (MRPT's CMultiMetricMap), created from an MRPT configuration section as
/// MRPT 2.5.8's TSetOfMetricMapInitializers::loadFromConfigFile reads it.
///
/// Configuration, in section [S]:
///  - `<name>_count = N` for each map kind, where <name> is any name MRPT
///    registers for it: the short alias (`occupancyGrid`, `pointsMap`,
///    `colourPointsMap`, `weightedPointsMap`, `beaconMap`, `landmarksMap`,
///    `heightMap`, `dem`, `octoMap`, `colourOctoMap`), the class name (`COccupancyGridMap2D`) or the
///    qualified one (`mrpt::maps::COccupancyGridMap2D`). Each map i reads
///    sections `[S_<name>_<ii>_creationOpts]`, `_insertOpts`,
///    `_likelihoodOpts` (and `_renderOpts` / `_colorOpts` for point maps),
///    with <name> spelled as in its `_count` key and ii = 00, 01, ...
///    Maps are created in MRPT's order (by name, byte-wise).
///  - `<prefix>_creationOpts` also holds MRPT's generic keys
///    `enableObservationInsertion`, `enableObservationLikelihood`,
///    `enableSaveAs3DObject` (and the older `disableSaveAs3DObject`).
///  - MRPT 1.x keys MRPT 2.x no longer reads, which rove applies:
///    `likelihoodMapSelection` (`mapFuseAll`/-1, `mapGrid`/0, `mapPoints`/1,
///    `mapLandmarks`/2, `mapGasGrid`/3, `mapWifiGrid`/4, `mapBeacon`/5) and
///    `enableInsertion_pointsMap`, `_landmarksMap`, `_gridMaps`,
///    `_gasGridMaps`, `_beaconMap`, `_wifiGridMaps`.
///  - Kinds rove does not implement (gas, wifi and reflectivity grids,
///    3D occupancy grids, MRF height maps) are a ConfigError naming
///    the `_count` key when their count is > 0.
///
/// Strictness: a `*_count` key in [S] that names no map kind, and any key of
/// a map's own sections that its options do not know, is a ConfigError
/// naming file, section, key and line. Keys MRPT's files carry that have no
/// effect in rove are listed in the load report.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/core/ini.h"
#include "rove/core/config_section.h"
#include "rove/maps/metric_map.h"

namespace rove {

/// One map of a MultiMetricMap with its generic options.
struct MetricMapEntry {
  /// The map (never null).
  std::unique_ptr<MetricMap> map;
  /// Generic options (insertion/likelihood enabled).
  GenericMapParams params;
  /// The section prefix it was configured from (e.g.
  /// "MappingApplication_pointsMap_00"); empty if added in code.
  std::string section_prefix;
  /// Observations this map used (incremented by MultiMetricMap::insert).
  std::size_t observations_inserted = 0;
};

/// What from_config() found besides the maps.
struct MultiMetricMapLoadReport {
  /// Keys present that have no effect in rove.
  std::vector<IgnoredConfigKey> ignored_keys;
};

/// A set of metric maps. Thread-safety: thread-compatible.
class MultiMetricMap final : public MetricMap {
 public:
  /// No maps; likelihood fuses all.
  MultiMetricMap() = default;
  MultiMetricMap(MultiMetricMap&&) noexcept = default;
  MultiMetricMap& operator=(MultiMetricMap&&) noexcept = default;

  /// Builds the maps declared in section `section` of `ini` (see the file
  /// comment). Throws ConfigError (file, section, key) on an unknown or
  /// unsupported kind, a malformed value or an unknown key of a map's
  /// sections; a missing section declares no maps. `report`, if given,
  /// receives the keys without effect.
  static MultiMetricMap from_config(const IniFile& ini, std::string_view section,
                                    MultiMetricMapLoadReport* report = nullptr);

  /// Appends a map. Precondition (InvalidArgument): not null.
  void add(std::unique_ptr<MetricMap> map, GenericMapParams params = {},
           std::string section_prefix = {});
  /// The maps, in creation order.
  const std::vector<MetricMapEntry>& entries() const noexcept { return entries_; }
  /// Number of maps.
  std::size_t size() const noexcept { return entries_.size(); }
  /// The first map of kind `kind` (MetricMap::kind()), or nullptr.
  MetricMap* find(std::string_view kind) noexcept;
  /// As above, const.
  const MetricMap* find(std::string_view kind) const noexcept;

  /// Which maps log_likelihood() consults: std::nullopt = all of them
  /// (mapFuseAll), else only those of this kind (e.g. "occupancyGrid").
  std::optional<std::string> likelihood_selection;

  /// "multiMetricMap".
  std::string_view kind() const noexcept override { return "multiMetricMap"; }
  /// Inserts into every map whose insertion is enabled; true if any used it.
  bool insert(const Observation& observation, const Pose3& T_map_robot) override;
  using MetricMap::insert;
  /// True if some selected map with likelihood enabled can evaluate it.
  bool can_compute_likelihood(const Observation& observation) const override;
  /// Sum of the log-likelihoods of the selected maps with likelihood
  /// enabled that can evaluate the observation (MRPT's fuse-all: the maps
  /// are treated as independent evidence).
  double log_likelihood(const Observation& observation,
                        const Pose3& T_map_robot) const override;
  /// True if every map is empty.
  bool empty() const override;
  /// Clears every map and the insertion counters.
  void clear() override;
  /// Union of the maps' boxes.
  MapBounds bounding_box() const override;
  /// Sum of the maps' element counts (unit "elements").
  MapStatistics statistics() const override;

 private:
  std::vector<MetricMapEntry> entries_;
};

/// The map kinds rove can create from a configuration: their canonical
/// names ("occupancyGrid", "pointsMap", ...).
std::vector<std::string> supported_metric_map_kinds();

/// Creates one map of kind `name` (any MRPT name of the kind) from the
/// sections `<prefix>_creationOpts`, `_insertOpts`, `_likelihoodOpts`, ...,
/// checking that every key of those sections is known. `params` receives the
/// generic options and `ignored` (may be null) the keys without effect.
/// Throws ConfigError naming `count_key` in `count_section` if the kind is
/// unknown or unsupported, and as the options loaders otherwise.
std::unique_ptr<MetricMap> create_metric_map(const IniFile& ini, std::string_view name,
                                             const std::string& prefix, GenericMapParams& params,
                                             std::vector<IgnoredConfigKey>* ignored);

}  // namespace rove
