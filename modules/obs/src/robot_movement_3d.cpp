#include "rove/obs/robot_movement_3d.h"

#include <string>

#include "archive_helpers.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {

void save(OutArchive& ar, const Twist3& t) {
  write_version(ar, 1);
  for (double v : {t.vx, t.vy, t.vz, t.wx, t.wy, t.wz}) ar.write_scalar(v);
}

void load(InArchive& ar, Twist3& t) {
  read_version(ar, "Twist3", 1);
  for (double* v : {&t.vx, &t.vy, &t.vz, &t.wx, &t.wy, &t.wz}) *v = ar.read_scalar<double>("Twist3");
}

bool operator==(const RobotMovement3D& a, const RobotMovement3D& b) {
  return a.timestamp == b.timestamp && a.pose_change.mean() == b.pose_change.mean() &&
         a.pose_change.covariance() == b.pose_change.covariance() && a.source == b.source &&
         a.velocity == b.velocity;
}

void RobotMovement3D::save_payload(OutArchive& ar) const {
  save_header(ar);
  detail::save_pose3(ar, pose_change.mean());
  const auto& C = pose_change.covariance();
  ar.write_scalars(std::span<const double>(C.data(), 36));
  ar.write_scalar(static_cast<std::uint8_t>(source));
  save(ar, velocity);
}

void RobotMovement3D::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  const Pose3 mean = detail::load_pose3(ar, "pose_change.mean");
  const std::uint64_t at = ar.offset();
  Pose3Gaussian::Matrix C;
  ar.read_scalars(std::span<double>(C.data(), 36), "pose_change.covariance");
  pose_change = parse_guard(ar, at, "pose_change.covariance",
                                    [&] { return Pose3Gaussian(mean, C); });
  const std::uint64_t source_at = ar.offset();
  const auto s = ar.read_scalar<std::uint8_t>("source");
  if (s > 1) ar.fail_at(source_at, "source", "unknown movement source " + std::to_string(s));
  source = static_cast<Movement3DSource>(s);
  load(ar, velocity);
}

std::unique_ptr<Action> RobotMovement3D::clone() const {
  return std::make_unique<RobotMovement3D>(*this);
}

bool RobotMovement3D::equals(const Action& other) const {
  const auto* o = dynamic_cast<const RobotMovement3D*>(&other);
  return o != nullptr && *this == *o;
}

}  // namespace rove
