#pragma once
// A small synthetic world for the Monte-Carlo localization tests: a 12 m ×
// 8 m room with four obstacles and a cut corner that break its symmetries, as exact line
// segments (the ground truth) and as an occupancy grid (the map); laser
// scans simulated by exact ray–segment intersection; odometry actions with
// MRPT's Gaussian model.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include <Eigen/Core>

#include "rove/bayes/random.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/math/se2.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"

namespace rove::test {

struct Segment {
  Eigen::Vector2d a, b;
};

inline std::vector<Segment> room_segments() {
  std::vector<Segment> s;
  const auto box = [&](double x0, double y0, double x1, double y1) {
    s.push_back({{x0, y0}, {x1, y0}});
    s.push_back({{x1, y0}, {x1, y1}});
    s.push_back({{x1, y1}, {x0, y1}});
    s.push_back({{x0, y1}, {x0, y0}});
  };
  box(0, 0, 12, 8);            // outer walls
  box(3, 2, 4, 5);             // a pillar
  s.push_back({{8, 0}, {8, 3}});  // a short wall out of the south wall
  box(9.5, 5.5, 10.5, 6.5);    // a small box
  box(2.0, 7.4, 2.6, 8.0);     // a cabinet against the north wall
  s.push_back({{10, 0}, {12, 2}});  // the south-east corner cut off
  return s;
}

inline double distance_to_segment(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d d = s.b - s.a;
  const double t = std::clamp((p - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (s.a + t * d - p).norm();
}

// True for points of the free interior (inside the room, outside obstacles).
inline bool room_free(const Eigen::Vector2d& p) {
  const auto in = [&](double x0, double y0, double x1, double y1) {
    return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1;
  };
  return in(0, 0, 12, 8) && !in(3, 2, 4, 5) && !in(9.5, 5.5, 10.5, 6.5) &&
         !in(2.0, 7.4, 2.6, 8.0) && p.y() >= p.x() - 10.0;
}

// The room as a 5 cm occupancy grid: cells within 4 cm of a wall occupied,
// the interior free, the outside unknown.
inline OccupancyGrid room_grid() {
  OccupancyGrid g(-1.0f, 13.0f, -1.0f, 9.0f, 0.05f, 0.5f);
  const auto segments = room_segments();
  for (std::uint32_t cy = 0; cy < g.size_y(); ++cy) {
    for (std::uint32_t cx = 0; cx < g.size_x(); ++cx) {
      const Eigen::Vector2d p(g.idx_to_x(cx), g.idx_to_y(cy));
      double d = std::numeric_limits<double>::infinity();
      for (const auto& s : segments) d = std::min(d, distance_to_segment(p, s));
      const int x = static_cast<int>(cx), y = static_cast<int>(cy);
      if (d <= 0.04) {
        g.set_free_probability(x, y, 0.0f);
      } else if (room_free(p)) {
        g.set_free_probability(x, y, 1.0f);
      }
    }
  }
  return g;
}

// The room grid as a multi-metric map with MRPT's likelihood field options.
inline MultiMetricMap room_map(std::uint32_t decimation = 5) {
  OccupancyGridCreationOptions creation;
  creation.min_x = -1.0f;
  creation.max_x = 13.0f;
  creation.min_y = -1.0f;
  creation.max_y = 9.0f;
  creation.resolution = 0.05f;
  GridLikelihoodOptions lik;
  lik.method = GridLikelihoodMethod::LikelihoodFieldThrun;
  lik.lf_decimation = decimation;
  lik.lf_std_hit = 0.2f;
  lik.lf_max_corrs_distance = 0.3f;
  auto grid = std::make_unique<OccupancyGridMetricMap>(creation, GridInsertionOptions{}, lik);
  grid->grid() = room_grid();
  MultiMetricMap map;
  map.add(std::move(grid));
  return map;
}

// A 180° scan of 181 rays from `pose` (sensor at the robot's origin), ranges
// exact plus N(0, noise²); no return beyond 20 m.
inline std::shared_ptr<RangeScan2D> simulate_scan(const SE2d& pose, Rng& rng, double noise = 0.01) {
  auto scan = std::make_shared<RangeScan2D>();
  scan->aperture = std::numbers::pi;
  scan->right_to_left = true;
  scan->max_range = 20.0f;
  const auto segments = room_segments();
  const Eigen::Vector2d o = pose.translation();
  std::vector<float> ranges(181);
  for (int i = 0; i < 181; ++i) {
    const double a = pose.angle() - std::numbers::pi / 2 + i * std::numbers::pi / 180.0;
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& s : segments) {
      const Eigen::Vector2d e = s.b - s.a;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const Eigen::Vector2d w = s.a - o;
      const double t = (w.x() * e.y() - w.y() * e.x()) / den;
      const double u = (w.x() * d.y() - w.y() * d.x()) / den;
      if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
    }
    ranges[static_cast<std::size_t>(i)] =
        best < 20.0 ? static_cast<float>(best + noise * rng.normal()) : 20.0f;
  }
  scan->set_ranges(std::move(ranges));
  return scan;
}

inline SensoryFrame frame_of(std::shared_ptr<const Observation> obs) {
  SensoryFrame f;
  f.add(std::move(obs));
  return f;
}

// The odometry action of moving from `a` to `b` (increment a⁻¹b), MRPT's
// Gaussian model with default parameters.
inline RobotMovement2D movement(const SE2d& a, const SE2d& b) {
  const SE2d d = a.inverse() * b;
  return RobotMovement2D(Pose2(d.translation().x(), d.translation().y(), d.angle()),
                         MotionModelOptions{});
}

// A path of poses through the free room: east along y = 1.2, north along
// x = 6.5, then west along y = 6.8 (0.25 m steps, turning in place).
inline std::vector<SE2d> room_path() {
  std::vector<SE2d> p;
  for (double x = 1.0; x <= 6.5; x += 0.25) p.emplace_back(x, 1.2, 0.0);
  for (double y = 1.2; y <= 6.8; y += 0.25) p.emplace_back(6.5, y, std::numbers::pi / 2);
  for (double x = 6.5; x >= 1.0; x -= 0.25) p.emplace_back(x, 6.8, std::numbers::pi);
  return p;
}

}  // namespace rove::test
