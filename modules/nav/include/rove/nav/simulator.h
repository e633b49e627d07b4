#pragma once
/// \file
/// A 2D robot simulator for testing navigation without hardware: a disc
/// robot (differential drive or holonomic) with velocity and acceleration
/// limits moving in the obstacles of a NavigationGrid, a 2D lidar ray-cast
/// in the same grid with Gaussian range noise, and odometry with noise
/// proportional to the motion. Every step can go to a rove rawlog (an
/// odometry action and a sensory frame with the scan), so a run can be
/// replayed, localized and mapped by the rest of rove.
///
/// Frames and units: the map frame of the grid; the robot frame x forward,
/// y left; meters, radians, seconds, m/s, rad/s.

#include <cstdint>
#include <memory>
#include <random>
#include <string_view>

#include "rove/core/config_section.h"
#include "rove/io/rove_rawlog.h"
#include "rove/math/se2.h"
#include "rove/nav/navigation_grid.h"
#include "rove/obs/odometry_data.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose2.h"

namespace rove {

/// How the robot moves.
enum class RobotKinematics : std::uint8_t {
  DifferentialDrive,  ///< forward speed and turn rate (no sideways motion)
  Holonomic,          ///< any planar velocity and turn rate
};

/// A velocity command in the robot frame.
struct VelocityCommand {
  double vx = 0;     ///< forward, m/s
  double vy = 0;     ///< left, m/s (holonomic robots only; 0 for differential drive)
  double omega = 0;  ///< counter-clockwise, rad/s
  friend bool operator==(const VelocityCommand&, const VelocityCommand&) = default;
};

/// Velocity and acceleration limits (all > 0).
struct RobotLimits {
  double max_v = 1.0;                    ///< |vx|, |vy| and the planar speed, m/s
  double max_omega = 60.0 * 3.14159265358979323846 / 180.0;  ///< |ω|, rad/s
  double max_acc_v = 1.0;                ///< linear acceleration, m/s²
  double max_acc_omega = 2.0;            ///< angular acceleration, rad/s²
  /// Throws InvalidArgument naming the first limit that is not finite and > 0.
  void check() const;
};

/// The simulated lidar (defaults: a 360° scanner, 1° between rays).
struct SimulatedLidarOptions {
  int rays = 360;                             ///< ≥ 2
  double aperture = 2 * 3.14159265358979323846 * 359.0 / 360.0;  ///< (0, 2π] radians
  double max_range = 20.0;                    ///< meters, > 0
  double range_sigma = 0.01;                  ///< Gaussian range noise σ, meters, ≥ 0
  SE2d T_robot_sensor;                        ///< where it sits on the robot
  void check() const;                         ///< throws InvalidArgument
};

/// Options of Simulator.
struct SimulatorOptions {
  RobotKinematics kinematics = RobotKinematics::DifferentialDrive;
  RobotLimits limits;
  double robot_radius = 0.30;   ///< meters, > 0: the disc that must not touch an obstacle
  double dt = 0.1;              ///< seconds per step (the control period), > 0
  SimulatedLidarOptions lidar;
  double odometry_sigma_xy = 0.01;     ///< σ of translation per meter moved, ≥ 0
  double odometry_sigma_phi = 0.01;    ///< σ of rotation per radian turned, ≥ 0
  double odometry_sigma_phi_per_m = 0.005;  ///< σ of rotation per meter moved, rad/m, ≥ 0
  std::uint64_t seed = 1;       ///< of the noise
  /// Throws InvalidArgument naming the first bad field.
  void check() const;
};

/// What one step did.
struct SimulatorStep {
  double time = 0;              ///< seconds since the start, after the step
  SE2d T_map_robot;             ///< ground truth after the step
  Pose2 odometry_increment;     ///< the noisy odometry of the step (robot frame)
  Twist2 velocity;              ///< the velocity reached (after the limits)
  bool collided = false;        ///< the robot touched an obstacle and stopped
};

/// The simulator. Keeps a reference to the world grid (must outlive it).
/// Thread-compatible.
class Simulator {
 public:
  /// A robot at rest at `start`. Throws InvalidArgument if the options
  /// fail check() or the robot disc at start overlaps an obstacle.
  Simulator(const NavigationGrid& world, const SE2d& start, SimulatorOptions options = {});

  /// Applies `command` for one period: the command is clamped to the
  /// limits (a differential-drive robot ignores vy), the velocity moves
  /// toward it within the accelerations, the pose follows the constant
  /// twist (SE2 exponential). If the disc would touch an obstacle the robot
  /// stops at the last free pose of the period and `collided` is set.
  /// Precondition: finite command.
  SimulatorStep step(const VelocityCommand& command);

  /// A lidar scan at the current pose (noise drawn from the simulator's
  /// generator): rays without echo within max_range are invalid.
  RangeScan2D scan();

  /// Ground truth.
  const SE2d& pose() const noexcept { return pose_; }
  /// The odometry pose (the noisy increments composed from the start).
  const Pose2& odometry() const noexcept { return odometry_; }
  /// The current velocity.
  const Twist2& velocity() const noexcept { return velocity_; }
  /// Seconds since the start.
  double time() const noexcept { return time_; }
  /// Collisions so far.
  int collisions() const noexcept { return collisions_; }
  /// Distance from the robot's edge to the nearest obstacle, meters
  /// (capped at 10 m; negative never: 0 when touching).
  double clearance() const;
  /// The options.
  const SimulatorOptions& options() const noexcept { return options_; }
  /// The world.
  const NavigationGrid& world() const noexcept { return world_; }

 private:
  bool touches(const SE2d& p) const;

  const NavigationGrid& world_;
  SimulatorOptions options_;
  SE2d pose_;
  Pose2 odometry_;
  Twist2 velocity_;
  double time_ = 0;
  int collisions_ = 0;
  std::mt19937_64 rng_;
};

/// Writes one step to a rove rawlog of layout #1: an action collection with
/// the step's odometry (RobotMovement2D, MRPT's default Gaussian model, the
/// velocity reached), then a sensory frame with the scan. Both stamped with
/// the step's time after `t0`.
void write_simulation_step(RoveRawlogWriter& log, const SimulatorStep& step, const RangeScan2D& scan,
                           Timestamp t0);

}  // namespace rove
