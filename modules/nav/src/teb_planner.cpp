#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_set>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/nav/teb.h"
#include "rove/nav/teb_edges.h"

namespace rove {

namespace {

void positive(double v, const char* name) {
  ROVE_CHECK_MSG(std::isfinite(v) && v > 0, "TEB option {} must be finite and > 0, got {}", name, v);
}
void non_negative(double v, const char* name) {
  ROVE_CHECK_MSG(std::isfinite(v) && v >= 0, "TEB option {} must be finite and >= 0, got {}", name, v);
}

Eigen::Vector2d closest_on_segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  if (len2 <= 0) return a;
  const double t = std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
  return a + t * d;
}

}  // namespace

void TebOptions::check() const {
  positive(dt_ref, "dt_ref");
  non_negative(dt_hysteresis, "dt_hysteresis");
  ROVE_CHECK_MSG(dt_hysteresis < dt_ref, "TEB option dt_hysteresis ({}) must be below dt_ref ({})", dt_hysteresis,
                 dt_ref);
  ROVE_CHECK_MSG(min_samples >= 3, "TEB option min_samples must be >= 3, got {}", min_samples);
  ROVE_CHECK_MSG(max_samples >= min_samples && max_samples <= 100000,
                 "TEB option max_samples must be in [min_samples, 100000], got {}", max_samples);
  positive(max_global_plan_lookahead_dist, "max_global_plan_lookahead_dist");
  ROVE_CHECK_MSG(!std::isnan(global_plan_viapoint_sep), "TEB option global_plan_viapoint_sep is NaN");
  ROVE_CHECK_MSG(feasibility_check_no_poses >= 0, "TEB option feasibility_check_no_poses must be >= 0");
  positive(max_vel_x, "max_vel_x");
  non_negative(max_vel_x_backwards, "max_vel_x_backwards");
  positive(max_vel_theta, "max_vel_theta");
  positive(acc_lim_x, "acc_lim_x");
  positive(acc_lim_theta, "acc_lim_theta");
  non_negative(min_turning_radius, "min_turning_radius");
  non_negative(robot_radius, "robot_radius");
  positive(xy_goal_tolerance, "xy_goal_tolerance");
  positive(yaw_goal_tolerance, "yaw_goal_tolerance");
  non_negative(min_obstacle_dist, "min_obstacle_dist");
  ROVE_CHECK_MSG(obstacle_association_force_inclusion_factor >= 1,
                 "TEB option obstacle_association_force_inclusion_factor must be >= 1");
  ROVE_CHECK_MSG(obstacle_association_cutoff_factor >= obstacle_association_force_inclusion_factor,
                 "TEB option obstacle_association_cutoff_factor must be >= the inclusion factor");
  ROVE_CHECK_MSG(no_inner_iterations >= 1 && no_inner_iterations <= 1000,
                 "TEB option no_inner_iterations must be in [1, 1000]");
  ROVE_CHECK_MSG(no_outer_iterations >= 1 && no_outer_iterations <= 1000,
                 "TEB option no_outer_iterations must be in [1, 1000]");
  non_negative(penalty_epsilon, "penalty_epsilon");
  for (const auto& [v, name] :
       {std::pair{weight_max_vel_x, "weight_max_vel_x"}, {weight_max_vel_theta, "weight_max_vel_theta"},
        {weight_acc_lim_x, "weight_acc_lim_x"}, {weight_acc_lim_theta, "weight_acc_lim_theta"},
        {weight_kinematics_nh, "weight_kinematics_nh"},
        {weight_kinematics_forward_drive, "weight_kinematics_forward_drive"},
        {weight_kinematics_turning_radius, "weight_kinematics_turning_radius"},
        {weight_optimaltime, "weight_optimaltime"}, {weight_shortest_path, "weight_shortest_path"},
        {weight_obstacle, "weight_obstacle"}, {weight_viapoint, "weight_viapoint"}}) {
    non_negative(v, name);
  }
  ROVE_CHECK_MSG(weight_adapt_factor >= 1 && std::isfinite(weight_adapt_factor),
                 "TEB option weight_adapt_factor must be >= 1");
}

TebOptions TebOptions::from_config(const ConfigSection& s) {
  TebOptions o;
  constexpr double kBig = 1e9;
  o.dt_ref = s.get_in_range("dt_ref", o.dt_ref, 1e-6, kBig);
  o.dt_hysteresis = s.get_in_range("dt_hysteresis", o.dt_hysteresis, 0, kBig);
  o.min_samples = static_cast<int>(s.get_in_range("min_samples", o.min_samples, 3, 100000));
  o.max_samples = static_cast<int>(s.get_in_range("max_samples", o.max_samples, 3, 100000));
  o.max_global_plan_lookahead_dist =
      s.get_in_range("max_global_plan_lookahead_dist", o.max_global_plan_lookahead_dist, 1e-6, kBig);
  o.global_plan_viapoint_sep = s.get_in_range("global_plan_viapoint_sep", o.global_plan_viapoint_sep, -kBig, kBig);
  o.feasibility_check_no_poses =
      static_cast<int>(s.get_in_range("feasibility_check_no_poses", o.feasibility_check_no_poses, 0, 100000));
  o.kinematics = s.get_enum("kinematics", o.kinematics,
                            {{"diff-drive", TebKinematics::DifferentialDrive}, {"car-like", TebKinematics::CarLike}});
  o.max_vel_x = s.get_in_range("max_vel_x", o.max_vel_x, 1e-9, kBig);
  o.max_vel_x_backwards = s.get_in_range("max_vel_x_backwards", o.max_vel_x_backwards, 0, kBig);
  o.max_vel_theta = s.get_in_range("max_vel_theta", o.max_vel_theta, 1e-9, kBig);
  o.acc_lim_x = s.get_in_range("acc_lim_x", o.acc_lim_x, 1e-9, kBig);
  o.acc_lim_theta = s.get_in_range("acc_lim_theta", o.acc_lim_theta, 1e-9, kBig);
  o.min_turning_radius = s.get_in_range("min_turning_radius", o.min_turning_radius, 0, kBig);
  o.robot_radius = s.get_in_range("robot_radius", o.robot_radius, 0, kBig);
  o.xy_goal_tolerance = s.get_in_range("xy_goal_tolerance", o.xy_goal_tolerance, 1e-9, kBig);
  o.yaw_goal_tolerance = s.get_in_range("yaw_goal_tolerance", o.yaw_goal_tolerance, 1e-9, kBig);
  o.free_goal_vel = s.get<bool>("free_goal_vel", o.free_goal_vel);
  o.min_obstacle_dist = s.get_in_range("min_obstacle_dist", o.min_obstacle_dist, 0, kBig);
  o.obstacle_association_force_inclusion_factor = s.get_in_range(
      "obstacle_association_force_inclusion_factor", o.obstacle_association_force_inclusion_factor, 1, kBig);
  o.obstacle_association_cutoff_factor =
      s.get_in_range("obstacle_association_cutoff_factor", o.obstacle_association_cutoff_factor, 1, kBig);
  o.no_inner_iterations = static_cast<int>(s.get_in_range("no_inner_iterations", o.no_inner_iterations, 1, 1000));
  o.no_outer_iterations = static_cast<int>(s.get_in_range("no_outer_iterations", o.no_outer_iterations, 1, 1000));
  o.penalty_epsilon = s.get_in_range("penalty_epsilon", o.penalty_epsilon, 0, kBig);
  for (auto [field, key] :
       {std::pair{&o.weight_max_vel_x, "weight_max_vel_x"}, {&o.weight_max_vel_theta, "weight_max_vel_theta"},
        {&o.weight_acc_lim_x, "weight_acc_lim_x"}, {&o.weight_acc_lim_theta, "weight_acc_lim_theta"},
        {&o.weight_kinematics_nh, "weight_kinematics_nh"},
        {&o.weight_kinematics_forward_drive, "weight_kinematics_forward_drive"},
        {&o.weight_kinematics_turning_radius, "weight_kinematics_turning_radius"},
        {&o.weight_optimaltime, "weight_optimaltime"}, {&o.weight_shortest_path, "weight_shortest_path"},
        {&o.weight_obstacle, "weight_obstacle"}, {&o.weight_viapoint, "weight_viapoint"}}) {
    *field = s.get_in_range(key, *field, 0, kBig);
  }
  o.weight_adapt_factor = s.get_in_range("weight_adapt_factor", o.weight_adapt_factor, 1, kBig);
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(s.file(), s.name(), "", e.message());
  }
  return o;
}

Eigen::Vector2d closest_point(const TebObstacle& ob, const Eigen::Vector2d& p) {
  const auto& v = ob.vertices;
  ROVE_CHECK_MSG(!v.empty(), "an obstacle needs at least one vertex");
  if (v.size() == 1) return v[0];
  if (v.size() == 2) return closest_on_segment(v[0], v[1], p);
  // A closed polygon: p itself when inside (even-odd rule), else the
  // nearest point of its edges.
  bool inside = false;
  Eigen::Vector2d best = v[0];
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if ((v[i].y() > p.y()) != (v[j].y() > p.y()) &&
        p.x() < (v[j].x() - v[i].x()) * (p.y() - v[i].y()) / (v[j].y() - v[i].y()) + v[i].x()) {
      inside = !inside;
    }
    const Eigen::Vector2d c = closest_on_segment(v[j], v[i], p);
    const double d = (c - p).squaredNorm();
    if (d < best_d) best_d = d, best = c;
  }
  return inside ? p : best;
}

std::vector<TebObstacle> point_obstacles(const std::vector<Eigen::Vector2d>& points, double cell) {
  ROVE_CHECK_MSG(cell > 0 && std::isfinite(cell), "cell must be > 0, got {}", cell);
  std::unordered_set<std::int64_t> taken;
  std::vector<TebObstacle> out;
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) continue;
    const auto kx = static_cast<std::int64_t>(std::floor(p.x() / cell));
    const auto ky = static_cast<std::int64_t>(std::floor(p.y() / cell));
    if (!taken.insert(kx * 73856093 ^ ky * 19349663).second) continue;
    out.push_back({{p}});
  }
  return out;
}

std::vector<Eigen::Vector2d> scan_points_in_map(const RangeScan2D& scan, const SE2d& T_map_robot) {
  std::vector<Eigen::Vector2d> pts = scan.points_2d(ScanFrame::Robot);
  for (auto& p : pts) p = T_map_robot * p;
  return pts;
}

double TimedElasticBand::duration() const {
  double t = 0;
  for (double d : dts) t += d;
  return t;
}

double TimedElasticBand::length() const {
  double l = 0;
  for (std::size_t i = 1; i < poses.size(); ++i) l += (poses[i].translation() - poses[i - 1].translation()).norm();
  return l;
}

void resize_band(TimedElasticBand& band, const TebOptions& o) {
  // teb's autoResize: repeat single passes while something changes.
  for (int round = 0; round < 100; ++round) {
    bool changed = false;
    for (std::size_t i = 0; i < band.dts.size(); ++i) {
      const double dt = band.dts[i];
      const int n = static_cast<int>(band.poses.size());
      if (dt > o.dt_ref + o.dt_hysteresis && n < o.max_samples) {
        const SE2d& a = band.poses[i];
        const SE2d& b = band.poses[i + 1];
        const double mid_angle = a.angle() + 0.5 * teb::wrap_angle(b.angle() - a.angle());
        const Eigen::Vector2d mid = 0.5 * (a.translation() + b.translation());
        band.poses.insert(band.poses.begin() + static_cast<std::ptrdiff_t>(i) + 1, SE2d(mid.x(), mid.y(), mid_angle));
        band.dts[i] = 0.5 * dt;
        band.dts.insert(band.dts.begin() + static_cast<std::ptrdiff_t>(i) + 1, 0.5 * dt);
        changed = true;
      } else if (dt < o.dt_ref - o.dt_hysteresis && n > o.min_samples) {
        if (i + 1 < band.dts.size()) {
          band.dts[i + 1] += dt;
          band.dts.erase(band.dts.begin() + static_cast<std::ptrdiff_t>(i));
          band.poses.erase(band.poses.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        } else if (i > 0) {
          band.dts[i - 1] += dt;
          band.dts.erase(band.dts.begin() + static_cast<std::ptrdiff_t>(i));
          band.poses.erase(band.poses.begin() + static_cast<std::ptrdiff_t>(i));
        }
        changed = true;
      }
    }
    if (!changed) break;
  }
}

}  // namespace rove
