#pragma once
/// \file
/// OdometryObservation: the robot's absolute odometry pose as a sensor
/// reading (MRPT's CObservationOdometry), used in observation-only logs.

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "rove/obs/observation.h"
#include "rove/obs/odometry_data.h"
#include "rove/poses/pose2.h"

namespace rove {

/// Absolute odometry: the pose the robot's odometry integrates, in the
/// odometry frame (its origin is where odometry started; it drifts).
/// Successive readings give increments with `b - a` (Pose2 ⊖).
class OdometryObservation final : public ObservationOf<OdometryObservation> {
 public:
  /// Stored class name: "OdometryObservation".
  static constexpr std::string_view kClassName = "OdometryObservation";

  /// T_odom_robot: the robot's pose in the odometry frame (m, rad).
  Pose2 odometry;
  /// Encoder ticks since the last reading, if the robot reports them.
  std::optional<EncoderTicks> encoder_ticks;
  /// The robot's velocity in its own frame, if reported.
  std::optional<Twist2> velocity;

  /// Identity odometry, no extras.
  OdometryObservation() = default;

  /// Exact equality of every field.
  friend bool operator==(const OdometryObservation& a, const OdometryObservation& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
