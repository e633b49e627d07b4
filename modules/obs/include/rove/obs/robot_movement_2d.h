#pragma once
/// \file
/// RobotMovement2D: a planar robot motion measured by odometry, with its
/// probabilistic motion model (MRPT's CActionRobotMovement2D).

#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string_view>

#include "rove/obs/action.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/motion_model_options.h"
#include "rove/obs/odometry_data.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_particles.h"
#include "rove/poses/pose2.h"

namespace rove {

/// A pose increment u = (Δx, Δy, Δφ) in the robot frame at the start of the
/// motion (m, rad), with the motion model that turns it into a PDF.
///
/// If `estimated_pose_change` is set (MRPT's emScan2DMatching: the change
/// was estimated by other means, e.g. scan matching), that Gaussian is the
/// PDF and the motion model is not used.
class RobotMovement2D final : public Action {
 public:
  /// Stored class name: "RobotMovement2D".
  static constexpr std::string_view kClassName = "RobotMovement2D";

  /// The raw odometry increment (MRPT's rawOdometryIncrementReading).
  Pose2 odometry_increment;
  /// Motion model and its parameters (MRPT's motionModelConfiguration).
  MotionModelOptions motion_model;
  /// An externally estimated PDF of the change, replacing the model.
  std::optional<Pose2Gaussian> estimated_pose_change;
  /// Encoder ticks during the motion, if known.
  std::optional<EncoderTicks> encoder_ticks;
  /// Velocity at the end of the motion in the robot frame, if known.
  std::optional<Twist2> velocity;

  /// A zero increment with default options.
  RobotMovement2D() = default;
  /// From an odometry increment and the model to use. Throws
  /// InvalidArgument if the options fail their check.
  RobotMovement2D(const Pose2& increment, const MotionModelOptions& options);

  /// The mean change: estimated_pose_change's mean if set, else the
  /// odometry increment.
  Pose2 mean() const;
  /// The Gaussian PDF: estimated_pose_change if set, else
  /// gaussian_motion_model(odometry_increment, motion_model.gaussian)
  /// (whatever motion_model.model selects).
  Pose2Gaussian gaussian() const;
  /// Thrun particles (thrun_motion_particles with motion_model.thrun).
  Pose2Particles particles(std::mt19937_64& rng) const;
  /// One sample of the change: from estimated_pose_change if set, else
  /// from the selected model (Gaussian PDF sample, or sample_thrun_motion).
  Pose2 sample(std::mt19937_64& rng) const;

  /// Exact equality of every field.
  friend bool operator==(const RobotMovement2D& a, const RobotMovement2D& b);

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

/// The 2D movement of `actions` with the smallest covariance determinant
/// (MRPT's CActionCollection::getBestMovementEstimation), or nullptr when
/// it holds none.
std::shared_ptr<const RobotMovement2D> best_movement_2d(const ActionCollection& actions);

}  // namespace rove
