#include "rove/nav/simulator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rove/core/check.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/pose3.h"

namespace rove {

namespace {

void check_positive(double v, const char* name) {
  ROVE_CHECK_MSG(std::isfinite(v) && v > 0, "{} must be finite and > 0, got {}", name, v);
}
void check_non_negative(double v, const char* name) {
  ROVE_CHECK_MSG(std::isfinite(v) && v >= 0, "{} must be finite and >= 0, got {}", name, v);
}

// Moves `from` toward `to` by at most `step`.
double approach(double from, double to, double step) { return from + std::clamp(to - from, -step, step); }

}  // namespace

void RobotLimits::check() const {
  check_positive(max_v, "max_v");
  check_positive(max_omega, "max_omega");
  check_positive(max_acc_v, "max_acc_v");
  check_positive(max_acc_omega, "max_acc_omega");
}

void SimulatedLidarOptions::check() const {
  ROVE_CHECK_MSG(rays >= 2 && rays <= 100000, "lidar rays must be in [2, 100000], got {}", rays);
  ROVE_CHECK_MSG(std::isfinite(aperture) && aperture > 0 && aperture <= 2 * std::numbers::pi,
                 "lidar aperture must be in (0, 2 pi], got {}", aperture);
  check_positive(max_range, "lidar max_range");
  check_non_negative(range_sigma, "lidar range_sigma");
}

void SimulatorOptions::check() const {
  limits.check();
  check_positive(robot_radius, "robot_radius");
  check_positive(dt, "dt");
  lidar.check();
  check_non_negative(odometry_sigma_xy, "odometry_sigma_xy");
  check_non_negative(odometry_sigma_phi, "odometry_sigma_phi");
  check_non_negative(odometry_sigma_phi_per_m, "odometry_sigma_phi_per_m");
}

Simulator::Simulator(const NavigationGrid& world, const SE2d& start, SimulatorOptions options)
    : world_(world), options_(std::move(options)), pose_(start), rng_(options_.seed) {
  options_.check();
  const Eigen::Vector2d& t = start.translation();
  ROVE_CHECK_MSG(!touches(start),
                 "the robot (radius {} m) at ({:.3f}, {:.3f}) overlaps an obstacle or the map's edge",
                 options_.robot_radius, t.x(), t.y());
}

bool Simulator::touches(const SE2d& p) const {
  const double r = options_.robot_radius;
  return world_.distance_to_obstacle(p.translation(), r) < r;
}

double Simulator::clearance() const {
  const double r = options_.robot_radius;
  return std::max(0.0, world_.distance_to_obstacle(pose_.translation(), 10.0 + r) - r);
}

SimulatorStep Simulator::step(const VelocityCommand& command) {
  ROVE_CHECK_FINITE(command.vx);
  ROVE_CHECK_FINITE(command.vy);
  ROVE_CHECK_FINITE(command.omega);
  const RobotLimits& lim = options_.limits;
  const double dt = options_.dt;
  // The command within the velocity limits...
  double vx = command.vx, vy = options_.kinematics == RobotKinematics::Holonomic ? command.vy : 0.0;
  const double speed = std::hypot(vx, vy);
  if (speed > lim.max_v) vx *= lim.max_v / speed, vy *= lim.max_v / speed;
  const double omega = std::clamp(command.omega, -lim.max_omega, lim.max_omega);
  // ...reached within the accelerations.
  const double dvx = vx - velocity_.vx, dvy = vy - velocity_.vy, dv = std::hypot(dvx, dvy);
  const double reach = dv > lim.max_acc_v * dt ? lim.max_acc_v * dt / dv : 1.0;
  velocity_.vx += dvx * reach;
  velocity_.vy += dvy * reach;
  velocity_.omega = approach(velocity_.omega, omega, lim.max_acc_omega * dt);

  // The constant twist over the period, in sub-steps of at most 2 cm and
  // 1°, so that no obstacle is jumped over.
  const SE2d before = pose_;
  const double move = std::hypot(velocity_.vx, velocity_.vy) * dt, turn = std::abs(velocity_.omega) * dt;
  const int n = std::max(1, static_cast<int>(std::ceil(std::max(move / 0.02, turn / (std::numbers::pi / 180)))));
  const SE2d delta = SE2d::exp(SE2d::Tangent(velocity_.vx * dt / n, velocity_.vy * dt / n, velocity_.omega * dt / n));
  SimulatorStep s;
  for (int k = 0; k < n; ++k) {
    const SE2d next = pose_ * delta;
    if (touches(next)) {
      s.collided = true;
      ++collisions_;
      velocity_ = Twist2{};
      break;
    }
    pose_ = next;
  }
  time_ += dt;

  // Odometry: the true increment with noise growing with the motion.
  const SE2d inc = before.inverse() * pose_;
  const double d = inc.translation().norm(), dphi = inc.angle();
  std::normal_distribution<double> unit(0.0, 1.0);
  const double sxy = options_.odometry_sigma_xy * d;
  const double sphi = options_.odometry_sigma_phi * std::abs(dphi) + options_.odometry_sigma_phi_per_m * d;
  s.odometry_increment = Pose2(inc.translation().x() + sxy * unit(rng_), inc.translation().y() + sxy * unit(rng_),
                               dphi + sphi * unit(rng_));
  odometry_ = odometry_ + s.odometry_increment;
  s.time = time_;
  s.T_map_robot = pose_;
  s.velocity = velocity_;
  return s;
}

RangeScan2D Simulator::scan() {
  const SimulatedLidarOptions& o = options_.lidar;
  RangeScan2D scan;
  scan.aperture = o.aperture;
  scan.right_to_left = true;
  scan.max_range = static_cast<float>(o.max_range);
  scan.std_error = static_cast<float>(o.range_sigma);
  scan.sensor_label = "LIDAR";
  const SE2d& s = o.T_robot_sensor;
  scan.T_robot_sensor = Pose3(s.translation().x(), s.translation().y(), 0.0, s.angle(), 0.0, 0.0);
  const SE2d T_map_sensor = pose_ * s;
  scan.ranges.resize(static_cast<std::size_t>(o.rays));
  scan.valid.resize(static_cast<std::size_t>(o.rays));
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double a = T_map_sensor.angle() + scan.ray_angle(i);
    const double r = world_.cast_ray(T_map_sensor.translation(), a, o.max_range);
    if (std::isinf(r)) {
      scan.ranges[i] = scan.max_range;
      scan.valid[i] = false;
      continue;
    }
    const double measured = std::max(0.0, r + o.range_sigma * noise(rng_));
    scan.ranges[i] = static_cast<float>(measured);
    scan.valid[i] = measured < o.max_range;
  }
  return scan;
}

void write_simulation_step(RoveRawlogWriter& log, const SimulatorStep& step, const RangeScan2D& scan,
                           Timestamp t0) {
  const Timestamp t = Timestamp::from_ns(t0.ns + static_cast<std::int64_t>(std::llround(step.time * 1e9)));
  auto movement = std::make_shared<RobotMovement2D>(step.odometry_increment, MotionModelOptions{});
  movement->velocity = step.velocity;
  movement->timestamp = t;
  ActionCollection actions;
  actions.add(movement);
  log.write(actions);
  auto observation = std::make_shared<RangeScan2D>(scan);
  observation->timestamp = t;
  SensoryFrame frame;
  frame.add(observation);
  log.write(frame);
}

}  // namespace rove
