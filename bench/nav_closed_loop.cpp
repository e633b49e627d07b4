// Closed-loop navigation benchmark: on a grid map, N random start/goal
// pairs (uniform over the cells with room for the robot and the global
// margin, a start heading drawn too, at least 5 m apart, joined by a global
// path), each driven from start to goal in rove's simulator by the chosen
// local planner. Prints per planner: goal reached, collisions, other
// endings; time to goal, driven length and minimum clearance (median over
// the runs that reached the goal, and the smallest clearance of all runs);
// the local planner's CPU time per control cycle (median and 99th
// percentile over every cycle of every run), with the band size and
// obstacle count.
//
//   bench_nav_closed_loop MAP [--pairs N] [--seed S] [--planner teb|reactive|reactive-nd|reactive-vff]
//                         [--runs-out FILE]
//
// reactive: FullEval, MRPT's default method; -nd and -vff the others.
//
// MAP: an MRPT .gridmap[.gz] or a ROS map.yaml. One thread: the cycle times
// are those of one core.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rove/io/grid_image.h"
#include "rove/io/mrpt_gridmap.h"
#include "rove/nav/navigation_run.h"

namespace {

rove::OccupancyGrid load(const std::string& path) {
  if (path.ends_with(".yaml")) return rove::load_ros_map(path).grid;
  return rove::load_mrpt_gridmap(path).grid;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

struct Pair {
  rove::SE2d start, goal;
};

std::vector<Pair> draw_pairs(const rove::NavigationGrid& g, const rove::NavigationRunOptions& o, int count,
                             std::uint64_t seed) {
  const double room = o.simulator.robot_radius + o.global_margin;
  std::vector<Eigen::Vector2d> free;
  for (int y = 0; y < static_cast<int>(g.size_y()); ++y) {
    for (int x = 0; x < static_cast<int>(g.size_x()); ++x) {
      if (g.clearance(x, y) > room) free.push_back(g.cell_center(x, y));
    }
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, free.size() - 1);
  std::uniform_real_distribution<double> heading(-std::numbers::pi, std::numbers::pi);
  rove::GridPlannerOptions gp = o.global;
  gp.robot_radius = room;
  std::vector<Pair> pairs;
  for (int attempt = 0; static_cast<int>(pairs.size()) < count && attempt < 100 * count; ++attempt) {
    const Eigen::Vector2d a = free[pick(rng)], b = free[pick(rng)];
    if ((a - b).norm() < 5.0) continue;
    const rove::SE2d start(a.x(), a.y(), heading(rng)), goal(b.x(), b.y(), 0.0);
    if (!rove::plan_path(g, start, goal, gp).ok()) continue;  // not reachable
    pairs.push_back({start, goal});
  }
  return pairs;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MAP [--pairs N] [--seed S] [--planner teb] [--runs-out FILE]\n", argv[0]);
    return 2;
  }
  const std::string map = argv[1];
  int pairs_count = 100;
  std::uint64_t seed = 1;
  std::string planner = "teb", runs_out;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--pairs")) pairs_count = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--seed")) seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--planner")) planner = argv[i + 1];
    else if (!std::strcmp(argv[i], "--runs-out")) runs_out = argv[i + 1];
  }
  const rove::NavigationGrid world = rove::NavigationGrid::from_occupancy(load(map));
  rove::NavigationRunOptions o = rove::NavigationRunOptions::for_robot(0.3, 0.8, 60 * std::numbers::pi / 180);
  if (planner == "reactive") o.planner = rove::LocalPlannerKind::Reactive;
  else if (planner == "reactive-nd") o.planner = rove::LocalPlannerKind::Reactive, o.reactive.holonomic = rove::HolonomicMethod::NearnessDiagram;
  else if (planner == "reactive-vff") o.planner = rove::LocalPlannerKind::Reactive, o.reactive.holonomic = rove::HolonomicMethod::Vff;
  else if (planner != "teb") {
    std::fprintf(stderr, "unknown planner %s (teb, reactive, reactive-nd, reactive-vff)\n", planner.c_str());
    return 2;
  }
  const std::vector<Pair> pairs = draw_pairs(world, o, pairs_count, seed);
  std::printf("map %s: %u x %u cells of %.3f m; %zu pairs (seed %llu); planner %s; robot radius %.2f m, "
              "%.2f m/s, %.0f deg/s\n",
              map.c_str(), world.size_x(), world.size_y(), world.resolution(), pairs.size(),
              static_cast<unsigned long long>(seed), planner.c_str(), o.simulator.robot_radius,
              o.simulator.limits.max_v, o.simulator.limits.max_omega * 180 / std::numbers::pi);
  std::ofstream runs;
  if (!runs_out.empty()) {
    runs.open(runs_out);
    runs << "# pair start_x start_y start_yaw goal_x goal_y termination time_s length_m planned_m min_clearance_m "
            "replans\n";
  }
  int reached = 0, collisions = 0, other = 0;
  std::vector<double> times, lengths, clearances, cycle_ms, band, obstacles;
  double min_clearance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const rove::NavigationRunResult r = rove::run_navigation(world, pairs[k].start, pairs[k].goal, o);
    reached += r.ok();
    collisions += r.termination == rove::NavigationTermination::Collision;
    other += !r.ok() && r.termination != rove::NavigationTermination::Collision;
    min_clearance = std::min(min_clearance, r.min_clearance);
    if (r.ok()) {
      times.push_back(r.time);
      lengths.push_back(r.length);
      clearances.push_back(r.min_clearance);
    } else {
      std::printf("  pair %zu: %s: %s\n", k, std::string(rove::to_string(r.termination)).c_str(), r.message.c_str());
    }
    for (std::size_t c = 0; c < r.cycle_seconds.size(); ++c) {
      cycle_ms.push_back(1e3 * r.cycle_seconds[c]);
      band.push_back(r.cycle_band_poses[c]);
      obstacles.push_back(r.cycle_obstacles[c]);
    }
    if (runs.is_open()) {
      const auto& s = pairs[k].start;
      runs << k << ' ' << s.translation().x() << ' ' << s.translation().y() << ' ' << s.angle() << ' '
           << pairs[k].goal.translation().x() << ' ' << pairs[k].goal.translation().y() << ' '
           << rove::to_string(r.termination) << ' ' << r.time << ' ' << r.length << ' ' << r.global.path.length
           << ' ' << r.min_clearance << ' ' << r.replans << '\n';
    }
  }
  const double n = static_cast<double>(pairs.size());
  std::printf("goal reached %d / %zu (%.1f %%), collisions %d, other endings %d\n", reached, pairs.size(),
              100.0 * reached / n, collisions, other);
  std::printf("time to goal median %.1f s, driven length median %.1f m, min clearance median %.3f m, smallest %.3f m\n",
              quantile(times, 0.5), quantile(lengths, 0.5), quantile(clearances, 0.5), min_clearance);
  std::printf("local planner per cycle over %zu cycles: median %.3f ms, 99th percentile %.3f ms, max %.3f ms; "
              "band poses median %.0f (max %.0f), obstacle points median %.0f (max %.0f)\n",
              cycle_ms.size(), quantile(cycle_ms, 0.5), quantile(cycle_ms, 0.99), quantile(cycle_ms, 1.0),
              quantile(band, 0.5), quantile(band, 1.0), quantile(obstacles, 0.5), quantile(obstacles, 1.0));
  return 0;
}
