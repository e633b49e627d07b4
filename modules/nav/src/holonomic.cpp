#include "rove/nav/holonomic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Core>

#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {

std::string_view to_string(HolonomicMethod method) {
  switch (method) {
    case HolonomicMethod::FullEval: return "CHolonomicFullEval";
    case HolonomicMethod::NearnessDiagram: return "CHolonomicND";
    case HolonomicMethod::Vff: return "CHolonomicVFF";
  }
  return "unknown";
}

namespace {

double alpha_of(int k, int n) { return std::numbers::pi * (-1.0 + (2.0 * k + 1.0) / n); }

int index_of(double alpha, int n) {
  const double a = std::remainder(alpha, 2 * std::numbers::pi);
  return std::clamp(static_cast<int>(std::lround(0.5 * (n * (1.0 + a / std::numbers::pi) - 1.0))), 0, n - 1);
}

// Directions apart, around the circle of K.
int sector_gap(int a, int b, int n) {
  const int d = std::abs(a - b);
  return std::min(d, n - d);
}

// Point of direction k at normalized distance d, TP-space (polar → plane).
Eigen::Vector2d tp_point(int k, double d, int n) {
  const double a = alpha_of(k, n);
  return {d * std::cos(a), d * std::sin(a)};
}

void check_input(const HolonomicInput& in) {
  ROVE_CHECK_MSG(in.free.size() >= 3, "a holonomic method needs at least 3 directions, got {}", in.free.size());
  ROVE_CHECK_MSG(std::isfinite(in.target_alpha) && std::isfinite(in.target_distance) && in.target_distance >= 0,
                 "the target must be finite (alpha {}, distance {})", in.target_alpha, in.target_distance);
}

// Speed: a ramp to zero as the obstacle ahead gets within `slow_obstacle`
// and as the target gets within `slow_target`.
double ramp_speed(double free_ahead, double slow_obstacle, double target, double slow_target) {
  double s = 1.0;
  if (slow_obstacle > 0 && free_ahead < slow_obstacle) s *= std::max(0.0, free_ahead / slow_obstacle);
  if (slow_target > 0 && target < slow_target) s *= std::max(0.0, target / slow_target);
  return std::clamp(s, 0.0, 1.0);
}

std::array<double, 7> read_array7(const ConfigSection& s, std::string_view key, std::array<double, 7> fallback) {
  if (!s.has(key)) return fallback;
  const std::vector<double> v = s.get_vector<double>(key, {});
  if (v.size() != 7) s.fail(key, "expected 7 values");
  std::array<double, 7> out{};
  std::copy(v.begin(), v.end(), out.begin());
  return out;
}

}  // namespace

VffOptions VffOptions::from_config(const ConfigSection& s) {
  VffOptions o;
  o.target_slow_approaching_distance =
      s.get_in_range("TARGET_SLOW_APPROACHING_DISTANCE", o.target_slow_approaching_distance, 0, 1e9);
  o.target_attractive_force = s.get_in_range("TARGET_ATTRACTIVE_FORCE", o.target_attractive_force, 0, 1e9);
  return o;
}

NdOptions NdOptions::from_config(const ConfigSection& s) {
  NdOptions o;
  o.wide_gap_size_percent = s.get_in_range("WIDE_GAP_SIZE_PERCENT", o.wide_gap_size_percent, 0, 1);
  o.max_sector_dist_for_d2_percent =
      s.get_in_range("MAX_SECTOR_DIST_FOR_D2_PERCENT", o.max_sector_dist_for_d2_percent, 0, 1);
  o.risk_evaluation_sectors_percent =
      s.get_in_range("RISK_EVALUATION_SECTORS_PERCENT", o.risk_evaluation_sectors_percent, 0, 1);
  o.risk_evaluation_distance = s.get_in_range("RISK_EVALUATION_DISTANCE", o.risk_evaluation_distance, 0, 1);
  o.too_close_obstacle = s.get_in_range("TOO_CLOSE_OBSTACLE", o.too_close_obstacle, 0, 1);
  o.target_slow_approaching_distance =
      s.get_in_range("TARGET_SLOW_APPROACHING_DISTANCE", o.target_slow_approaching_distance, 0, 1e9);
  if (s.has("factorWeights")) {
    const std::vector<double> w = s.get_vector<double>("factorWeights", {});
    if (w.size() != 4) s.fail("factorWeights", "expected 4 values");
    std::copy(w.begin(), w.end(), o.factor_weights.begin());
  }
  return o;
}

FullEvalOptions FullEvalOptions::from_config(const ConfigSection& s) {
  FullEvalOptions o;
  o.factor_weights = read_array7(s, "factorWeights", o.factor_weights);
  std::array<double, 7> norm{};
  for (int i = 0; i < 7; ++i) norm[static_cast<std::size_t>(i)] = o.factor_normalize[static_cast<std::size_t>(i)];
  norm = read_array7(s, "factorNormalizeOrNot", norm);
  for (int i = 0; i < 7; ++i) o.factor_normalize[static_cast<std::size_t>(i)] = norm[static_cast<std::size_t>(i)] != 0;
  o.too_close_obstacle = s.get_in_range("TOO_CLOSE_OBSTACLE", o.too_close_obstacle, 0, 1);
  o.target_slow_approaching_distance =
      s.get_in_range("TARGET_SLOW_APPROACHING_DISTANCE", o.target_slow_approaching_distance, 0, 1e9);
  o.obstacle_slow_down_distance = s.get_in_range("OBSTACLE_SLOW_DOWN_DISTANCE", o.obstacle_slow_down_distance, 0, 1);
  o.hysteresis_sector_count = s.get_in_range("HYSTERESIS_SECTOR_COUNT", o.hysteresis_sector_count, 0, 1e6);
  o.clearance_threshold_ratio = s.get_in_range("clearance_threshold_ratio", o.clearance_threshold_ratio, 0, 1);
  o.gap_width_ratio_threshold = s.get_in_range("gap_width_ratio_threshold", o.gap_width_ratio_threshold, 0, 1);
  s.ignore({"LOG_SCORE_MATRIX"}, "rove keeps no score-matrix log");
  if (s.has("PHASE_COUNT")) {
    const int phases = static_cast<int>(s.get_in_range("PHASE_COUNT", 1, 1, 16));
    o.phases.clear();
    for (int p = 1; p <= phases; ++p) {
      FullEvalPhase ph;
      const std::string fk = "PHASE" + std::to_string(p) + "_FACTORS";
      const std::string tk = "PHASE" + std::to_string(p) + "_THRESHOLD";
      if (!s.has(fk)) s.fail(fk, "missing (PHASE_COUNT says there are " + std::to_string(phases) + " phases)");
      for (double f : s.get_vector<double>(fk, {})) {
        if (f < 0 || f > 6 || f != std::floor(f)) s.fail(fk, "factor indices are 0..6");
        ph.factors.push_back(static_cast<int>(f));
      }
      if (ph.factors.empty()) s.fail(fk, "a phase needs at least one factor");
      ph.threshold = s.get_in_range(tk, ph.threshold, 0, 1);
      o.phases.push_back(ph);
    }
  }
  return o;
}

HolonomicOutput holonomic_vff(const HolonomicInput& in, const VffOptions& o) {
  check_input(in);
  const int n = static_cast<int>(in.free.size());
  Eigen::Vector2d force = Eigen::Vector2d::Zero();
  for (int k = 0; k < n; ++k) {
    const double d = std::max(in.free[static_cast<std::size_t>(k)], 0.01);
    if (d >= 1.0) continue;
    const double a = alpha_of(k, n);
    force -= Eigen::Vector2d(std::cos(a), std::sin(a)) / (d * d * n);
  }
  force += o.target_attractive_force * Eigen::Vector2d(std::cos(in.target_alpha), std::sin(in.target_alpha));
  HolonomicOutput out;
  out.direction = index_of(std::atan2(force.y(), force.x()), n);
  out.speed = ramp_speed(in.free[static_cast<std::size_t>(out.direction)], 0.2, in.target_distance,
                         o.target_slow_approaching_distance);
  return out;
}

HolonomicOutput holonomic_nd(const HolonomicInput& in, const NdOptions& o) {
  check_input(in);
  const int n = static_cast<int>(in.free.size());
  const auto free = [&](int k) { return in.free[static_cast<std::size_t>(((k % n) + n) % n)]; };
  const int kt = index_of(in.target_alpha, n);
  const double open_level = std::min(in.target_distance, o.max_sector_dist_for_d2_percent);
  int dir = -1;
  if (free(kt) >= std::min(in.target_distance, 1.0)) {
    dir = kt;  // the target is in free space: go straight to it
  } else {
    // Regions: runs of directions free beyond the open level, found from a
    // closed direction once around the circle (indices may pass n − 1).
    struct Region {
      int first, last;  // inclusive
    };
    std::vector<Region> regions;
    int closed = -1;
    for (int k = 0; k < n && closed < 0; ++k) {
      if (free(k) <= open_level) closed = k;
    }
    if (closed < 0) {
      regions.push_back({0, n - 1});
    } else {
      int start = -1;
      for (int k = closed + 1; k <= closed + n; ++k) {
        const bool open = free(k) > open_level;
        if (open && start < 0) start = k;
        if (!open && start >= 0) {
          regions.push_back({start, k - 1});
          start = -1;
        }
      }
    }
    double best = -std::numeric_limits<double>::infinity();
    const Region* chosen = nullptr;
    const Eigen::Vector2d target = tp_point(kt, in.target_distance, n);
    for (const Region& r : regions) {
      double mean = 0, nearest = std::numeric_limits<double>::infinity();
      int closest = r.first;
      for (int k = r.first; k <= r.last; ++k) {
        mean += free(k) / (r.last - r.first + 1);
        const double e = (tp_point(k % n, std::min(free(k), in.target_distance), n) - target).norm();
        if (e < nearest) nearest = e, closest = k % n;
      }
      const bool held = in.last_direction >= 0 && sector_gap(closest, in.last_direction, n) <= (r.last - r.first + 1);
      const double score = o.factor_weights[0] * mean + o.factor_weights[1] * (1.0 - 2.0 * sector_gap(closest, kt, n) / n) +
                           o.factor_weights[2] / (1.0 + nearest) + o.factor_weights[3] * (held ? 1.0 : 0.0);
      if (score > best) best = score, chosen = &r;
    }
    if (!chosen) return {kt, 0.0};  // everything blocked: stop, facing the target
    const int width = chosen->last - chosen->first + 1;
    const int wide = std::max(1, static_cast<int>(std::lround(o.wide_gap_size_percent * n)));
    const bool target_inside = [&] {
      for (int k = chosen->first; k <= chosen->last; ++k) {
        if (k % n == kt) return true;
      }
      return false;
    }();
    if (target_inside) {
      dir = kt;
    } else if (width >= wide) {
      // Wide region: from its edge nearer the target, half a wide gap in.
      const bool first_nearer = sector_gap(chosen->first % n, kt, n) <= sector_gap(chosen->last % n, kt, n);
      dir = first_nearer ? chosen->first + wide / 2 : chosen->last - wide / 2;
    } else {
      dir = (chosen->first + chosen->last) / 2;
    }
    dir = ((dir % n) + n) % n;
  }
  // Low safety: obstacles near the direction on one side push it away.
  const int risk = std::max(1, static_cast<int>(std::lround(o.risk_evaluation_sectors_percent * n)));
  double left = 1.0, right = 1.0;
  for (int j = 1; j <= risk; ++j) {
    left = std::min(left, free(dir + j));
    right = std::min(right, free(dir - j));
  }
  if (std::min(left, right) < o.risk_evaluation_distance) {
    const double push = (left - right) / std::max(o.risk_evaluation_distance, 1e-9);
    dir = ((dir + static_cast<int>(std::lround(std::clamp(push, -1.0, 1.0) * risk)) % n) + n) % n;
  }
  HolonomicOutput out;
  out.direction = dir;
  out.speed = ramp_speed(free(dir), o.too_close_obstacle, in.target_distance, o.target_slow_approaching_distance);
  return out;
}

HolonomicOutput holonomic_full_eval(const HolonomicInput& in, const FullEvalOptions& o) {
  check_input(in);
  const int n = static_cast<int>(in.free.size());
  const auto free = [&](int k) { return in.free[static_cast<std::size_t>(((k % n) + n) % n)]; };
  const int kt = index_of(in.target_alpha, n);
  const Eigen::Vector2d target = tp_point(kt, in.target_distance, n);
  const int side = std::max(1, static_cast<int>(std::lround(o.clearance_threshold_ratio * n)));
  // Direct motion: the target is reachable along its own direction through
  // a gap at least gap_width_ratio_threshold·K wide.
  int gap = 0;
  for (int j = -n / 2; j <= n / 2; ++j) gap += free(kt + j) >= std::min(in.target_distance, 1.0) && std::abs(j) <= n / 2;
  std::vector<std::array<double, 7>> f(static_cast<std::size_t>(n));
  std::vector<bool> eligible(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    auto& row = f[static_cast<std::size_t>(k)];
    const double d = free(k);
    eligible[static_cast<std::size_t>(k)] = d > o.too_close_obstacle;
    const double reach = std::min(d, in.target_distance);
    const double end_gap = (tp_point(k, reach, n) - target).norm();
    row[0] = d;
    row[1] = 1.0 - 2.0 * sector_gap(k, kt, n) / n;
    row[2] = (d < in.target_distance ? 0.5 : 1.0) / (1.0 + end_gap);  // blocked short of the target: halved
    row[3] = in.last_direction >= 0 && sector_gap(k, in.last_direction, n) <= o.hysteresis_sector_count ? 1.0 : 0.0;
    double clearance = d;
    for (int j = 1; j <= side; ++j) clearance = std::min({clearance, free(k - j), free(k + j)});
    row[4] = clearance;
    row[5] = 1.0 / (1.0 + end_gap);
    row[6] = std::exp(-std::abs(static_cast<double>(sector_gap(k, kt, n))) / (n / 10.0));
  }
  if (free(kt) >= std::min(in.target_distance, 1.0) && eligible[static_cast<std::size_t>(kt)] &&
      gap >= o.gap_width_ratio_threshold * n) {
    return {kt, ramp_speed(free(kt), o.obstacle_slow_down_distance, in.target_distance,
                           o.target_slow_approaching_distance)};
  }
  // Normalized factors are scaled so their largest eligible value is 1.
  std::array<double, 7> scale{};
  scale.fill(1.0);
  for (int i = 0; i < 7; ++i) {
    if (!o.factor_normalize[static_cast<std::size_t>(i)]) continue;
    double hi = 0;
    for (int k = 0; k < n; ++k) {
      if (eligible[static_cast<std::size_t>(k)]) hi = std::max(hi, f[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)]);
    }
    scale[static_cast<std::size_t>(i)] = hi > 0 ? 1.0 / hi : 1.0;
  }
  std::vector<int> alive;
  for (int k = 0; k < n; ++k) {
    if (eligible[static_cast<std::size_t>(k)]) alive.push_back(k);
  }
  if (alive.empty()) return {kt, 0.0};
  std::vector<double> score(static_cast<std::size_t>(n), 0.0);
  for (const FullEvalPhase& phase : o.phases) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int k : alive) {
      double s = 0;
      for (int i : phase.factors) {
        s += o.factor_weights[static_cast<std::size_t>(i)] * scale[static_cast<std::size_t>(i)] *
             f[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)];
      }
      score[static_cast<std::size_t>(k)] = s;
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    const double keep = lo + phase.threshold * (hi - lo);
    std::vector<int> next;
    for (int k : alive) {
      if (score[static_cast<std::size_t>(k)] >= keep - 1e-12) next.push_back(k);
    }
    alive.swap(next);
  }
  int best = alive.front();
  for (int k : alive) {
    if (score[static_cast<std::size_t>(k)] > score[static_cast<std::size_t>(best)]) best = k;
  }
  return {best, ramp_speed(free(best), o.obstacle_slow_down_distance, in.target_distance,
                           o.target_slow_approaching_distance)};
}

}  // namespace rove
