#pragma once
/// \file
/// A navigation run in the simulator: a global path on the map (grid
/// planner), then a local planner each control cycle — the timed elastic
/// band (teb.h) or the reactive navigator (reactive_navigator.h) — fed with
/// the simulated lidar's points, until the robot reaches the goal, touches
/// an obstacle, gets stuck or runs out of time. What `rove nav run` and the
/// closed-loop benchmark drive.
///
/// The local planner sees the robot's true pose (localization is taken as
/// solved here: the run measures the planners) and the points of the
/// current scan; the rawlog it can write holds the noisy odometry and
/// scans, for the localization and mapping tools.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/rove_rawlog.h"
#include "rove/math/se2.h"
#include "rove/nav/grid_planner.h"
#include "rove/nav/navigation_grid.h"
#include "rove/nav/reactive_navigator.h"
#include "rove/nav/simulator.h"
#include "rove/nav/teb.h"

namespace rove {

/// Which local planner drives.
enum class LocalPlannerKind : std::uint8_t {
  Teb,       ///< the timed elastic band
  Reactive,  ///< the PTG-based reactive navigator
};

/// "teb" or "reactive".
std::string_view to_string(LocalPlannerKind kind);

/// Options of run_navigation.
struct NavigationRunOptions {
  /// The local planner.
  LocalPlannerKind planner = LocalPlannerKind::Teb;
  /// The global planner; its robot_radius is overridden by the simulator's
  /// radius + global_margin (for the reactive navigator, at least its
  /// largest PTG footprint + 0.05 m, so that the path leaves it room).
  GridPlannerOptions global;
  /// Extra clearance the global path keeps beyond the robot radius, m. ≥ 0.
  double global_margin = 0.15;
  /// The TEB (its limits should not exceed the simulator's).
  TebOptions teb;
  /// The reactive navigator (its PTGs' footprint should cover the robot).
  ReactiveNavigatorOptions reactive = ReactiveNavigatorOptions::defaults(0.4);
  /// The reactive navigator's target: the farthest point at most this far
  /// along the global path ahead of the robot that the robot sees in a
  /// straight line on the map (or the goal), m. > 0.
  double reactive_lookahead = 2.0;
  /// The robot and its sensors.
  SimulatorOptions simulator;
  /// Scan points nearer than this to the robot are the local planner's
  /// obstacles, m. > 0.
  double obstacle_range = 3.0;
  /// The obstacles are thinned to one per square of this side, m. > 0.
  double obstacle_cell = 0.1;
  /// The goal is reached within this distance, m (its heading is not
  /// checked unless goal_heading). > 0.
  double goal_tolerance = 0.25;
  /// Also require the goal's heading (within the TEB's yaw tolerance).
  bool goal_heading = false;
  /// Replan the global path from the robot after this long without getting
  /// nearer to the goal along the path, s. > 0.
  double replan_after = 8.0;
  /// Give up (Stuck) after this many replans. ≥ 0.
  int max_replans = 5;
  /// Give up (Timeout) after this long, s; ≤ 0: 60 s + three times the
  /// global path's length at the top speed.
  double max_time = 0;
  /// Throws InvalidArgument naming the first bad field (and the nested
  /// options' checks).
  void check() const;

  /// Options for a disc robot of `radius` m with top speeds `max_v` (m/s)
  /// and `max_omega` (rad/s), every part agreeing: the simulator's limits;
  /// the TEB's radius and speeds, its wanted obstacle distance (0.1 m, with
  /// a 0.05 m penalty margin) matching the global path's margin; the
  /// reactive navigator's PTGs (footprint radius + 0.1 m, its speeds); A*
  /// for the global path. Preconditions: positive finite values.
  static NavigationRunOptions for_robot(double radius, double max_v, double max_omega);
};

/// Why a run ended.
enum class NavigationTermination : std::uint8_t {
  GoalReached,  ///< within goal_tolerance of the goal
  Collision,    ///< the robot touched an obstacle (the simulator stopped it)
  NoPath,       ///< the global planner found no path (its message says why)
  Stuck,        ///< no progress after max_replans replans
  Timeout,      ///< max_time elapsed
};

/// "goal-reached", "collision", "no-path", "stuck", "timeout".
std::string_view to_string(NavigationTermination t);

/// What a frame callback sees after each control cycle.
struct NavigationFrame {
  double time = 0;                          ///< s
  SE2d T_map_robot;                         ///< ground truth
  std::vector<Eigen::Vector2d> obstacles;   ///< the local planner's obstacle points
  std::vector<SE2d> local_plan;             ///< the band (TEB) or the chosen trajectory (reactive)
  VelocityCommand command;                  ///< sent this cycle
};

/// The outcome of a run.
struct NavigationRunResult {
  NavigationTermination termination = NavigationTermination::NoPath;
  std::string message;                  ///< one line for a person
  GridPlanResult global;                ///< the first global plan
  std::vector<SE2d> driven;             ///< ground-truth pose after each cycle (the start first)
  double time = 0;                      ///< s, when the run ended
  double length = 0;                    ///< driven path length, m
  double min_clearance = 0;             ///< smallest distance robot edge ↔ obstacle, m
  int cycles = 0;                       ///< control cycles run
  int replans = 0;                      ///< global replans after the first
  int infeasible_cycles = 0;            ///< cycles the local planner refused to move
  std::vector<double> cycle_seconds;    ///< local planner time per cycle (CPU time of the calling thread)
  std::vector<int> cycle_obstacles;     ///< obstacle points the local planner saw per cycle
  std::vector<int> cycle_band_poses;    ///< band poses after each cycle (TEB; 0 for the reactive navigator)
  /// True only when the goal was reached.
  bool ok() const noexcept { return termination == NavigationTermination::GoalReached; }
};

/// Drives from `start` to `goal` in `world` (the simulator's world and the
/// map the global planner uses). `log` (may be null) receives every step
/// (simulation_step: odometry and scan); `on_frame` (may be empty) sees
/// every cycle. Throws InvalidArgument when the options fail check() or
/// the robot at `start` overlaps an obstacle.
NavigationRunResult run_navigation(const NavigationGrid& world, const SE2d& start, const SE2d& goal,
                                   const NavigationRunOptions& options, RoveRawlogWriter* log = nullptr,
                                   const std::function<void(const NavigationFrame&)>& on_frame = {});

}  // namespace rove
