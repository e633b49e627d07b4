#pragma once
/// \file
/// ImuObservation: one inertial measurement (MRPT's CObservationIMU, its
/// commonly present fields). Vectors are in the IMU's sensor frame, whose
/// pose on the robot is T_robot_sensor.

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/obs/observation.h"

namespace rove {

/// Angular velocity, linear acceleration and orientation, each present only
/// if the device reported it.
class ImuObservation final : public ObservationOf<ImuObservation> {
 public:
  /// Stored class name: "ImuObservation".
  static constexpr std::string_view kClassName = "ImuObservation";

  /// Angular velocity (ωx, ωy, ωz), rad/s, sensor frame.
  std::optional<Eigen::Vector3d> angular_velocity;
  /// Specific force (ax, ay, az), m/s² (a resting IMU reads +g upward),
  /// sensor frame.
  std::optional<Eigen::Vector3d> linear_acceleration;
  /// Orientation q_world_sensor from the device's own filter, a unit
  /// quaternion (w, x, y, z).
  std::optional<Eigen::Quaterniond> orientation;

  /// No data present.
  ImuObservation() = default;

  /// Throws InvalidArgument if a present vector is not finite or the
  /// orientation is not a finite unit quaternion (|‖q‖ − 1| <= 1e-6).
  void check() const;

  /// Exact equality of every field.
  friend bool operator==(const ImuObservation& a, const ImuObservation& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
