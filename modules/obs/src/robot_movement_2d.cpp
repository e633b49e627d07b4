#include "rove/obs/robot_movement_2d.h"

#include "archive_helpers.h"
#include "rove/obs/motion_models.h"
#include "rove/serialization/stl.h"

namespace rove {

RobotMovement2D::RobotMovement2D(const Pose2& increment, const MotionModelOptions& options)
    : odometry_increment(increment), motion_model(options) {
  motion_model.check();
}

Pose2 RobotMovement2D::mean() const {
  return estimated_pose_change ? estimated_pose_change->mean() : odometry_increment;
}

Pose2Gaussian RobotMovement2D::gaussian() const {
  if (estimated_pose_change) return *estimated_pose_change;
  return gaussian_motion_model(odometry_increment, motion_model.gaussian);
}

Pose2Particles RobotMovement2D::particles(std::mt19937_64& rng) const {
  return thrun_motion_particles(odometry_increment, motion_model.thrun, rng);
}

Pose2 RobotMovement2D::sample(std::mt19937_64& rng) const {
  if (estimated_pose_change) return estimated_pose_change->sample(rng);
  if (motion_model.model == MotionModel::Thrun) {
    return sample_thrun_motion(odometry_increment, motion_model.thrun, rng);
  }
  return gaussian_motion_model(odometry_increment, motion_model.gaussian).sample(rng);
}

bool operator==(const RobotMovement2D& a, const RobotMovement2D& b) {
  const bool same_estimate =
      a.estimated_pose_change.has_value() == b.estimated_pose_change.has_value() &&
      (!a.estimated_pose_change ||
       (a.estimated_pose_change->mean() == b.estimated_pose_change->mean() &&
        a.estimated_pose_change->covariance() == b.estimated_pose_change->covariance()));
  return a.timestamp == b.timestamp && a.odometry_increment == b.odometry_increment &&
         a.motion_model == b.motion_model && same_estimate && a.encoder_ticks == b.encoder_ticks &&
         a.velocity == b.velocity;
}

void RobotMovement2D::save_payload(OutArchive& ar) const {
  save_header(ar);
  detail::save_pose2(ar, odometry_increment);
  save(ar, motion_model);
  ar.write_scalar(estimated_pose_change.has_value());
  if (estimated_pose_change) detail::save_pose2_gaussian(ar, *estimated_pose_change);
  save(ar, encoder_ticks);
  save(ar, velocity);
}

void RobotMovement2D::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  odometry_increment = detail::load_pose2(ar, "odometry_increment");
  load(ar, motion_model);
  if (ar.read_scalar<bool>("has estimated_pose_change")) {
    estimated_pose_change = detail::load_pose2_gaussian(ar, "estimated_pose_change");
  } else {
    estimated_pose_change.reset();
  }
  load(ar, encoder_ticks);
  load(ar, velocity);
}

std::unique_ptr<Action> RobotMovement2D::clone() const {
  return std::make_unique<RobotMovement2D>(*this);
}

bool RobotMovement2D::equals(const Action& other) const {
  const auto* o = dynamic_cast<const RobotMovement2D*>(&other);
  return o != nullptr && *this == *o;
}

std::shared_ptr<const RobotMovement2D> best_movement_2d(const ActionCollection& actions) {
  std::shared_ptr<const RobotMovement2D> best;
  double best_det = 0.0;
  for (const auto& a : actions.actions) {
    auto m = std::dynamic_pointer_cast<const RobotMovement2D>(a);
    if (!m) continue;
    const double det = m->gaussian().covariance().determinant();
    if (!best || det < best_det) {
      best = std::move(m);
      best_det = det;
    }
  }
  return best;
}

}  // namespace rove
