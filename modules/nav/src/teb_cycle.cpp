// One TEB control cycle: the local goal on the global plan, the band kept
// from the last cycle or made anew, the optimization, the feasibility check
// and the command.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/nav/teb.h"
#include "rove/nav/teb_edges.h"

namespace rove {

std::string_view to_string(TebTermination t) {
  switch (t) {
    case TebTermination::Optimized: return "optimized";
    case TebTermination::GoalReached: return "goal-reached";
    case TebTermination::Infeasible: return "infeasible";
    case TebTermination::NoPlan: return "no-plan";
  }
  return "unknown";
}

TebPlanner::TebPlanner(TebOptions options) : options_(std::move(options)) { options_.check(); }

namespace {

double heading_of(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double fallback) {
  const Eigen::Vector2d d = to - from;
  return d.squaredNorm() > 1e-18 ? std::atan2(d.y(), d.x()) : fallback;
}

// The interval a step needs at the top speeds (at least 1 % of dt_ref).
double initial_dt(const SE2d& a, const SE2d& b, const TebOptions& o) {
  const double dist = (b.translation() - a.translation()).norm();
  const double turn = std::abs(teb::wrap_angle(b.angle() - a.angle()));
  return std::max({dist / o.max_vel_x, turn / o.max_vel_theta, 0.01 * o.dt_ref});
}

// A band from the robot through plan[first, last) to the local goal, with
// at least min_samples poses (midpoints inserted into the longest steps).
TimedElasticBand initial_band(const SE2d& robot, const std::vector<SE2d>& plan, std::size_t first,
                              std::size_t last, const SE2d& goal, const TebOptions& o) {
  TimedElasticBand band;
  band.poses.push_back(robot);
  for (std::size_t i = first; i < last; ++i) {
    const Eigen::Vector2d& p = plan[i].translation();
    const Eigen::Vector2d& next = i + 1 < last ? plan[i + 1].translation() : goal.translation();
    band.poses.emplace_back(p.x(), p.y(), heading_of(p, next, band.poses.back().angle()));
  }
  band.poses.push_back(goal);
  while (static_cast<int>(band.poses.size()) < o.min_samples) {
    std::size_t longest = 0;
    double best = -1;
    for (std::size_t i = 0; i + 1 < band.poses.size(); ++i) {
      const double d = (band.poses[i + 1].translation() - band.poses[i].translation()).norm();
      if (d > best) best = d, longest = i;
    }
    const SE2d& a = band.poses[longest];
    const SE2d& b = band.poses[longest + 1];
    const Eigen::Vector2d mid = 0.5 * (a.translation() + b.translation());
    const double angle = a.angle() + 0.5 * teb::wrap_angle(b.angle() - a.angle());
    band.poses.insert(band.poses.begin() + static_cast<std::ptrdiff_t>(longest) + 1, SE2d(mid.x(), mid.y(), angle));
  }
  for (std::size_t i = 0; i + 1 < band.poses.size(); ++i) band.dts.push_back(initial_dt(band.poses[i], band.poses[i + 1], o));
  return band;
}

// teb's updateAndPruneTEB: drop the poses the robot has passed (the
// nearest of the next ten, keeping min_samples), then move the ends.
void prune_band(TimedElasticBand& band, const SE2d& robot, const SE2d& goal, const TebOptions& o) {
  const int lookahead = std::min<int>(static_cast<int>(band.poses.size()) - o.min_samples, 10);
  int nearest = 0;
  double best = (robot.translation() - band.poses[0].translation()).norm();
  for (int i = 1; i <= lookahead; ++i) {
    const double d = (robot.translation() - band.poses[static_cast<std::size_t>(i)].translation()).norm();
    if (d >= best) break;
    best = d;
    nearest = i;
  }
  if (nearest > 0) {
    band.poses.erase(band.poses.begin() + 1, band.poses.begin() + nearest + 1);
    band.dts.erase(band.dts.begin() + 1, band.dts.begin() + nearest + 1);
  }
  band.poses.front() = robot;
  band.poses.back() = goal;
}

// The first feasibility_check_no_poses poses and the straight steps between
// them (sampled every half radius) keep the footprint off the obstacles.
bool feasible(const TimedElasticBand& band, const std::vector<TebObstacle>& obstacles, const TebOptions& o) {
  const int last = std::min<int>(o.feasibility_check_no_poses, static_cast<int>(band.poses.size()) - 1);
  const double step = std::max(0.5 * o.robot_radius, 0.01);
  for (int i = 0; i < last; ++i) {
    const Eigen::Vector2d a = band.poses[static_cast<std::size_t>(i)].translation();
    const Eigen::Vector2d b = band.poses[static_cast<std::size_t>(i) + 1].translation();
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int k = 1; k <= pieces; ++k) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / pieces);
      for (const TebObstacle& ob : obstacles) {
        if ((closest_point(ob, p) - p).norm() < o.robot_radius) return false;
      }
    }
  }
  return true;
}

}  // namespace

TebResult TebPlanner::plan(const SE2d& T_map_robot, const Twist2& velocity, const std::vector<SE2d>& global_plan,
                           const std::vector<TebObstacle>& obstacles) {
  ROVE_CHECK_MSG(std::isfinite(velocity.vx) && std::isfinite(velocity.omega), "the robot's velocity is not finite");
  const TebOptions& o = options_;
  TebResult r;
  if (global_plan.empty()) {
    r.termination = TebTermination::NoPlan;
    r.message = "the global plan is empty";
    band_ = {};
    return r;
  }
  const SE2d& goal = global_plan.back();
  const Eigen::Vector2d& robot = T_map_robot.translation();
  const double to_goal = (goal.translation() - robot).norm();
  if (to_goal < o.xy_goal_tolerance &&
      std::abs(teb::wrap_angle(goal.angle() - T_map_robot.angle())) < o.yaw_goal_tolerance) {
    r.termination = TebTermination::GoalReached;
    r.message = fmt::format("the goal is {:.3f} m away, within the tolerance {} m", to_goal, o.xy_goal_tolerance);
    band_ = {};
    return r;
  }
  // The plan point nearest to the robot among those within reach of the
  // plan's start, then the local goal at most the look-ahead beyond it.
  const double reach = o.max_global_plan_lookahead_dist + 2.0;
  std::size_t nearest = 0;
  double best = std::numeric_limits<double>::infinity(), along = 0;
  for (std::size_t i = 0; i < global_plan.size(); ++i) {
    if (i > 0) along += (global_plan[i].translation() - global_plan[i - 1].translation()).norm();
    if (along > reach) break;
    const double d = (global_plan[i].translation() - robot).norm();
    if (d < best) best = d, nearest = i;
  }
  std::size_t local = nearest;
  std::vector<Eigen::Vector2d> vias;
  double ahead = 0, since_via = 0;
  while (local + 1 < global_plan.size()) {
    const double step = (global_plan[local + 1].translation() - global_plan[local].translation()).norm();
    if (ahead + step > o.max_global_plan_lookahead_dist) break;
    ahead += step;
    since_via += step;
    ++local;
    if (o.global_plan_viapoint_sep > 0 && since_via >= o.global_plan_viapoint_sep && local + 1 < global_plan.size()) {
      vias.push_back(global_plan[local].translation());
      since_via = 0;
    }
  }
  const bool final_goal = local + 1 == global_plan.size();
  const SE2d local_goal =
      final_goal ? goal
                 : SE2d(global_plan[local].translation().x(), global_plan[local].translation().y(),
                        local > 0 ? heading_of(global_plan[local - 1].translation(), global_plan[local].translation(),
                                               global_plan[local].angle())
                                  : global_plan[local].angle());
  const bool keep = !band_.poses.empty() &&
                    (band_.poses.back().translation() - local_goal.translation()).norm() < 1.0 &&
                    std::abs(teb::wrap_angle(band_.poses.back().angle() - local_goal.angle())) < std::numbers::pi / 2;
  if (keep) {
    prune_band(band_, T_map_robot, local_goal, o);
  } else {
    band_ = initial_band(T_map_robot, global_plan, nearest + 1, local, local_goal, o);
  }
  r = optimize(band_, velocity, obstacles, vias);
  if (!feasible(band_, obstacles, o)) {
    r.termination = TebTermination::Infeasible;
    r.message = fmt::format("the first {} poses of the optimized band touch an obstacle", o.feasibility_check_no_poses);
    band_ = {};
    return r;
  }
  // teb's extractVelocity for a non-holonomic robot: the first step's
  // length over its interval, signed by its direction, and its turn.
  const SE2d& a = band_.poses[0];
  const SE2d& b = band_.poses[1];
  const double dt = band_.dts[0];
  const Eigen::Vector2d d = b.translation() - a.translation();
  const double forward = std::cos(a.angle()) * d.x() + std::sin(a.angle()) * d.y();
  const double v = (forward < 0 ? -1.0 : 1.0) * d.norm() / dt;
  r.command.vx = std::clamp(v, -o.max_vel_x_backwards, o.max_vel_x);
  r.command.omega = std::clamp(teb::wrap_angle(b.angle() - a.angle()) / dt, -o.max_vel_theta, o.max_vel_theta);
  r.termination = TebTermination::Optimized;
  r.message = fmt::format("{} poses over {:.2f} s, cost {:.4g} -> {:.4g} in {} iterations", r.poses, band_.duration(),
                          r.initial_cost, r.cost, r.iterations);
  return r;
}

}  // namespace rove
