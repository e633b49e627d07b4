#pragma once
/// \file
/// Options of the timed-elastic-band local planner (teb.h), with the names
/// and defaults of teb_local_planner (Rösmann et al.; its ROS parameters in
/// the comments) where it has them. Units: meters, radians, seconds.

#include <cstdint>

#include "rove/core/config_section.h"

namespace rove {

/// The robot's kinematics as the band models it.
enum class TebKinematics : std::uint8_t {
  DifferentialDrive,  ///< no sideways motion
  CarLike,            ///< no sideways motion and a minimum turning radius
};

/// TEB options (see the file comment). check() lists the constraints.
struct TebOptions {
  // --- trajectory ---
  /// `dt_ref`: the time step the band is resized toward, s. > 0.
  double dt_ref = 0.3;
  /// `dt_hysteresis`: a step is split above dt_ref + this and merged below
  /// dt_ref − this, s. ≥ 0, < dt_ref.
  double dt_hysteresis = 0.1;
  /// `min_samples`: poses of the band at least. ≥ 3.
  int min_samples = 3;
  /// `max_samples`: poses of the band at most. ≥ min_samples.
  int max_samples = 500;
  /// `max_global_plan_lookahead_dist`: the local goal lies at most this far
  /// along the global plan, m. > 0.
  double max_global_plan_lookahead_dist = 3.0;
  /// `global_plan_viapoint_sep`: a via-point every this many meters of the
  /// global plan within the look-ahead; ≤ 0: none.
  double global_plan_viapoint_sep = -1;
  /// `feasibility_check_no_poses`: poses checked against the obstacles
  /// before a command is sent. ≥ 0.
  int feasibility_check_no_poses = 5;

  // --- robot ---
  TebKinematics kinematics = TebKinematics::DifferentialDrive;
  /// `max_vel_x`, m/s. > 0.
  double max_vel_x = 0.4;
  /// `max_vel_x_backwards`, m/s. ≥ 0 (0 forbids driving backwards).
  double max_vel_x_backwards = 0.2;
  /// `max_vel_theta`, rad/s. > 0.
  double max_vel_theta = 0.3;
  /// `acc_lim_x`, m/s². > 0.
  double acc_lim_x = 0.5;
  /// `acc_lim_theta`, rad/s². > 0.
  double acc_lim_theta = 0.5;
  /// `min_turning_radius` (car-like), m. ≥ 0.
  double min_turning_radius = 0.0;
  /// Radius of the robot's circular footprint (`footprint_model/radius`), m. ≥ 0.
  double robot_radius = 0.3;

  // --- goal ---
  /// `xy_goal_tolerance`, m. > 0.
  double xy_goal_tolerance = 0.2;
  /// `yaw_goal_tolerance`, rad. > 0.
  double yaw_goal_tolerance = 0.2;
  /// `free_goal_vel`: the band need not stop at its goal.
  bool free_goal_vel = false;

  // --- obstacles ---
  /// `min_obstacle_dist`: wanted distance between the footprint and an
  /// obstacle, m. ≥ 0.
  double min_obstacle_dist = 0.2;
  /// `obstacle_association_force_inclusion_factor`: every obstacle nearer
  /// than this × min_obstacle_dist to a pose gets an edge. ≥ 1.
  double obstacle_association_force_inclusion_factor = 1.5;
  /// `obstacle_association_cutoff_factor`: beyond this × min_obstacle_dist
  /// no obstacle gets an edge; between the two, the nearest on each side. ≥
  /// the inclusion factor.
  double obstacle_association_cutoff_factor = 5.0;

  // --- optimization ---
  /// `no_inner_iterations`: Levenberg–Marquardt iterations per outer one. ≥ 1.
  int no_inner_iterations = 5;
  /// `no_outer_iterations`: resize + re-association rounds per cycle. ≥ 1.
  int no_outer_iterations = 4;
  /// `penalty_epsilon`: margin added to every bound, ≥ 0.
  double penalty_epsilon = 0.1;
  /// `weight_max_vel_x`. Every weight ≥ 0.
  double weight_max_vel_x = 2.0;
  /// `weight_max_vel_theta`.
  double weight_max_vel_theta = 1.0;
  /// `weight_acc_lim_x`.
  double weight_acc_lim_x = 1.0;
  /// `weight_acc_lim_theta`.
  double weight_acc_lim_theta = 1.0;
  /// `weight_kinematics_nh`: the non-holonomic constraint.
  double weight_kinematics_nh = 1000.0;
  /// `weight_kinematics_forward_drive`: against driving backwards.
  double weight_kinematics_forward_drive = 1.0;
  /// `weight_kinematics_turning_radius` (car-like).
  double weight_kinematics_turning_radius = 1.0;
  /// `weight_optimaltime`: the time-optimal objective.
  double weight_optimaltime = 1.0;
  /// `weight_shortest_path`: the shortest-path objective.
  double weight_shortest_path = 0.0;
  /// `weight_obstacle`.
  double weight_obstacle = 100.0;
  /// `weight_viapoint`.
  double weight_viapoint = 1.0;
  /// `weight_adapt_factor`: the obstacle weight is multiplied by this at
  /// each outer iteration after the first. ≥ 1.
  double weight_adapt_factor = 2.0;

  /// Throws InvalidArgument naming the first value out of range.
  void check() const;
  /// The keys present in `section` (named as the teb_local_planner
  /// parameters above; `kinematics` = diff-drive | car-like) over the
  /// defaults; ConfigError naming the key on a bad value.
  static TebOptions from_config(const ConfigSection& section);
};

}  // namespace rove
