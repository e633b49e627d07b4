#pragma once
/// \file
/// PointsMetricMap: a PointMap (point_map.h) behind the MetricMap
/// interface, configured as MRPT's point maps in a multi-metric map
/// (CSimplePointsMap, CColouredPointsMap, CWeightedPointsMap,
/// CPointsMapXYZI): `<prefix>_insertOpts` and `<prefix>_likelihoodOpts`
/// with MRPT's keys and defaults (PointMap implements MRPT's insertion and
/// likelihood); `<prefix>_renderOpts` / `_colorOpts` are accepted and
/// listed as without effect (they only style MRPT's 3D view).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rove/core/ini.h"
#include "rove/core/config_section.h"
#include "rove/maps/metric_map.h"
#include "rove/maps/point_map.h"

namespace rove {

/// Which MRPT point-map class a PointsMetricMap stands for.
enum class PointsMapFlavor : std::uint8_t {
  Simple = 0,     ///< CSimplePointsMap ("pointsMap")
  Coloured = 1,   ///< CColouredPointsMap ("colourPointsMap"): color channel
  Weighted = 2,   ///< CWeightedPointsMap ("weightedPointsMap")
  Intensity = 3,  ///< CPointsMapXYZI: intensity channel
};

/// A point map as a MetricMap. Thread-safety: as PointMap.
class PointsMetricMap final : public MetricMap {
 public:
  /// An empty map.
  explicit PointsMetricMap(PointsMapFlavor flavor = PointsMapFlavor::Simple);
  /// The map (its insertion_options / likelihood_options may be changed).
  PointMap& points() noexcept { return map_; }
  /// As above, const.
  const PointMap& points() const noexcept { return map_; }
  /// The MRPT class this map stands for.
  PointsMapFlavor flavor() const noexcept { return flavor_; }

  /// "pointsMap", "colourPointsMap", "weightedPointsMap" or "pointsMapXYZI".
  std::string_view kind() const noexcept override;
  /// Inserts a RangeScan2D or RangeImage3D (PointMap::insert).
  bool insert(const Observation& observation, const Pose3& T_map_robot) override;
  using MetricMap::insert;
  /// True for RangeScan2D and RangeImage3D.
  bool can_compute_likelihood(const Observation& observation) const override;
  /// MRPT's point-map likelihood (PointMap::log_likelihood); 0 for other
  /// kinds.
  double log_likelihood(const Observation& observation,
                        const Pose3& T_map_robot) const override;
  bool empty() const override { return map_.empty(); }    ///< no point
  void clear() override;                                    ///< removes every point
  MapBounds bounding_box() const override;                 ///< box of the points
  MapStatistics statistics() const override;               ///< point count

 private:
  PointsMapFlavor flavor_;
  PointMap map_;
};

/// Factory used by MultiMetricMap (reads and checks `<prefix>_insertOpts`,
/// `_likelihoodOpts`, `_renderOpts`, `_colorOpts`).
std::unique_ptr<MetricMap> make_points_metric_map(const IniFile& ini, const std::string& prefix,
                                                  PointsMapFlavor flavor,
                                                  std::vector<IgnoredConfigKey>* ignored);

}  // namespace rove
