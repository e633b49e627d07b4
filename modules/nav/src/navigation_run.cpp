#include "rove/nav/navigation_run.h"

#include <algorithm>
#include <ctime>
#include <cmath>
#include <limits>
#include <memory>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/interrupt.h"
#include "rove/nav/teb_edges.h"

namespace rove {

std::string_view to_string(LocalPlannerKind kind) {
  switch (kind) {
    case LocalPlannerKind::Teb: return "teb";
    case LocalPlannerKind::Reactive: return "reactive";
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
  reactive.check();
  ROVE_CHECK_MSG(std::isfinite(reactive_lookahead) && reactive_lookahead > 0, "reactive_lookahead must be > 0, got {}",
                 reactive_lookahead);
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

NavigationRunOptions NavigationRunOptions::for_robot(double radius, double max_v, double max_omega) {
  ROVE_CHECK_MSG(std::isfinite(radius) && radius > 0, "radius must be > 0, got {}", radius);
  ROVE_CHECK_MSG(std::isfinite(max_v) && max_v > 0, "max_v must be > 0, got {}", max_v);
  ROVE_CHECK_MSG(std::isfinite(max_omega) && max_omega > 0, "max_omega must be > 0, got {}", max_omega);
  NavigationRunOptions o;
  o.simulator.robot_radius = radius;
  o.simulator.limits.max_v = max_v;
  o.simulator.limits.max_omega = max_omega;
  o.global.method = GridPlannerMethod::AStar;
  o.global_margin = 0.15;
  o.teb.robot_radius = radius;
  o.teb.max_vel_x = max_v;
  o.teb.max_vel_theta = max_omega;
  o.teb.min_obstacle_dist = 0.1;
  o.teb.penalty_epsilon = 0.05;
  // The reactive navigator sized for a small robot among clutter: PTGs of
  // 5 m, and the normalized distances (fractions of those 5 m) of its
  // speed ramps and of the directions too close to take brought down to
  // the robot's scale (MRPT's file has 10 m and 0.05 / 0.15 / 0.15).
  o.reactive = ReactiveNavigatorOptions::defaults(radius + 0.1);
  o.reactive.robot_max_v = max_v;
  o.reactive.robot_max_w = max_omega;
  o.reactive.ref_distance = 5.0;
  o.reactive.secure_distance_start = 0.01;
  o.reactive.secure_distance_end = 0.10;
  o.reactive.full_eval.too_close_obstacle = 0.02;
  o.reactive.full_eval.obstacle_slow_down_distance = 0.10;
  o.reactive.nd.too_close_obstacle = 0.02;
  for (PtgOptions& p : o.reactive.ptgs) {
    p.v_max = max_v;
    p.w_max = max_omega;
    p.ref_distance = 5.0;
  }
  return o;
}

namespace {

// CPU seconds used by the calling thread so far.
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

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

// The reactive navigator's target: the farthest point at most `ahead`
// meters along the plan (sampled every 5 cm) that the robot sees in a
// straight line on the map (segment_free for its radius), else the plan's
// first point.
Eigen::Vector2d visible_point_ahead(const NavigationGrid& world, const Eigen::Vector2d& robot,
                                    const std::vector<SE2d>& plan, double ahead, double radius) {
  Eigen::Vector2d target = plan.front().translation();
  double along = 0;
  for (std::size_t i = 1; i < plan.size() && along < ahead; ++i) {
    const Eigen::Vector2d a = plan[i - 1].translation(), b = plan[i].translation();
    const double step = (b - a).norm();
    const int pieces = std::max(1, static_cast<int>(std::ceil(step / 0.05)));
    for (int k = 1; k <= pieces && along + step * k / pieces <= ahead + 1e-9; ++k) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / pieces);
      if (!world.segment_free(robot, p, radius)) return target;
      target = p;
    }
    along += step;
  }
  return target;
}

// The global path with the margin, else (the robot or the goal too near a
// wall for it, or only narrower ways) with the bare radius.
GridPlanResult plan_global(const NavigationGrid& world, const SE2d& from, const SE2d& goal,
                           const GridPlannerOptions& with_margin, double bare_radius) {
  GridPlanResult r = plan_path(world, from, goal, with_margin);
  if (r.ok()) return r;
  GridPlannerOptions bare = with_margin;
  bare.robot_radius = bare_radius;
  return plan_path(world, from, goal, bare);
}

// One cycle of the chosen local planner.
struct LocalStep {
  bool goal_reached = false;
  bool moving = false;
  VelocityCommand command;
  std::vector<SE2d> local_plan;
  int band_poses = 0;
};

class LocalPlanner {
 public:
  LocalPlanner(const NavigationRunOptions& o, const NavigationGrid& world) : o_(o), world_(world) {
    if (o.planner == LocalPlannerKind::Teb) {
      teb_ = std::make_unique<TebPlanner>(o.teb);
    } else {
      reactive_ = std::make_unique<ReactiveNavigator>(o.reactive);
    }
  }
  LocalStep step(const Simulator& sim, const std::vector<SE2d>& ahead, const std::vector<Eigen::Vector2d>& points,
                 const std::vector<TebObstacle>& obstacles) {
    LocalStep s;
    if (teb_) {
      const TebResult r = teb_->plan(sim.pose(), sim.velocity(), ahead, obstacles);
      s.goal_reached = r.termination == TebTermination::GoalReached;
      s.moving = r.termination == TebTermination::Optimized;
      s.command = r.command;
      s.local_plan = teb_->band().poses;
      s.band_poses = static_cast<int>(s.local_plan.size());
      return s;
    }
    const Eigen::Vector2d target = visible_point_ahead(world_, sim.pose().translation(), ahead,
                                                       o_.reactive_lookahead, o_.simulator.robot_radius);
    const bool final_target = (target - ahead.back().translation()).norm() < 1e-9;
    const ReactiveResult r = reactive_->step(sim.pose(), points, target, final_target ? 0.5 * o_.goal_tolerance : 0.0);
    s.goal_reached = final_target && r.termination == ReactiveTermination::TargetReached;
    s.moving = r.termination == ReactiveTermination::Moving;
    s.command = r.command;
    s.local_plan = r.trajectory;
    return s;
  }
  void reset() {
    if (teb_) teb_->reset();
  }

 private:
  const NavigationRunOptions& o_;
  const NavigationGrid& world_;
  std::unique_ptr<TebPlanner> teb_;
  std::unique_ptr<ReactiveNavigator> reactive_;
};

}  // namespace

NavigationRunResult run_navigation(const NavigationGrid& world, const SE2d& start, const SE2d& goal,
                                   const NavigationRunOptions& o, RoveRawlogWriter* log,
                                   const std::function<void(const NavigationFrame&)>& on_frame) {
  o.check();
  NavigationRunResult r;
  Simulator sim(world, start, o.simulator);
  GridPlannerOptions global = o.global;
  global.robot_radius = o.simulator.robot_radius + o.global_margin;
  if (o.planner == LocalPlannerKind::Reactive) {
    for (const PtgOptions& p : o.reactive.ptgs) global.robot_radius = std::max(global.robot_radius, p.robot_radius + 0.05);
  }
  r.global = plan_global(world, start, goal, global, o.simulator.robot_radius);
  if (!r.global.ok()) {
    r.termination = NavigationTermination::NoPath;
    r.message = r.global.message;
    return r;
  }
  std::vector<SE2d> plan = plan_poses(r.global.path, goal, o.goal_heading);
  const double max_time =
      o.max_time > 0 ? o.max_time : 60.0 + 3.0 * r.global.path.length / o.simulator.limits.max_v;
  LocalPlanner local_planner(o, world);
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
    const double c0 = thread_cpu_seconds();
    const LocalStep step = local_planner.step(sim, ahead, near, obstacles);
    r.cycle_seconds.push_back(thread_cpu_seconds() - c0);
    r.cycle_obstacles.push_back(static_cast<int>(o.planner == LocalPlannerKind::Teb ? obstacles.size() : near.size()));
    r.cycle_band_poses.push_back(step.band_poses);
    ++r.cycles;
    const double to_goal = (goal.translation() - sim.pose().translation()).norm();
    const bool heading_ok = !o.goal_heading || std::abs(teb::wrap_angle(goal.angle() - sim.pose().angle())) <
                                                   o.teb.yaw_goal_tolerance;
    if ((to_goal < o.goal_tolerance && heading_ok) || step.goal_reached) {
      r.termination = NavigationTermination::GoalReached;
      r.message = fmt::format("goal reached in {:.1f} s, {:.2f} m driven", sim.time(), r.length);
      break;
    }
    VelocityCommand command;
    if (step.moving) {
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
      NavigationFrame f{sim.time(), sim.pose(), near, step.local_plan, command};
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
      const GridPlanResult again = plan_global(world, sim.pose(), goal, global, o.simulator.robot_radius);
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
