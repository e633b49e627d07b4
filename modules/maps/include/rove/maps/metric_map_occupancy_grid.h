#pragma once
/// \file
/// OccupancyGridMetricMap: an OccupancyGrid (occupancy_grid.h) behind the
/// MetricMap interface, configured as MRPT's COccupancyGridMap2D in a
/// multi-metric map: `<prefix>_creationOpts` (`min_x`, `max_x`, `min_y`,
/// `max_y`, `resolution`; MRPT's defaults ±10 m, 0.10 m), `<prefix>_insertOpts`
/// (GridInsertionOptions, MRPT's keys) and `<prefix>_likelihoodOpts`.
///
/// Likelihood: GridLikelihoodModel (grid_likelihood.h) with the options of
/// `<prefix>_likelihoodOpts` (MRPT's seven methods and keys). The model is
/// rebuilt lazily when the grid changed, so the first log_likelihood()
/// after an insertion must not run concurrently with others.

#include <memory>
#include <string>
#include <vector>

#include "rove/core/ini.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/core/config_section.h"
#include "rove/maps/metric_map.h"
#include "rove/maps/occupancy_grid.h"

namespace rove {

/// Geometry of a new grid (`<prefix>_creationOpts`), MRPT's
/// COccupancyGridMap2D::TMapDefinition defaults.
struct OccupancyGridCreationOptions {
  float min_x = -10.0f;     ///< meters
  float max_x = 10.0f;      ///< meters
  float min_y = -10.0f;     ///< meters
  float max_y = 10.0f;      ///< meters
  float resolution = 0.10f; ///< cell side, meters
  /// Where these came from, for messages ("[prefix_creationOpts]"); empty
  /// when set in code.
  std::string origin;
  /// Loads the keys present; ConfigError on max <= min or resolution <= 0
  /// or not finite, and on a grid beyond 2^31 cells; ResourceError naming
  /// the section and `resolution` when the grid exceeds the memory budget.
  static OccupancyGridCreationOptions from_config(const ConfigSection& section);
};

/// An occupancy grid as a MetricMap. Thread-safety: thread-compatible.
class OccupancyGridMetricMap final : public MetricMap {
 public:
  /// A grid of the given geometry, all cells unknown.
  explicit OccupancyGridMetricMap(OccupancyGridCreationOptions creation = {},
                                  GridInsertionOptions insert_options = {},
                                  GridLikelihoodOptions likelihood_options = {});
  ~OccupancyGridMetricMap() override;
  /// The grid.
  const OccupancyGrid& grid() const noexcept { return grid_; }
  /// Mutable grid (e.g. to load one).
  OccupancyGrid& grid() noexcept { return grid_; }
  /// Scan insertion options.
  GridInsertionOptions insert_options;
  /// Likelihood options (changing them takes effect on the next
  /// log_likelihood() after an insertion or clear()).
  GridLikelihoodOptions likelihood_options;

  /// "occupancyGrid".
  std::string_view kind() const noexcept override { return "occupancyGrid"; }
  /// Inserts a RangeScan2D by ray casting (insert_scan); false for other
  /// kinds and for scans insert_scan declines (not horizontal, off the map
  /// plane). A grid that would grow beyond the memory budget throws
  /// ResourceError naming the creation section and its resolution.
  bool insert(const Observation& observation, const Pose3& T_map_robot) override;
  using MetricMap::insert;
  /// True for RangeScan2D.
  bool can_compute_likelihood(const Observation& observation) const override;
  /// The scan's log-likelihood with the configured method (MRPT's
  /// computeObservationLikelihood); 0 for other kinds.
  double log_likelihood(const Observation& observation,
                        const Pose3& T_map_robot) const override;
  /// True until a scan has been inserted.
  bool empty() const override { return grid_.empty(); }
  /// Restores the creation geometry with every cell unknown.
  void clear() override;
  /// The grid's extent (z = 0) when not empty.
  MapBounds bounding_box() const override;
  /// Cells whose probability differs from 0.5 (observed), of all cells.
  MapStatistics statistics() const override;

 private:
  OccupancyGridCreationOptions creation_;
  OccupancyGrid grid_;
  mutable std::unique_ptr<GridLikelihoodModel<std::int8_t>> model_;
  mutable std::uint64_t model_revision_ = 0;
};

/// Factory used by MultiMetricMap: reads the creation, insertion and
/// likelihood sections of `prefix`, checking for unknown keys.
std::unique_ptr<MetricMap> make_occupancy_grid_metric_map(const IniFile& ini,
                                                          const std::string& prefix,
                                                          std::vector<IgnoredConfigKey>* ignored);

}  // namespace rove
