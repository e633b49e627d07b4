#include "rove/nav/path_processing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"

namespace rove {

double path_length(const PathPoints& points) {
  double length = 0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

PathPoints simplify_path(const NavigationGrid& grid, const PathPoints& points, double radius) {
  ROVE_CHECK_MSG(radius >= 0, "radius must be >= 0, got {}", radius);
  if (points.size() <= 2) return points;
  PathPoints out{points.front()};
  std::size_t anchor = 0;
  while (anchor + 1 < points.size()) {
    std::size_t next = anchor + 1;
    while (next + 1 < points.size() && grid.segment_free(points[anchor], points[next + 1], radius)) {
      ++next;
    }
    out.push_back(points[next]);
    anchor = next;
  }
  return out;
}

PathPoints resample_path(const PathPoints& points, double step) {
  ROVE_CHECK_MSG(step > 0 && std::isfinite(step), "step must be > 0, got {}", step);
  if (points.size() < 2) return points;
  PathPoints out{points.front()};
  for (std::size_t i = 1; i < points.size(); ++i) {
    const Eigen::Vector2d a = points[i - 1], d = points[i] - a;
    const double len = d.norm();
    const auto pieces = static_cast<int>(std::ceil(len / step));
    for (int k = 1; k < pieces; ++k) out.push_back(a + d * (static_cast<double>(k) / pieces));
    out.push_back(points[i]);
  }
  return out;
}

PathPoints smooth_path(const NavigationGrid& grid, const PathPoints& points, double radius,
                       int iterations, double spacing) {
  ROVE_CHECK_MSG(iterations >= 0 && iterations <= 10000, "iterations must be in [0, 10000], got {}",
                 iterations);
  PathPoints p = resample_path(points, spacing);
  for (int it = 0; it < iterations; ++it) {
    bool moved = false;
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
      const Eigen::Vector2d q = p[k] + 0.25 * (p[k - 1] + p[k + 1] - 2.0 * p[k]);
      if ((q - p[k]).squaredNorm() < 1e-18) continue;
      if (grid.segment_free(p[k - 1], q, radius) && grid.segment_free(q, p[k + 1], radius)) {
        p[k] = q;
        moved = true;
      }
    }
    if (!moved) break;
  }
  return p;
}

PathPoints thin_path(const NavigationGrid& grid, const PathPoints& points, double radius,
                     double min_step) {
  ROVE_CHECK_MSG(min_step >= 0, "min_step must be >= 0, got {}", min_step);
  if (points.size() <= 2) return points;
  PathPoints out{points.front()};
  // Invariant: the segment from the last kept point to points[k − 1] is free.
  for (std::size_t k = 1; k < points.size(); ++k) {
    const bool last = k + 1 == points.size();
    if (k > 1 && out.back() != points[k - 1] && !grid.segment_free(out.back(), points[k], radius)) {
      out.push_back(points[k - 1]);
    }
    if (last || (points[k] - out.back()).norm() > min_step) out.push_back(points[k]);
  }
  return out;
}

GridPath make_grid_path(const NavigationGrid& grid, const PathPoints& points, const SE2d& start,
                        const SE2d& goal) {
  ROVE_CHECK_GE(points.size(), std::size_t{2});
  GridPath path;
  const std::size_t n = points.size();
  path.poses.reserve(n);
  path.clearances.reserve(n);
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    double heading = 0;
    if (i == 0) {
      heading = start.angle();
    } else if (i + 1 == n) {
      heading = goal.angle();
    } else {
      const Eigen::Vector2d d = points[i + 1] - points[i];
      heading = d.squaredNorm() > 0 ? std::atan2(d.y(), d.x()) : path.poses.back().angle();
    }
    path.poses.emplace_back(points[i].x(), points[i].y(), heading);
    path.clearances.push_back(grid.clearance_at(points[i]));
    if (i > 0) lowest = std::min(lowest, static_cast<double>(grid.segment_clearance(points[i - 1], points[i])));
  }
  path.length = path_length(points);
  path.min_clearance = n > 1 ? lowest : path.clearances.front();
  return path;
}

}  // namespace rove
