#pragma once
/// \file
/// BearingRange: range and bearing to identified landmarks (MRPT's
/// CObservationBearingRange), the input of EKF landmark SLAM.
///
/// Sensor frame: x forward, y left, z up. A landmark at range r, yaw ψ,
/// pitch θ lies at r·(cos θ cos ψ, cos θ sin ψ, −sin θ) (positive pitch
/// points below the XY plane, as rove's Pose3 and MRPT).

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/observation.h"
#include "rove/poses/angle.h"

namespace rove {

/// One landmark measurement.
struct LandmarkMeasurement {
  /// Landmark identifier; -1 if unknown (data association left to the user).
  std::int32_t landmark_id = -1;
  /// Distance, meters.
  float range = 0.0f;
  /// Bearing about z, radians (counter-clockwise positive).
  float yaw = 0.0f;
  /// Elevation, radians (positive below the XY plane).
  float pitch = 0.0f;
  /// Covariance of (range, yaw, pitch) if the sensor gives one per reading
  /// (m², rad²); otherwise the observation's sensor std devs apply.
  std::optional<Eigen::Matrix3d> covariance;

  /// The measured point in the sensor frame, meters.
  Eigen::Vector3d point_in_sensor() const;
  /// Exact equality.
  friend bool operator==(const LandmarkMeasurement&, const LandmarkMeasurement&) = default;
};

/// Landmarks seen at once by one sensor.
class BearingRange final : public ObservationOf<BearingRange> {
 public:
  /// Stored class name: "BearingRange".
  static constexpr std::string_view kClassName = "BearingRange";

  /// The measurements.
  std::vector<LandmarkMeasurement> measurements;
  /// Shortest measurable distance, meters.
  float min_sensor_distance = 0.0f;
  /// Longest measurable distance, meters.
  float max_sensor_distance = 10.0f;
  /// Full horizontal field of view, radians (centered on +x).
  float field_of_view_yaw = static_cast<float>(kPi);
  /// Full vertical field of view, radians (centered on the XY plane).
  float field_of_view_pitch = static_cast<float>(kPi / 2);
  /// Range standard deviation, meters.
  float sensor_std_range = 0.0f;
  /// Yaw standard deviation, radians.
  float sensor_std_yaw = 0.0f;
  /// Pitch standard deviation, radians.
  float sensor_std_pitch = 0.0f;

  /// No measurements.
  BearingRange() = default;

  /// The diagonal covariance of (range, yaw, pitch) from the sensor std
  /// devs, or the reading's own covariance if it has one.
  /// Precondition (InvalidArgument): i < measurements.size().
  Eigen::Matrix3d measurement_covariance(std::size_t i) const;

  /// Exact equality of every field.
  friend bool operator==(const BearingRange& a, const BearingRange& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

/// Writes a LandmarkMeasurement (versioned record).
void save(OutArchive& ar, const LandmarkMeasurement& m);
/// Reads a LandmarkMeasurement written by save.
void load(InArchive& ar, LandmarkMeasurement& m);

}  // namespace rove
