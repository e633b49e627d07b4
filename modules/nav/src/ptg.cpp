#include "rove/nav/ptg.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/memory_budget.h"
#include "rove/nav/teb_edges.h"

namespace rove {

namespace {
constexpr double kTurningRadiusReference = 0.1;  // MRPT's turningRadiusReference, m
}

std::string_view to_string(PtgFamily family) {
  switch (family) {
    case PtgFamily::DiffDriveC: return "CPTG_DiffDrive_C";
    case PtgFamily::DiffDriveAlpha: return "CPTG_DiffDrive_alpha";
    case PtgFamily::DiffDriveCCS: return "CPTG_DiffDrive_CCS";
    case PtgFamily::DiffDriveCS: return "CPTG_DiffDrive_CS";
  }
  return "unknown";
}

void PtgOptions::check() const {
  const auto positive = [](double v, const char* name) {
    ROVE_CHECK_MSG(std::isfinite(v) && v > 0, "PTG option {} must be finite and > 0, got {}", name, v);
  };
  positive(resolution, "resolution");
  positive(ref_distance, "refDistance");
  ROVE_CHECK_MSG(num_paths >= 3 && num_paths <= 4096, "PTG option num_paths must be in [3, 4096], got {}", num_paths);
  positive(v_max, "v_max_mps");
  positive(w_max, "w_max_dps");
  ROVE_CHECK_MSG(std::isfinite(k) && k != 0, "PTG option K must be finite and non-zero, got {}", k);
  positive(cte_a0v, "cte_a0v_deg");
  positive(cte_a0w, "cte_a0w_deg");
  ROVE_CHECK_MSG(std::isfinite(score_priority) && score_priority >= 0, "PTG option score_priority must be >= 0");
  positive(robot_radius, "robot radius");
  ROVE_CHECK_MSG((ref_distance + robot_radius) / resolution < 8000,
                 "PTG option resolution {} is too fine for refDistance {} (more than 16000 cells a side)", resolution,
                 ref_distance);
}

Ptg::Ptg(const PtgOptions& options) : o_(options) {
  o_.check();
  build_paths();
  build_grid();
}

double Ptg::alpha(int k) const {
  ROVE_CHECK_MSG(k >= 0 && k < o_.num_paths, "trajectory {} outside [0, {})", k, o_.num_paths);
  return std::numbers::pi * (-1.0 + (2.0 * k + 1.0) / o_.num_paths);
}

int Ptg::alpha_to_index(double a) const {
  const double wrapped = teb::wrap_angle(a);
  const int k = static_cast<int>(std::lround(0.5 * (o_.num_paths * (1.0 + wrapped / std::numbers::pi) - 1.0)));
  return std::clamp(k, 0, o_.num_paths - 1);
}

void Ptg::velocity(double a, double t, double phi, double& v, double& w) const {
  const double s = a > 0 ? 1.0 : (a < 0 ? -1.0 : 0.0);
  switch (o_.family) {
    case PtgFamily::DiffDriveC:
      v = o_.k * o_.v_max;
      w = o_.k * o_.w_max * a / std::numbers::pi;
      return;
    case PtgFamily::DiffDriveAlpha: {
      const double e = teb::wrap_angle(a - phi);
      v = o_.v_max * std::exp(-(e / o_.cte_a0v) * (e / o_.cte_a0v));
      w = o_.w_max * (2.0 / (1.0 + std::exp(-e / o_.cte_a0w)) - 1.0);
      return;
    }
    case PtgFamily::DiffDriveCCS: {
      const double arc = std::abs(a) / (2 * o_.w_max);
      v = t < arc ? -o_.v_max : o_.v_max;
      w = t < 2 * arc ? s * o_.w_max : 0.0;
      return;
    }
    case PtgFamily::DiffDriveCS:
      v = o_.v_max;
      w = t < std::abs(a) / o_.w_max ? s * o_.w_max : 0.0;
      return;
  }
}

void Ptg::build_paths() {
  const double step = 0.5 * o_.resolution;  // between stored samples, m
  const double fastest = std::max(o_.v_max, kTurningRadiusReference * o_.w_max);
  const double dt = std::min(0.01, 0.25 * step / fastest);
  const double t_max = 4.0 * o_.ref_distance / fastest + 2.0 * std::numbers::pi / o_.w_max;
  paths_.assign(static_cast<std::size_t>(o_.num_paths), {});
  for (int k = 0; k < o_.num_paths; ++k) {
    auto& path = paths_[static_cast<std::size_t>(k)];
    const double a = alpha(k);
    SE2d pose;
    double d = 0, t = 0, next = 0;
    while (d <= o_.ref_distance && t <= t_max) {
      if (d >= next) {
        path.push_back({static_cast<float>(pose.translation().x()), static_cast<float>(pose.translation().y()),
                        static_cast<float>(pose.angle()), static_cast<float>(d)});
        next += step;
      }
      double v = 0, w = 0;
      velocity(a, t, pose.angle(), v, w);
      if (v == 0 && w == 0) break;
      pose = pose * SE2d::exp(SE2d::Tangent(v * dt, 0.0, w * dt));
      d += std::sqrt(v * v + kTurningRadiusReference * kTurningRadiusReference * w * w) * dt;
      t += dt;
    }
    if (path.empty()) path.push_back({0, 0, 0, 0});
  }
}

void Ptg::build_grid() {
  const double res = o_.resolution, r = o_.robot_radius;
  half_ = o_.ref_distance + r + res;
  cells_ = static_cast<int>(std::ceil(2 * half_ / res));
  const auto cell_count = static_cast<std::uint64_t>(cells_) * static_cast<std::uint64_t>(cells_);
  check_memory_budget(checked_bytes(cell_count, 8), fmt::format("the collision grid of a PTG ({} x {} cells)", cells_, cells_));
  // A cell is covered by a sample when the footprint holds its center
  // (an obstacle point is taken at its cell's center: off by at most
  // res/√2, which the footprint's margin over the robot absorbs).
  const int reach = static_cast<int>(std::ceil(r / res)) + 1;
  std::vector<std::int32_t> last_k(static_cast<std::size_t>(cell_count), -1);
  const auto visit = [&](auto&& on_hit) {
    std::fill(last_k.begin(), last_k.end(), -1);
    for (int k = 0; k < o_.num_paths; ++k) {
      const auto& path = paths_[static_cast<std::size_t>(k)];
      for (std::size_t s = 0; s < path.size(); ++s) {
        const int cx = static_cast<int>(std::floor((path[s].x + half_) / res));
        const int cy = static_cast<int>(std::floor((path[s].y + half_) / res));
        for (int y = std::max(0, cy - reach); y <= std::min(cells_ - 1, cy + reach); ++y) {
          const double dy = -half_ + (y + 0.5) * res - path[s].y;
          for (int x = std::max(0, cx - reach); x <= std::min(cells_ - 1, cx + reach); ++x) {
            const double dx = -half_ + (x + 0.5) * res - path[s].x;
            if (dx * dx + dy * dy > r * r) continue;
            const std::size_t c = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * cells_;
            if (last_k[c] == k) continue;
            last_k[c] = k;
            on_hit(c, static_cast<std::uint16_t>(k), static_cast<std::uint16_t>(std::min<std::size_t>(s, 0xffff)));
          }
        }
      }
    }
  };
  std::vector<std::uint32_t> count(static_cast<std::size_t>(cell_count) + 1, 0);
  visit([&](std::size_t c, std::uint16_t, std::uint16_t) { ++count[c + 1]; });
  for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  check_memory_budget(checked_bytes(count.back(), sizeof(Hit)), "the collision grid of a PTG");
  cell_start_ = count;
  hits_.resize(count.back());
  visit([&](std::size_t c, std::uint16_t k, std::uint16_t s) { hits_[count[c]++] = {k, s}; });
}

SE2d Ptg::pose_at(int k, double d) const {
  ROVE_CHECK_MSG(k >= 0 && k < o_.num_paths, "trajectory {} outside [0, {})", k, o_.num_paths);
  const auto& path = paths_[static_cast<std::size_t>(k)];
  const double step = 0.5 * o_.resolution;
  const auto i = std::min(path.size() - 1, static_cast<std::size_t>(std::max(0.0, std::round(d / step))));
  return SE2d(path[i].x, path[i].y, path[i].phi);
}

double Ptg::path_length(int k) const {
  ROVE_CHECK_MSG(k >= 0 && k < o_.num_paths, "trajectory {} outside [0, {})", k, o_.num_paths);
  return paths_[static_cast<std::size_t>(k)].back().d;
}

VelocityCommand Ptg::command(int k) const {
  double v = 0, w = 0;
  velocity(alpha(k), 0.0, 0.0, v, w);
  return {v, 0.0, w};
}

// Samples are stored every `step` of distance along the path, give or take
// one integration step (a quarter of `step`), and the distance along the
// path bounds the distance in the plane: from a sample at distance e from
// the point, the next j samples are at least e − (j + 1)·step away. The
// scans below skip those that cannot come nearer than `best`.
namespace {

// Samples to advance when the current one is `gap` farther than the best
// (gap may be −inf while there is no best yet).
std::size_t skip(double gap, double step) {
  return gap > 2 * step ? static_cast<std::size_t>(gap / step - 1.0) : std::size_t{1};
}

}  // namespace

double Ptg::inverse_map(const Eigen::Vector2d& p, int& k, double& d) const {
  const double step = 0.5 * o_.resolution;
  double best = std::numeric_limits<double>::infinity();
  k = o_.num_paths / 2;
  d = 0;
  for (int j = 0; j < o_.num_paths; ++j) {
    const auto& path = paths_[static_cast<std::size_t>(j)];
    for (std::size_t i = 0; i < path.size();) {
      const Sample& s = path[i];
      const double e = std::hypot(s.x - p.x(), s.y - p.y());
      if (e < best - 1e-9 || (e < best + 1e-9 && s.d < d)) {
        best = e;
        k = j;
        d = s.d;
      }
      i += skip(e - best, step);
    }
  }
  return best;
}

void Ptg::free_distances(const std::vector<Eigen::Vector2d>& obstacles, std::vector<double>& free) const {
  free.resize(static_cast<std::size_t>(o_.num_paths));
  for (int k = 0; k < o_.num_paths; ++k) free[static_cast<std::size_t>(k)] = path_length(k);
  const double res = o_.resolution, step = 0.5 * res, r = o_.robot_radius;
  for (const Eigen::Vector2d& p : obstacles) {
    const int x = static_cast<int>(std::floor((p.x() + half_) / res));
    const int y = static_cast<int>(std::floor((p.y() + half_) / res));
    if (x < 0 || y < 0 || x >= cells_ || y >= cells_) continue;
    const Eigen::Vector2d center(-half_ + (x + 0.5) * res, -half_ + (y + 0.5) * res);
    if (center.norm() <= r) {
      // Already inside the footprint (the robot nearer to it than the
      // footprint's margin): it blocks a trajectory only where the
      // trajectory comes nearer to it than the robot is now.
      const double now = center.norm() - 0.01;
      for (int k = 0; k < o_.num_paths; ++k) {
        const auto& path = paths_[static_cast<std::size_t>(k)];
        for (std::size_t i = 1; i < path.size() && path[i - 1].d < free[static_cast<std::size_t>(k)]; ++i) {
          if (std::hypot(path[i].x - center.x(), path[i].y - center.y()) < now) {
            free[static_cast<std::size_t>(k)] = std::min<double>(free[static_cast<std::size_t>(k)], path[i - 1].d);
            break;
          }
        }
      }
      continue;
    }
    const std::size_t c = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * cells_;
    for (std::uint32_t h = cell_start_[c]; h < cell_start_[c + 1]; ++h) {
      // The last sample before the touching one is the free distance.
      double& f = free[hits_[h].k];
      f = std::min(f, std::max(0.0, (hits_[h].sample - 1.0) * step));
    }
  }
}

double Ptg::distance_to_path(int k, double up_to, const Eigen::Vector2d& p) const {
  ROVE_CHECK_MSG(k >= 0 && k < o_.num_paths, "trajectory {} outside [0, {})", k, o_.num_paths);
  const double step = 0.5 * o_.resolution;
  double best = std::numeric_limits<double>::infinity();
  const auto& path = paths_[static_cast<std::size_t>(k)];
  for (std::size_t i = 0; i < path.size() && path[i].d <= up_to + 1e-9;) {
    const double e = std::hypot(path[i].x - p.x(), path[i].y - p.y());
    best = std::min(best, e);
    i += skip(e - best, step);
  }
  return best;
}

}  // namespace rove
