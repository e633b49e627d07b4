#pragma once
/// \file
/// HeightMap: a 2D grid holding the mean height of the points that fell in
/// each cell (MRPT's CHeightGridMap2D, "mrSimpleAverage" representation),
/// a digital elevation model built from 2D scans (points at the scanner's
/// height and tilt) and 3D range images.
///
/// Geometry as MRPT's CDynamicGrid: cell (cx, cy) covers
/// [x_min + cx·res, x_min + (cx+1)·res) × [y_min + cy·res, ...), with
/// size_x = round((x_max − x_min) / res); points outside the grid are
/// ignored (the grid does not grow). Heights are map-frame z, meters.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/maps/metric_map.h"

namespace rove {

/// One cell: the running mean and variance of the heights inserted in it.
struct HeightCell {
  float mean_z = 0.0f;        ///< mean height, meters (0 while count == 0, as MRPT)
  float variance_z = 0.0f;    ///< sample variance of the heights, m² (0 with < 2 points)
  std::uint32_t count = 0;    ///< points inserted
  double mean = 0.0;          ///< running mean in double (mean_z is its float copy)
  double m2 = 0.0;            ///< Welford's sum of squared deviations (for variance_z)
};

/// Creation options (`<prefix>_creationOpts`, MRPT's defaults).
struct HeightMapCreationOptions {
  double min_x = -2.0;      ///< meters (`min_x`)
  double max_x = 2.0;       ///< meters (`max_x`)
  double min_y = -2.0;      ///< meters (`min_y`)
  double max_y = 2.0;       ///< meters (`max_y`)
  double resolution = 0.1;  ///< cell side, meters (`resolution`)
  /// Loads the keys present; `mapType` must be `mrSimpleAverage` (or 0),
  /// the only representation MRPT's CHeightGridMap2D has. Throws ConfigError
  /// on a malformed value, max <= min or resolution <= 0.
  static HeightMapCreationOptions from_config(const ConfigSection& section);
};

/// Insertion options (`<prefix>_insertOpts`, MRPT's defaults).
struct HeightMapInsertOptions {
  /// Only insert points with z_min <= z <= z_max (map-frame z, as MRPT
  /// applies it to the transformed points) (`filterByHeight`).
  bool filter_by_height = false;
  double z_min = -0.5;  ///< meters (`z_min`)
  double z_max = 0.5;   ///< meters (`z_max`)
  /// Loads the keys present (`colorMap` is accepted and listed as without
  /// effect: it only colors MRPT's 3D view).
  static HeightMapInsertOptions from_config(const ConfigSection& section);
};

/// Likelihood options (`<prefix>_likelihoodOpts`; MRPT's height map has no
/// likelihood, these keys are rove's).
struct HeightMapLikelihoodOptions {
  /// Height noise of an observed point, meters (`sigma_z`).
  double sigma_z = 0.05;
  /// A point in an unobserved or outside cell counts as this many standard
  /// deviations off (`outlier_sigmas`).
  double outlier_sigmas = 3.0;
  /// Use one point in `decimation` (`decimation`, >= 1).
  unsigned decimation = 1;
  /// Loads the keys present.
  static HeightMapLikelihoodOptions from_config(const ConfigSection& section);
};

/// A mean-height grid. Thread-safety: thread-compatible.
class HeightMap final : public MetricMap {
 public:
  /// A grid with the given geometry, every cell unobserved. Preconditions
  /// (InvalidArgument): finite limits, max > min, resolution > 0, at most
  /// 2^31 cells.
  explicit HeightMap(HeightMapCreationOptions creation = {},
                     HeightMapInsertOptions insert_options = {},
                     HeightMapLikelihoodOptions likelihood_options = {});

  /// Insertion options.
  HeightMapInsertOptions insert_options;
  /// Likelihood options.
  HeightMapLikelihoodOptions likelihood_options;

  std::uint32_t size_x() const noexcept { return size_x_; }  ///< cells along x
  std::uint32_t size_y() const noexcept { return size_y_; }  ///< cells along y
  double x_min() const noexcept { return x_min_; }           ///< meters
  double y_min() const noexcept { return y_min_; }           ///< meters
  double resolution() const noexcept { return resolution_; } ///< meters
  /// The cell holding (x, y), or nullptr outside the grid.
  const HeightCell* cell_at(double x, double y) const noexcept;
  /// Cell (cx, cy). Precondition (InvalidArgument): inside the grid.
  const HeightCell& cell(std::uint32_t cx, std::uint32_t cy) const;

  /// Inserts one map-frame point (MRPT's insertIndividualPoint). Returns
  /// false if it lies outside the grid; a point inside but filtered by
  /// height returns true and changes nothing.
  bool insert_point(const Eigen::Vector3d& p_map);

  /// "heightMap".
  std::string_view kind() const noexcept override { return "heightMap"; }
  /// Inserts the points of a RangeScan2D or RangeImage3D (in the map frame:
  /// T_map_robot ⊕ T_robot_sensor ⊕ p). Returns false for other kinds and
  /// for observations without points.
  bool insert(const Observation& observation, const Pose3& T_map_robot) override;
  using MetricMap::insert;
  /// True for RangeScan2D and RangeImage3D.
  bool can_compute_likelihood(const Observation& observation) const override;
  /// Mean over the (decimated) points of −½ (z − mean_z)² / (σ_z² +
  /// variance_z) in observed cells, −½·outlier_sigmas² elsewhere. 0 for an
  /// observation without points or of another kind.
  double log_likelihood(const Observation& observation,
                        const Pose3& T_map_robot) const override;
  /// True until a point has been inserted in some cell.
  bool empty() const override { return observed_cells_ == 0; }
  /// Marks every cell unobserved.
  void clear() override;
  /// Box of the observed cells (x, y) and their mean heights (z).
  MapBounds bounding_box() const override;
  /// Observed cells out of total cells.
  MapStatistics statistics() const override;

 private:
  std::vector<Eigen::Vector3d> observation_points(const Observation& obs,
                                                  const Pose3& T_map_robot) const;
  std::ptrdiff_t index_at(double x, double y) const noexcept;
  std::vector<HeightCell> cells_;
  std::uint32_t size_x_ = 0, size_y_ = 0;
  double x_min_ = 0, y_min_ = 0, resolution_ = 0;
  std::size_t observed_cells_ = 0;
};

}  // namespace rove
