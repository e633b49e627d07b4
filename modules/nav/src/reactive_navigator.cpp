#include "rove/nav/reactive_navigator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/nav/teb_edges.h"

namespace rove {

std::string_view to_string(ReactiveTermination t) {
  switch (t) {
    case ReactiveTermination::Moving: return "moving";
    case ReactiveTermination::TargetReached: return "target-reached";
    case ReactiveTermination::Blocked: return "blocked";
  }
  return "unknown";
}

ReactiveNavigator::ReactiveNavigator(ReactiveNavigatorOptions options) : options_(std::move(options)) {
  options_.check();
  for (const PtgOptions& p : options_.ptgs) ptgs_.push_back(std::make_unique<Ptg>(p));
}

void ReactiveNavigator::consider(std::size_t i, int k, double holonomic_speed, int kt, double target_d,
                                 const std::vector<double>& free, const std::vector<double>& normalized,
                                 const Eigen::Vector2d& t, Candidate& best) const {
  const Ptg& ptg = *ptgs_[i];
  const double ref = ptg.options().ref_distance;
  const int n = ptg.path_count();
  const double cfd = normalized[static_cast<std::size_t>(k)];
  // MRPT's default scores (reactive_navigator.h), without a delay model.
  const double eff = std::max(0.0, target_d);
  const double target_distance = cfd > eff ? 1.0 / (1.0 + eff * eff) : 0.0;
  const double cfd_score = cfd > eff + 0.05 ? 1.0 : cfd;
  const double eucl = ptg.distance_to_path(k, free[static_cast<std::size_t>(k)], t) / ref;
  const double nearness = 1.0 / (1.0 + eucl * eucl);
  const double hysteresis = static_cast<int>(i) == last_ptg_ && std::abs(k - last_direction_) <= 1 ? 1.0 : 0.0;
  double dif = std::abs(kt - k);
  if (dif > n / 2.0) dif = n - dif;
  const double index_near = std::exp(-std::abs(dif / (n / 10.0)));
  const double score = ptg.options().score_priority *
                       (0.3 * target_distance + 0.5 * cfd_score + 8.0 * nearness + 0.1 * hysteresis + 0.2 * index_near);
  // The secure-distance ramp on the free distance ahead, unless the path
  // heads for the target and is free up to it (the holonomic method's
  // approach slows down there).
  const bool reaches_target = std::abs(k - kt) <= 1 && cfd >= target_d;
  const double ramp = reaches_target ? 1.0
                                     : std::clamp((cfd - options_.secure_distance_start) /
                                                      (options_.secure_distance_end - options_.secure_distance_start),
                                                  0.0, 1.0);
  const double speed = holonomic_speed * ramp;
  if (speed > 0 && score > best.score) best = {static_cast<int>(i), k, score, speed, free[static_cast<std::size_t>(k)]};
}

ReactiveResult ReactiveNavigator::step(const SE2d& T_map_robot, const std::vector<Eigen::Vector2d>& obstacles,
                                       const Eigen::Vector2d& target, double allowed_distance) {
  ROVE_CHECK_FINITE(target);
  ReactiveResult r;
  const SE2d T_robot_map = T_map_robot.inverse();
  const Eigen::Vector2d t = T_robot_map * target;
  if (t.norm() <= allowed_distance) {
    r.termination = ReactiveTermination::TargetReached;
    r.message = fmt::format("the target is {:.3f} m away, within {} m", t.norm(), allowed_distance);
    last_ptg_ = last_direction_ = -1;
    return r;
  }
  std::vector<Eigen::Vector2d> near;
  near.reserve(obstacles.size());
  for (const Eigen::Vector2d& p : obstacles) {
    const Eigen::Vector2d q = T_robot_map * p;
    if (q.allFinite() && q.norm() <= options_.ref_distance) near.push_back(q);
  }
  Candidate best;
  std::vector<double> free, normalized;
  for (std::size_t i = 0; i < ptgs_.size(); ++i) {
    const Ptg& ptg = *ptgs_[i];
    const double ref = ptg.options().ref_distance;
    int kt = 0;
    double dt = 0;
    const double off = ptg.inverse_map(t, kt, dt);
    const double target_d = (dt + off) / ref;  // beyond the PTG's reach: more than its length
    ptg.free_distances(near, free);
    normalized.resize(free.size());
    for (std::size_t k = 0; k < free.size(); ++k) normalized[k] = std::min(1.0, free[k] / ref);
    HolonomicInput in{normalized, ptg.alpha(kt), target_d,
                      static_cast<int>(i) == last_ptg_ ? last_direction_ : -1};
    HolonomicOutput out;
    switch (options_.holonomic) {
      case HolonomicMethod::FullEval: out = holonomic_full_eval(in, options_.full_eval); break;
      case HolonomicMethod::NearnessDiagram: out = holonomic_nd(in, options_.nd); break;
      case HolonomicMethod::Vff: out = holonomic_vff(in, options_.vff); break;
    }
    // The holonomic method's choice, and the last cycle's motion when it
    // was this PTG's (MRPT's continuation: with its hysteresis score it
    // wins near-ties, so the choice does not flip between cycles).
    consider(i, out.direction, out.speed, kt, target_d, free, normalized, t, best);
    if (static_cast<int>(i) == last_ptg_ && last_direction_ != out.direction) {
      consider(i, last_direction_, out.speed, kt, target_d, free, normalized, t, best);
    }
  }
  if (best.ptg < 0) {
    r.termination = ReactiveTermination::Blocked;
    r.message = "no PTG has a free motion toward the target";
    last_ptg_ = last_direction_ = -1;
    return r;
  }
  const Ptg& ptg = *ptgs_[static_cast<std::size_t>(best.ptg)];
  VelocityCommand c = ptg.command(best.k);
  c.vx *= best.speed;
  c.omega *= best.speed;
  const double fit = std::min({1.0, options_.robot_max_v / std::max(std::abs(c.vx), 1e-12),
                               options_.robot_max_w / std::max(std::abs(c.omega), 1e-12)});
  c.vx *= fit;
  c.omega *= fit;
  r.termination = ReactiveTermination::Moving;
  r.command = c;
  r.ptg = best.ptg;
  r.direction = best.k;
  r.score = best.score;
  r.free_distance = best.free;
  for (double d = 0; d <= best.free + 1e-9; d += 0.2) r.trajectory.push_back(T_map_robot * ptg.pose_at(best.k, d));
  r.message = fmt::format("{} path {} ({:.2f} m free), score {:.3f}", to_string(ptg.options().family), best.k, best.free,
                          best.score);
  last_ptg_ = best.ptg;
  last_direction_ = best.k;
  return r;
}

}  // namespace rove
