#pragma once
/// \file
/// RobotPoseEstimator2D: the robot's latest planar pose from the last
/// localization (e.g. an accepted ICP fix) plus the odometry travelled since,
/// with MRPT's CRobot2DPoseEstimator rules, which ICP-SLAM uses to predict
/// the pose of each new scan:
///  - latest pose = last localization ⊕ (last odometry ⊖ odometry at that
///    localization) when the last odometry is newer than the last
///    localization, else the last localization; before any localization the
///    localization is the origin, so the latest pose is the odometry itself;
///  - the estimate at a time t is the same composition extrapolated to t
///    with the last odometry velocity (zero when the odometry carries none),
///    and is unavailable when the localization is older than
///    max_localization_age or the odometry older than max_odometry_age.
/// Thread-safety: thread-compatible.

#include <optional>

#include "rove/obs/odometry_data.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"

namespace rove {

/// Options of RobotPoseEstimator2D (MRPT's CRobot2DPoseEstimator::TOptions).
struct RobotPoseEstimator2DOptions {
  /// Odometry older than this, seconds, is not extrapolated. > 0. Default 1.
  double max_odometry_age = 1.0;
  /// A localization older than this, seconds, is not extrapolated. > 0. Default 4.
  double max_localization_age = 4.0;
};

/// Tracks the robot pose from localizations and odometry. See the file comment.
class RobotPoseEstimator2D {
 public:
  /// Nothing known yet.
  explicit RobotPoseEstimator2D(RobotPoseEstimator2DOptions options = {});

  /// Forgets every localization and odometry reading.
  void reset();
  /// A new localization T_map_robot taken at `time` (may be invalid).
  void update_localization(const Pose2& T_map_robot, Timestamp time);
  /// A new cumulative odometry reading (odometry frame) at `time`, with the
  /// robot's velocity in its own frame if known.
  void update_odometry(const Pose2& odometry, Timestamp time,
                       const std::optional<Twist2>& velocity = std::nullopt);

  /// The latest pose (see the file comment); nullopt before any reading.
  std::optional<Pose2> latest_pose() const;
  /// The pose extrapolated to `time`; nullopt when there is no localization
  /// or odometry yet, `time` is invalid, or the data is too old.
  std::optional<Pose2> estimate_at(Timestamp time) const;

  /// Moves `pose` for `seconds` at `velocity` (robot frame): a straight line
  /// when the lateral speed exceeds 1 cm/s or the turn rate is below 1e-9
  /// rad/s, else a circular arc (MRPT's extrapolateRobotPose, without its
  /// division by zero when the robot goes straight).
  static Pose2 extrapolate(const Pose2& pose, const Twist2& velocity, double seconds);

 private:
  RobotPoseEstimator2DOptions options_;
  Timestamp last_loc_time_;
  Pose2 last_loc_;
  Pose2 loc_odo_ref_;
  Timestamp last_odo_time_;
  Pose2 last_odo_;
  Twist2 velocity_;
  bool has_loc_ = false;
  bool has_odo_ = false;
};

}  // namespace rove
