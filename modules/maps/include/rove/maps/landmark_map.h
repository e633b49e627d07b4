#pragma once
/// \file
/// LandmarkMap: identified 3D landmarks with Gaussian positions (the parts of
/// MRPT's CLandmarksMap that apply to point landmarks and beacons): built
/// from BearingRange observations, initial beacons from the configuration,
/// and the likelihood of BearingRange and BeaconRanges observations.
///
/// What MRPT's CLandmarksMap does and this class does not: SIFT features
/// from (stereo) images, "occupancy features" from laser scans, GPS and
/// robot-pose likelihoods. Their option keys are accepted from MRPT files
/// and listed as without effect (see rove/core/config_section.h), as is
/// `insert_Landmarks_from_range_scans` when true: laser scans give this map
/// no information (log-likelihood 0).
///
/// Frames and units: landmark positions in the map frame, meters;
/// BearingRange measurements in the sensor frame (x forward, y left, z up;
/// positive pitch below the XY plane), meters and radians.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/maps/beacon_map.h"
#include "rove/core/config_section.h"
#include "rove/maps/metric_map.h"
#include "rove/obs/bearing_range.h"

namespace rove {

/// One landmark.
struct Landmark {
  /// Identifier (from the sensor, or assigned by the map for measurements
  /// with unknown identity).
  std::int32_t id = 0;
  /// Position density in the map frame (meters, m²).
  PointGaussian3 position;
  /// Optional appearance descriptor (free length; empty if none).
  std::vector<float> descriptor;
  /// How many measurements have been fused into it.
  std::uint32_t times_seen = 0;
};

/// Creation options (`<prefix>_creationOpts`): landmarks known beforehand
/// (MRPT's `nBeacons`, `beacon_001_ID`, `beacon_001_X`/`Y`/`Z`, ...), with
/// zero covariance.
struct LandmarkMapCreationOptions {
  /// The initial landmarks.
  std::vector<Landmark> initial;
  /// Loads `nBeacons` and the numbered keys (1-based, three digits).
  static LandmarkMapCreationOptions from_config(const ConfigSection& section);
};

/// Insertion options (`<prefix>_insertOpts`).
struct LandmarkMapInsertOptions {
  /// Insert BearingRange observations (rove: `insert_bearing_range`).
  bool insert_bearing_range = true;
  /// Gate (squared Mahalanobis distance) for associating a measurement
  /// without identifier to an existing landmark; beyond it a new landmark is
  /// created (rove: `association_gate_chi2`; 11.34 = χ²₃ at 99%).
  double association_gate_chi2 = 11.34;
  /// Loads the keys present (lists image-feature keys and a true
  /// `insert_Landmarks_from_range_scans` as without effect).
  static LandmarkMapInsertOptions from_config(const ConfigSection& section);
};

/// Likelihood options (`<prefix>_likelihoodOpts`).
struct LandmarkMapLikelihoodOptions {
  /// Std. dev. of beacon ranges, meters (`beaconRangesStd`).
  double beacon_ranges_std = 0.08;
  /// Use the observation's own std_error instead
  /// (`beaconRangesUseObservationStd`).
  bool beacon_ranges_use_observation_std = false;
  /// Loads the keys present (lists SIFT, GPS and scan keys as without effect).
  static LandmarkMapLikelihoodOptions from_config(const ConfigSection& section);
};

/// A map of landmarks. Thread-safety: thread-compatible.
class LandmarkMap final : public MetricMap {
 public:
  /// A map holding creation.initial.
  explicit LandmarkMap(LandmarkMapCreationOptions creation = {},
                       LandmarkMapInsertOptions insert_options = {},
                       LandmarkMapLikelihoodOptions likelihood_options = {});

  /// Insertion options.
  LandmarkMapInsertOptions insert_options;
  /// Likelihood options.
  LandmarkMapLikelihoodOptions likelihood_options;

  /// The landmarks, in order of creation.
  const std::vector<Landmark>& landmarks() const noexcept { return landmarks_; }
  /// The landmark with identifier `id`, or nullptr.
  const Landmark* find(std::int32_t id) const noexcept;
  /// Adds a landmark, replacing one with the same id. Precondition
  /// (InvalidArgument): finite mean and covariance.
  void add(Landmark landmark);

  /// "landmarksMap".
  std::string_view kind() const noexcept override { return "landmarksMap"; }
  /// Inserts a BearingRange observation: each measurement's point and its
  /// covariance (range/yaw/pitch covariance through the spherical-to-
  /// Cartesian Jacobian and the sensor rotation) is fused with its landmark
  /// by a Kalman update, associated by identifier, or (identifier −1) by
  /// the nearest landmark within the Mahalanobis gate; otherwise it starts
  /// a new landmark. Returns false for other kinds or when disabled.
  bool insert(const Observation& observation, const Pose3& T_map_robot) override;
  using MetricMap::insert;
  /// True for BearingRange and BeaconRanges.
  bool can_compute_likelihood(const Observation& observation) const override;
  /// BeaconRanges: Σ −½((d̂ − d)/σ)² over readings whose beacon is a
  /// landmark (MRPT's CLandmarksMap), the uniform log-density over the
  /// sensor span for the others. BearingRange: Σ −½ νᵀS⁻¹ν with ν the
  /// (range, yaw, pitch) innovation against the landmark (by identifier; for
  /// −1 the most likely landmark) and S = H·C·Hᵀ + R; unmatched
  /// measurements add the uniform log-density over the range span.
  /// 0 for other kinds.
  double log_likelihood(const Observation& observation,
                        const Pose3& T_map_robot) const override;
  /// True when there is no landmark.
  bool empty() const override { return landmarks_.empty(); }
  /// Removes every landmark.
  void clear() override { landmarks_.clear(); }
  /// Box of the landmark means.
  MapBounds bounding_box() const override;
  /// Landmark count.
  MapStatistics statistics() const override;

 private:
  Landmark* find_mutable(std::int32_t id) noexcept;
  std::vector<Landmark> landmarks_;
};

/// A bearing-range measurement as a point in the map frame with its
/// covariance: p = T_map_sensor · r(cos θ cos ψ, cos θ sin ψ, −sin θ),
/// C = R·J·Σ·Jᵀ·Rᵀ with J = ∂p/∂(r, ψ, θ) and Σ the (range, yaw, pitch)
/// covariance. Precondition (InvalidArgument): finite range, yaw, pitch.
PointGaussian3 bearing_range_to_point(const LandmarkMeasurement& m,
                                      const Eigen::Matrix3d& covariance_rng_yaw_pitch,
                                      const Pose3& T_map_sensor);

}  // namespace rove
