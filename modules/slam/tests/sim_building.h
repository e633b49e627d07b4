#pragma once
// A simulated building for the SLAM tests against ground truth: walls as
// segments (a 24 m x 14 m ring corridor around a 14 m x 4 m block, with
// pillars so that no corridor is featureless), exact ray casting, and a
// loop around the block.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose2.h"

namespace rove::test {

struct Segment {
  Eigen::Vector2d a, b;
};

/// The building's walls; `origin` shifts all of it.
inline std::vector<Segment> building(const Eigen::Vector2d& origin) {
  std::vector<Segment> w;
  const auto box = [&](double x0, double y0, double x1, double y1) {
    const Eigen::Vector2d p[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    for (int i = 0; i < 4; ++i) w.push_back({origin + p[i], origin + p[(i + 1) % 4]});
  };
  box(-2, -2, 22, 12);
  box(3, 3, 17, 7);
  for (const double x : {1.0, 6.0, 11.5, 16.0, 20.0}) {
    box(x, -2, x + 0.4, -1.5);
    box(x - 0.5, 11.5, x - 0.1, 12);
  }
  box(-2, 4.5, -1.4, 5.2);
  box(21.5, 3.5, 22, 4.4);
  box(8, 2.6, 9, 3);
  box(12, 7, 12.5, 7.5);
  return w;
}

/// Range along the ray from p in direction d to the nearest wall (inf: none).
inline double cast(const std::vector<Segment>& walls, const Eigen::Vector2d& p,
                   const Eigen::Vector2d& d) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : walls) {
    const Eigen::Vector2d e = s.b - s.a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Eigen::Vector2d ap = s.a - p;
    const double t = (ap.x() * e.y() - ap.y() * e.x()) / den;  // along the ray
    const double u = (ap.x() * d.y() - ap.y() * d.x()) / den;  // along the wall
    if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
  }
  return best;
}

/// The true path (x, y, heading) every `step` meters, `laps` times
/// counter-clockwise around the block from (1.5, 1.5) + origin, turning in
/// place at the corners in three steps (of 30° with shortest_turns; without
/// it the turn is the plain difference of the headings, so the last corner
/// of a lap turns 270° clockwise in steps of 90°).
inline std::vector<Pose2> loop_path(const Eigen::Vector2d& origin, int laps = 1, double step = 0.2,
                                    bool shortest_turns = true) {
  std::vector<Pose2> out;
  const Eigen::Vector2d corners[5] = {{1.5, 1.5}, {18.5, 1.5}, {18.5, 8.5}, {1.5, 8.5}, {1.5, 1.5}};
  for (int lap = 0; lap < laps; ++lap) {
    for (int leg = 0; leg < 4; ++leg) {
      const Eigen::Vector2d a = corners[leg], b = corners[leg + 1];
      const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
      const int n = static_cast<int>(std::round((b - a).norm() / step));
      if (!out.empty()) {
        const double before = out.back().phi();
        double turn = heading - before;
        if (shortest_turns) turn = std::atan2(std::sin(turn), std::cos(turn));
        for (int k = 1; k <= 3; ++k)
          out.emplace_back(origin.x() + a.x(), origin.y() + a.y(), before + k * turn / 3);
      }
      for (int i = out.empty() ? 0 : 1; i <= n; ++i) {
        const Eigen::Vector2d p = origin + a + (b - a) * (static_cast<double>(i) / n);
        out.emplace_back(p.x(), p.y(), heading);
      }
    }
  }
  return out;
}

}  // namespace rove::test

namespace rove::test {

/// The end points, in the robot frame, of `rays` rays spread evenly over
/// `fov` radians (centered on the robot's x axis) from the robot at
/// `T_world_robot`, with range noise of `sigma` meters drawn from `rng`;
/// rays without a wall within max_range give no point.
template <typename Rng>
std::vector<Eigen::Vector2d> simulate_points(const std::vector<Segment>& walls,
                                             const Eigen::Vector3d& T_world_robot, int rays,
                                             double fov, double sigma, Rng& rng,
                                             double max_range = 30.0) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < rays; ++i) {
    const double local = -0.5 * fov + fov * (i + 0.5) / rays;
    const double a = T_world_robot.z() + local;
    const double r = cast(walls, T_world_robot.head<2>(), Eigen::Vector2d(std::cos(a), std::sin(a)));
    if (!(r < max_range)) continue;
    const double rn = r + (sigma > 0 ? noise(rng) : 0.0);
    pts.emplace_back(rn * std::cos(local), rn * std::sin(local));
  }
  return pts;
}

}  // namespace rove::test

namespace rove::test {

/// A 361-ray scan over 180° (30 m range; no return beyond) from the robot at
/// `T_world_robot`, with range noise of `sigma` meters: sigma × unit(rng)
/// (the caller's standard normal, which may serve other draws too).
template <typename Rng>
RangeScan2D simulate_scan(const std::vector<Segment>& walls, const Pose2& T_world_robot, double sigma,
                          std::normal_distribution<double>& unit, Rng& rng) {
  RangeScan2D scan;
  scan.aperture = std::numbers::pi;
  scan.max_range = 30.0f;
  std::vector<float> ranges;
  for (std::size_t i = 0; i < 361; ++i) {
    const double a = T_world_robot.phi() - std::numbers::pi / 2 + std::numbers::pi * static_cast<double>(i) / 360.0;
    const double r = cast(walls, T_world_robot.translation(), Eigen::Vector2d(std::cos(a), std::sin(a)));
    ranges.push_back(r < 30.0 ? static_cast<float>(r + sigma * unit(rng)) : 0.0f);
  }
  scan.set_ranges(std::move(ranges));
  return scan;
}

}  // namespace rove::test
