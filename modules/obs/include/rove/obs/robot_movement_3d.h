#pragma once
/// \file
/// RobotMovement3D: a 6-DoF motion increment with Gaussian uncertainty
/// (MRPT's CActionRobotMovement3D), e.g. from wheel or visual odometry.

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "rove/obs/action.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/serialization/archive.h"

namespace rove {

/// A 3D velocity in the robot frame: linear (m/s) and angular (rad/s)
/// (MRPT's TTwist3D, same order).
struct Twist3 {
  double vx = 0.0;  ///< forward, m/s
  double vy = 0.0;  ///< left, m/s
  double vz = 0.0;  ///< up, m/s
  double wx = 0.0;  ///< about x, rad/s
  double wy = 0.0;  ///< about y, rad/s
  double wz = 0.0;  ///< about z, rad/s
  /// Exact equality.
  friend bool operator==(const Twist3&, const Twist3&) = default;
};

/// Writes a Twist3 (versioned record).
void save(OutArchive& ar, const Twist3& t);
/// Reads a Twist3 written by save.
void load(InArchive& ar, Twist3& t);

/// How a RobotMovement3D was estimated (MRPT's TEstimationMethod).
enum class Movement3DSource : std::uint8_t {
  Odometry = 0,        ///< wheel/inertial odometry
  VisualOdometry = 1,  ///< visual odometry
};

/// The robot's pose change between two sensory frames, as a Gaussian in the
/// robot frame at the start of the motion (T_start_end ± covariance, order
/// x, y, z, yaw, pitch, roll as MRPT).
class RobotMovement3D final : public Action {
 public:
  /// Stored class name: "RobotMovement3D".
  static constexpr std::string_view kClassName = "RobotMovement3D";

  /// The pose increment with its covariance.
  Pose3Gaussian pose_change;
  /// How the increment was estimated.
  Movement3DSource source = Movement3DSource::Odometry;
  /// The robot's velocity at the end of the motion, if any component is
  /// known; unknown components are NaN (MRPT flags each one).
  std::optional<Twist3> velocity;

  /// A zero motion with zero covariance.
  RobotMovement3D() = default;

  /// Exact equality of every field.
  friend bool operator==(const RobotMovement3D& a, const RobotMovement3D& b);

  /// The stored class name (kClassName).
  std::string_view class_name() const override { return kClassName; }
  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
  /// A deep copy.
  std::unique_ptr<Action> clone() const override;
  /// Same dynamic type and operator==.
  bool equals(const Action& other) const override;
};

}  // namespace rove
