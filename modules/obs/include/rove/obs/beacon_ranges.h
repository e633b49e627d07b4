#pragma once
/// \file
/// BeaconRanges: distances to identified radio/ultrasonic beacons (MRPT's
/// CObservationBeaconRanges), the input of range-only localization/SLAM.

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/observation.h"

namespace rove {

/// One range measurement to one beacon.
struct BeaconRange {
  /// The beacon's identifier.
  std::int32_t beacon_id = 0;
  /// Measured distance from the receiving antenna to the beacon, meters.
  float range = 0.0f;
  /// Where the receiving antenna sits on the robot (robot frame, meters);
  /// MRPT's `sensorLocationOnRobot`. Each reading may come from a different
  /// antenna, so this replaces T_robot_sensor's translation.
  Eigen::Vector3d position_on_robot = Eigen::Vector3d::Zero();
  /// Exact equality.
  friend bool operator==(const BeaconRange&, const BeaconRange&) = default;
};

/// A position estimate some beacon systems (e.g. UWB) compute themselves and
/// attach to their readings (MRPT's auxEstimatePose), in the map frame.
struct BeaconAuxEstimate {
  double x_m = 0.0;  ///< meters
  double y_m = 0.0;  ///< meters
  /// Heading, radians, if the system estimated one (MRPT writes −inf when
  /// it did not).
  std::optional<double> heading_rad;
  /// Exact equality.
  friend bool operator==(const BeaconAuxEstimate&, const BeaconAuxEstimate&) = default;
};

/// Ranges to several beacons taken at once.
class BeaconRanges final : public ObservationOf<BeaconRanges> {
 public:
  /// Stored class name: "BeaconRanges".
  static constexpr std::string_view kClassName = "BeaconRanges";

  /// The measurements.
  std::vector<BeaconRange> readings;
  /// Shortest distance the sensor can measure, meters.
  float min_sensor_distance = 0.0f;
  /// Longest distance the sensor can measure, meters.
  float max_sensor_distance = 1e2f;
  /// Standard deviation of a range, meters (MRPT's `stdError`).
  float std_error = 1e-2f;
  /// The beacon system's own position estimate, if it gave one (version 2).
  std::optional<BeaconAuxEstimate> aux_estimate;

  /// No readings.
  BeaconRanges() = default;

  /// The range to beacon `id`, if measured (the first such reading).
  std::optional<float> range_to(std::int32_t id) const;

  /// Exact equality of every field.
  friend bool operator==(const BeaconRanges& a, const BeaconRanges& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 2; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

/// Writes a BeaconRange (versioned record).
void save(OutArchive& ar, const BeaconRange& r);
/// Reads a BeaconRange written by save.
void load(InArchive& ar, BeaconRange& r);

}  // namespace rove
