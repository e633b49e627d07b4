#include "rove/nav/navigation_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/interrupt.h"
#include "rove/nav/teb_edges.h"

namespace rove {

std::string_view to_string(LocalPlannerKind kind) {
  switch (kind) {
    case LocalPlannerKind::Teb: return "teb";
  }
  return "unknown";
}

std::string_view to_string(NavigationTermination t) {
  switch (t) {
    case NavigationTermination::GoalReached: return "goal-reached";
    case NavigationTermination::Collision: return "collision";
    case NavigationTermination::NoPath: return "no-path";
    case NavigationTermination::Stuck: return "stuck";
    case NavigationTermination::Timeout: return "timeout";
  }
  return "unknown";
}

void NavigationRunOptions::check() const {
  simulator.check();
  teb.check();
  ROVE_CHECK_MSG(std::isfinite(global_margin) && global_margin >= 0, "global_margin must be >= 0, got {}",
                 global_margin);
  ROVE_CHECK_MSG(std::isfinite(obstacle_range) && obstacle_range > 0, "obstacle_range must be > 0, got {}",
                 obstacle_range);
  ROVE_CHECK_MSG(std::isfinite(obstacle_cell) && obstacle_cell > 0, "obstacle_cell must be > 0, got {}",
                 obstacle_cell);
  ROVE_CHECK_MSG(std::isfinite(goal_tolerance) && goal_tolerance > 0, "goal_tolerance must be > 0, got {}",
                 goal_tolerance);
  ROVE_CHECK_MSG(std::isfinite(replan_after) && replan_after > 0, "replan_after must be > 0, got {}", replan_after);
  ROVE_CHECK_MSG(max_replans >= 0, "max_replans must be >= 0, got {}", max_replans);
  ROVE_CHECK_MSG(!std::isnan(max_time), "max_time is NaN");
}

namespace {

// The global plan as the local planner follows it: poses from the robot's
// position along the path, the goal last with its heading (the final
// segment's when the goal's heading does not matter).
std::vector<SE2d> plan_poses(const GridPath& path, const SE2d& goal, bool goal_heading) {
  std::vector<SE2d> poses = path.poses;
  if (!goal_heading && poses.size() >= 2) {
    const Eigen::Vector2d d = poses.back().translation() - poses[poses.size() - 2].translation();
    if (d.squaredNorm() > 1e-12) poses.back() = SE2d(goal.translation().x(), goal.translation().y(), std::atan2(d.y(), d.x()));
  }
  return poses;
}

// Remaining length along the plan from its point nearest to p (searching
// forward from `from`, within 3 m of path), and that point's index.
std::pair<double, std::size_t> remaining(const std::vector<SE2d>& plan, std::size_t from, const Eigen::Vector2d& p) {
  std::size_t best = from;
  double best_d = std::numeric_limits<double>::infinity(), along = 0;
  for (std::size_t i = from; i < plan.size(); ++i) {
    if (i > from) along += (plan[i].translation() - plan[i - 1].translation()).norm();
    if (along > 3.0) break;
    const double d = (plan[i].translation() - p).norm();
    if (d < best_d) best_d = d, best = i;
  }
  double rest = best_d;
  for (std::size_t i = best + 1; i < plan.size(); ++i) rest += (plan[i].translation() - plan[i - 1].translation()).norm();
  return {rest, best};
}

}  // namespace

NavigationRunResult run_navigation(const NavigationGrid& world, const SE2d& start, const SE2d& goal,
                                   const NavigationRunOptions& o, RoveRawlogWriter* log,
                                   const std::function<void(const NavigationFrame&)>& on_frame) {
  o.check();
  NavigationRunResult r;
  Simulator sim(world, start, o.simulator);
  GridPlannerOptions global = o.global;
  global.robot_radius = o.simulator.robot_radius + o.global_margin;
  r.global = plan_path(world, start, goal, global);
  if (!r.global.ok()) {
    // Too near a wall for the margin: the bare radius may still pass.
    GridPlannerOptions bare = global;
    bare.robot_radius = o.simulator.robot_radius;
    if (r.global.termination == PlanTermination::StartBlocked || r.global.termination == PlanTermination::GoalBlocked ||
        r.global.termination == PlanTermination::NoPath) {
      r.global = plan_path(world, start, goal, bare);
    }
    if (!r.global.ok()) {
      r.termination = NavigationTermination::NoPath;
      r.message = r.global.message;
      return r;
    }
  }
  std::vector<SE2d> plan = plan_poses(r.global.path, goal, o.goal_heading);
  const double max_time = o.max_time > 0 ? o.max_time : 60.0 + 3.0 * r.global.path.length / o.teb.max_vel_x;
  TebPlanner local_planner(o.teb);
  const Timestamp t0 = Timestamp::from_seconds(0.0);
  r.driven.push_back(start);
  r.min_clearance = sim.clearance();
  std::size_t plan_at = 0;
  double best_rest = remaining(plan, 0, start.translation()).first, last_progress = 0;
  while (true) {
    throw_if_interrupted();
    const RangeScan2D scan = sim.scan();
    std::vector<Eigen::Vector2d> near;
    for (const Eigen::Vector2d& p : scan_points_in_map(scan, sim.pose())) {
      if ((p - sim.pose().translation()).norm() <= o.obstacle_range) near.push_back(p);
    }
    const std::vector<TebObstacle> obstacles = point_obstacles(near, o.obstacle_cell);
    const std::vector<SE2d> ahead(plan.begin() + static_cast<std::ptrdiff_t>(plan_at), plan.end());
    const auto c0 = std::chrono::steady_clock::now();
    const TebResult step = local_planner.plan(sim.pose(), sim.velocity(), ahead, obstacles);
    r.cycle_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count());
    r.cycle_obstacles.push_back(static_cast<int>(obstacles.size()));
    r.cycle_band_poses.push_back(static_cast<int>(local_planner.band().poses.size()));
    ++r.cycles;
    const double to_goal = (goal.translation() - sim.pose().translation()).norm();
    const bool heading_ok = !o.goal_heading || std::abs(teb::wrap_angle(goal.angle() - sim.pose().angle())) <
                                                   o.teb.yaw_goal_tolerance;
    if ((to_goal < o.goal_tolerance && heading_ok) || step.termination == TebTermination::GoalReached) {
      r.termination = NavigationTermination::GoalReached;
      r.message = fmt::format("goal reached in {:.1f} s, {:.2f} m driven", sim.time(), r.length);
      break;
    }
    VelocityCommand command;
    if (step.termination == TebTermination::Optimized) {
      command = step.command;
    } else {
      ++r.infeasible_cycles;
    }
    const SimulatorStep s = sim.step(command);
    if (log) write_simulation_step(*log, s, scan, t0);
    r.length += (s.T_map_robot.translation() - r.driven.back().translation()).norm();
    r.driven.push_back(s.T_map_robot);
    r.min_clearance = std::min(r.min_clearance, sim.clearance());
    r.time = sim.time();
    if (on_frame) {
      NavigationFrame f{sim.time(), sim.pose(), near, local_planner.band().poses, command};
      on_frame(f);
    }
    if (s.collided) {
      r.termination = NavigationTermination::Collision;
      r.message = fmt::format("the robot touched an obstacle at ({:.2f}, {:.2f}) after {:.1f} s",
                              sim.pose().translation().x(), sim.pose().translation().y(), sim.time());
      break;
    }
    const auto [rest, index] = remaining(plan, plan_at, sim.pose().translation());
    plan_at = index;
    if (rest < best_rest - 0.1) {
      best_rest = rest;
      last_progress = sim.time();
    }
    if (sim.time() - last_progress > o.replan_after) {
      if (r.replans >= o.max_replans) {
        r.termination = NavigationTermination::Stuck;
        r.message = fmt::format("no progress after {} replans, {:.2f} m from the goal", r.replans, to_goal);
        break;
      }
      ++r.replans;
      GridPlannerOptions bare = global;
      GridPlanResult again = plan_path(world, sim.pose(), goal, global);
      if (!again.ok()) {
        bare.robot_radius = o.simulator.robot_radius;
        again = plan_path(world, sim.pose(), goal, bare);
      }
      if (again.ok()) {
        plan = plan_poses(again.path, goal, o.goal_heading);
        plan_at = 0;
      }
      local_planner.reset();
      best_rest = remaining(plan, 0, sim.pose().translation()).first;
      last_progress = sim.time();
    }
    if (sim.time() >= max_time) {
      r.termination = NavigationTermination::Timeout;
      r.message = fmt::format("out of time after {:.1f} s, {:.2f} m from the goal", sim.time(), to_goal);
      break;
    }
  }
  r.time = sim.time();
  return r;
}

}  // namespace rove
