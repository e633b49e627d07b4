#pragma once
/// \file
/// OctreeMetricMap: an OccupancyOctree behind the MetricMap interface, as
/// MRPT's COctoMap ("octoMap") and CColouredOctoMap ("colourOctoMap") in a
/// multi-metric map, configured from MRPT's sections:
///  - `<prefix>_creationOpts`: `resolution` (m, default 0.10);
///  - `<prefix>_insertOpts`: `maxrange` (m, −1 = none), `pruning`,
///    `occupancyThres`, `probHit`, `probMiss`, `clampingThresMin`,
///    `clampingThresMax` (OctoMap's defaults);
///  - `<prefix>_likelihoodOpts`: `decimation` (use every n-th point).
///
/// Observations inserted (rays from the sensor to each point, one update per
/// cell and scan, OctoMap's insertPointCloud):
///  - RangeScan2D: its points with MRPT's point-map rules (as MRPT builds
///    them for COctoMap);
///  - RangeImage3D: the points stored with it if any (MRPT's points3D),
///    else its depth image projected; the colour map takes each point's
///    colour from the intensity image (integrated as OctoMap's
///    integrateNodeColor);
///  - VelodyneScan: its stored point cloud, else its raw packets decoded
///    with the calibration it carries (decode_velodyne_scan, every return);
///    a scan with packets but no usable calibration is not inserted and is
///    counted (undecoded_velodyne_scans()).
/// Points at the sensor's origin ((0, 0, 0), MRPT's invalid points), not
/// finite or outside the tree are skipped. Points are mapped with the
/// sensor's pose on the robot, T_map_robot ⊕ T_robot_sensor ⊕ p (MRPT's
/// COctoMap applies only the robot's pose to the points of 3D scans).
/// `pruning = true` prunes after each insertion, as MRPT documents it (MRPT
/// 2.5.8 passes it to OctoMap as lazy_eval, i.e. does the opposite).
///
/// Likelihood (MRPT's computeObservationLikelihood): the sum over the
/// observation's points (every `decimation`-th) that fall in a known cell of
/// log p(occupied) of that cell.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/core/ini.h"
#include "rove/maps/metric_map.h"
#include "rove/maps/occupancy_octree.h"

namespace rove {

/// How observations are inserted (MRPT's COctoMapBase::TInsertionOptions).
struct OctreeMapInsertOptions {
  double max_range = -1.0;        ///< `maxrange`, m; < 0: no limit
  bool pruning = true;            ///< `pruning`: prune after each insertion
  OccupancyOctreeParams sensor;   ///< the probabilities (OctoMap's defaults)
  int num_threads = 1;            ///< threads per insertion (not an MRPT key)
  /// Reads MRPT's keys; ConfigError naming the key for a bad value.
  static OctreeMapInsertOptions from_config(const ConfigSection& section);
};

/// Likelihood options (MRPT's COctoMapBase::TLikelihoodOptions).
struct OctreeMapLikelihoodOptions {
  std::uint32_t decimation = 1;  ///< `decimation`: every n-th point, ≥ 1
  /// Reads `decimation`; ConfigError if < 1.
  static OctreeMapLikelihoodOptions from_config(const ConfigSection& section);
};

/// An octree as a MetricMap. Thread-safety: as OccupancyOctree.
class OctreeMetricMap final : public MetricMap {
 public:
  /// An empty map of cells `resolution` meters wide; `colour` makes the
  /// colour map. Throws InvalidArgument as OccupancyOctree.
  OctreeMetricMap(double resolution, const OctreeMapInsertOptions& insert = {},
                  const OctreeMapLikelihoodOptions& likelihood = {}, bool colour = false);

  /// The tree.
  OccupancyOctree& tree() noexcept { return tree_; }
  /// As above, const.
  const OccupancyOctree& tree() const noexcept { return tree_; }
  /// Insertion options (may be changed; the probabilities take effect for
  /// the next clear()).
  OctreeMapInsertOptions insert_options;
  /// Likelihood options.
  OctreeMapLikelihoodOptions likelihood_options;

  /// "octoMap" or "colourOctoMap".
  std::string_view kind() const noexcept override;
  /// Inserts a RangeScan2D, RangeImage3D or VelodyneScan (see the file
  /// comment); false for other kinds or an observation without points.
  bool insert(const Observation& observation, const Pose3& T_map_robot) override;
  using MetricMap::insert;
  /// True for the kinds insert() takes.
  bool can_compute_likelihood(const Observation& observation) const override;
  /// MRPT's likelihood (see the file comment); 0 for other kinds.
  double log_likelihood(const Observation& observation, const Pose3& T_map_robot) const override;
  bool empty() const override { return tree_.empty(); }  ///< no node
  void clear() override;                                 ///< removes every node
  MapBounds bounding_box() const override;               ///< box of the known cells
  MapStatistics statistics() const override;             ///< occupied leaves, all leaves

  /// Velodyne scans given to insert() whose raw packets could not be
  /// decoded (no calibration, or one for an unsupported sensor).
  std::size_t undecoded_velodyne_scans() const noexcept { return undecoded_velodyne_; }
  /// Why the last of them could not be decoded (empty if none).
  const std::string& undecoded_velodyne_reason() const noexcept { return undecoded_reason_; }

 private:
  OccupancyOctree tree_;
  std::size_t undecoded_velodyne_ = 0;
  std::string undecoded_reason_;
};

/// Factory used by MultiMetricMap (reads and checks `<prefix>_creationOpts`
/// `resolution`, `_insertOpts`, `_likelihoodOpts`).
std::unique_ptr<MetricMap> make_octree_metric_map(const IniFile& ini, const std::string& prefix, bool colour,
                                                  std::vector<IgnoredConfigKey>* ignored);

}  // namespace rove
