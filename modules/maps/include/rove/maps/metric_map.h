#pragma once
/// \file
/// MetricMap: the run-time interface of every map a multi-metric map holds
/// (MRPT's CMetricMap). The concrete kind is chosen at run time from a
/// configuration file, so this is a virtual interface (STYLE.md item 4);
/// code that knows its map type uses the concrete class directly.
///
/// Frames and units: every pose given to a map is T_map_robot (the robot in
/// the map frame; meters, radians); each observation carries its own
/// T_robot_sensor. Log-likelihoods are natural logarithms, up to a constant
/// that depends on the map kind (MRPT's convention: maps are compared with
/// themselves across poses, not with each other).

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/observation.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/pose3.h"

namespace rove {

/// An axis-aligned box in the map frame, meters. Empty when min > max on
/// any axis (the box of a map that holds nothing).
struct MapBounds {
  /// Lower corner.
  Eigen::Vector3d min = Eigen::Vector3d::Constant(1.0);
  /// Upper corner.
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-1.0);
  /// True when the box contains nothing.
  bool empty() const noexcept { return (min.array() > max.array()).any(); }
  /// Grows the box to contain p.
  void extend(const Eigen::Vector3d& p) noexcept {
    if (empty()) {
      min = max = p;
    } else {
      min = min.cwiseMin(p);
      max = max.cwiseMax(p);
    }
  }
  /// Grows the box to contain `other` (no change if it is empty).
  void extend(const MapBounds& other) noexcept {
    if (other.empty()) return;
    extend(other.min);
    extend(other.max);
  }
};

/// What a map holds, for summaries: one count with its unit ("cells",
/// "points", "beacons", "landmarks") and the covered box.
struct MapStatistics {
  /// Number of elements (occupied/observed cells, points, beacons, ...).
  std::size_t elements = 0;
  /// What `elements` counts.
  std::string unit;
  /// Total cells of a grid map (0 for non-grid maps).
  std::size_t total_cells = 0;
  /// The map's bounding box.
  MapBounds bounds;
};

/// The options every map of a multi-metric map has (MRPT's
/// TMapGenericParams, read from `<prefix>_creationOpts`).
struct GenericMapParams {
  /// Observations are inserted into this map (`enableObservationInsertion`).
  bool enable_insertion = true;
  /// This map takes part in likelihood evaluation
  /// (`enableObservationLikelihood`).
  bool enable_likelihood = true;
  /// The map is included when a 3D view is exported (`enableSaveAs3DObject`).
  bool enable_save_3d = true;
};

/// A map that observations can be inserted into and evaluated against.
/// Thread-safety: thread-compatible (concurrent const calls are safe unless
/// the concrete class says otherwise).
class MetricMap {
 public:
  virtual ~MetricMap() = default;

  /// The kind, as MRPT's short class alias: "occupancyGrid", "pointsMap",
  /// "beaconMap", "landmarksMap", "heightMap", ...
  virtual std::string_view kind() const noexcept = 0;

  /// Inserts `observation` taken with the robot at `T_map_robot`. Returns
  /// true if the map used it, false if this map kind ignores that kind of
  /// observation (or the options exclude it). Throws InvalidArgument on an
  /// observation that is internally inconsistent.
  virtual bool insert(const Observation& observation, const Pose3& T_map_robot) = 0;

  /// Inserts every observation of `frame`; returns how many were used.
  std::size_t insert(const SensoryFrame& frame, const Pose3& T_map_robot);

  /// True if log_likelihood() gives information about this kind of
  /// observation (MRPT's canComputeObservationLikelihood).
  virtual bool can_compute_likelihood(const Observation& observation) const = 0;

  /// The log-likelihood of `observation` if the robot were at `T_map_robot`
  /// (MRPT's computeObservationLikelihood). 0 for an observation kind the
  /// map gives no information about (see can_compute_likelihood).
  virtual double log_likelihood(const Observation& observation,
                                const Pose3& T_map_robot) const = 0;

  /// True if nothing has been inserted (or loaded) since creation/clear().
  virtual bool empty() const = 0;

  /// Removes the content, keeping the options.
  virtual void clear() = 0;

  /// The box holding the map's content; empty() if there is none.
  virtual MapBounds bounding_box() const = 0;

  /// Element counts for summaries.
  virtual MapStatistics statistics() const = 0;

 protected:
  MetricMap() = default;
  MetricMap(const MetricMap&) = default;
  MetricMap& operator=(const MetricMap&) = default;
};

}  // namespace rove
