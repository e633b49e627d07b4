#include "rove/slam/robot_pose_estimator_2d.h"

#include <cmath>

#include "rove/core/check.h"

namespace rove {

RobotPoseEstimator2D::RobotPoseEstimator2D(RobotPoseEstimator2DOptions options)
    : options_(options) {
  ROVE_CHECK_GT(options_.max_odometry_age, 0.0);
  ROVE_CHECK_GT(options_.max_localization_age, 0.0);
}

void RobotPoseEstimator2D::reset() { *this = RobotPoseEstimator2D(options_); }

void RobotPoseEstimator2D::update_localization(const Pose2& T_map_robot, Timestamp time) {
  last_loc_time_ = time;
  last_loc_ = T_map_robot;
  has_loc_ = true;
  // The odometry "at" this localization: the last reading moved on to the
  // localization's time, so later readings count from there.
  if (has_odo_) {
    double dt = 0.0;
    if (time.valid() && last_odo_time_.valid()) dt = seconds_between(last_odo_time_, time);
    loc_odo_ref_ = extrapolate(last_odo_, velocity_, dt);
  }
}

void RobotPoseEstimator2D::update_odometry(const Pose2& odometry, Timestamp time,
                                           const std::optional<Twist2>& velocity) {
  // Without velocities none are made up (MRPT 2.x): extrapolation is a no-op.
  velocity_ = velocity.value_or(Twist2{});
  last_odo_time_ = time;
  last_odo_ = odometry;
  has_odo_ = true;
}

std::optional<Pose2> RobotPoseEstimator2D::latest_pose() const {
  if (!has_odo_ && !has_loc_) return std::nullopt;
  bool use_odo = false;
  if (has_odo_ && has_loc_) {
    use_odo = last_odo_time_ > last_loc_time_;
  } else {
    use_odo = has_odo_;
  }
  if (use_odo) return last_loc_ + (last_odo_ - loc_odo_ref_);
  return last_loc_;
}

std::optional<Pose2> RobotPoseEstimator2D::estimate_at(Timestamp time) const {
  if (!has_odo_ || !has_loc_ || !time.valid() || !last_loc_time_.valid() ||
      !last_odo_time_.valid()) {
    return std::nullopt;
  }
  if (std::abs(seconds_between(last_loc_time_, time)) > options_.max_localization_age) {
    return std::nullopt;
  }
  const double dt_odo = std::abs(seconds_between(last_odo_time_, time));
  if (dt_odo > options_.max_odometry_age) return std::nullopt;
  const Pose2 p = last_loc_ + (last_odo_ - loc_odo_ref_);
  return extrapolate(p, velocity_, dt_odo);
}

Pose2 RobotPoseEstimator2D::extrapolate(const Pose2& pose, const Twist2& v, double seconds) {
  if (v.vx == 0.0 && v.vy == 0.0 && v.omega == 0.0) return pose;
  if (std::abs(v.vy) > 1e-2 || std::abs(v.omega) < 1e-9) {
    return pose + Pose2(seconds * v.vx, seconds * v.vy, seconds * v.omega);
  }
  const double radius = v.vx / v.omega;
  const double theta = v.omega * seconds;
  return pose + Pose2(radius * std::sin(theta), radius * (1.0 - std::cos(theta)), theta);
}

}  // namespace rove
