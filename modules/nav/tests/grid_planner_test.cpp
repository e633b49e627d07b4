#include "rove/nav/grid_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

#include "nav_test_worlds.h"
#include "rove/core/error.h"
#include "rove/nav/path_processing.h"

namespace rove {
namespace {

// Dijkstra over the planners' moves (a diagonal needs both side cells
// free), costs res and res·√2: the shortest 8-connected path length.
double oracle_length(const NavigationGrid& g, double radius, int sx, int sy, int gx, int gy) {
  const int nx = static_cast<int>(g.size_x()), ny = static_cast<int>(g.size_y());
  const auto free = [&](int x, int y) { return g.clearance(x, y) > radius; };
  std::vector<double> d(static_cast<std::size_t>(nx * ny), std::numeric_limits<double>::infinity());
  using E = std::pair<double, int>;
  std::priority_queue<E, std::vector<E>, std::greater<>> q;
  d[sx + sy * nx] = 0;
  q.emplace(0.0, sx + sy * nx);
  while (!q.empty()) {
    const auto [c, i] = q.top();
    q.pop();
    if (c > d[i]) continue;
    const int x = i % nx, y = i / nx;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !free(x + dx, y + dy)) continue;
        if (dx != 0 && dy != 0 && (!free(x + dx, y) || !free(x, y + dy))) continue;
        const int j = x + dx + (y + dy) * nx;
        const double nc = c + g.resolution() * (dx != 0 && dy != 0 ? std::numbers::sqrt2 : 1.0);
        if (nc < d[j]) {
          d[j] = nc;
          q.emplace(nc, j);
        }
      }
    }
  }
  return d[gx + gy * nx];
}

void expect_safe(const NavigationGrid& g, const GridPath& p, double radius) {
  for (std::size_t i = 1; i < p.poses.size(); ++i) {
    EXPECT_TRUE(g.segment_free(p.poses[i - 1].translation(), p.poses[i].translation(), radius)) << i;
  }
  EXPECT_GT(p.min_clearance, radius);
  ASSERT_EQ(p.clearances.size(), p.poses.size());
}

TEST(GridPlanner, OpenRoomStraightLineWhenSimplified) {
  const NavigationGrid g = nav_test::empty_room(100, 80, 0.1);
  for (const auto method : {GridPlannerMethod::ValueIteration, GridPlannerMethod::AStar}) {
    GridPlannerOptions o;
    o.method = method;
    o.robot_radius = 0.3;
    o.simplify = true;
    const SE2d start(2.0, 2.0, 0.5), goal(8.0, 6.5, -1.0);
    const GridPlanResult r = plan_path(g, start, goal, o);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_EQ(r.path.poses.size(), 2u);
    EXPECT_NEAR(r.path.length, std::hypot(6.0, 4.5), 1e-9);
    EXPECT_TRUE(r.path.poses.front().is_approx(start));
    EXPECT_TRUE(r.path.poses.back().is_approx(goal));
    expect_safe(g, r.path, o.robot_radius);
  }
}

TEST(GridPlanner, AStarIsShortestWithoutClearanceCost) {
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const NavigationGrid g = nav_test::random_world(45, 35, 0.1, 0.12, seed);
    GridPlannerOptions o;
    o.robot_radius = 0.05;
    o.min_step = 0;
    o.clearance_weight = 0;
    o.method = GridPlannerMethod::AStar;
    const int sx = 2, sy = 3, gx = 40, gy = 30;
    const SE2d start(g.cell_center(sx, sy).x(), g.cell_center(sx, sy).y(), 0);
    const SE2d goal(g.cell_center(gx, gy).x(), g.cell_center(gx, gy).y(), 0);
    const bool start_free = g.clearance(sx, sy) > 0.05, goal_free = g.clearance(gx, gy) > 0.05;
    const GridPlanResult a = plan_path(g, start, goal, o);
    o.method = GridPlannerMethod::ValueIteration;
    const GridPlanResult v = plan_path(g, start, goal, o);
    if (!start_free || !goal_free) {
      EXPECT_FALSE(a.ok());
      continue;
    }
    const double best = oracle_length(g, 0.05, sx, sy, gx, gy);
    if (std::isinf(best)) {
      EXPECT_EQ(a.termination, PlanTermination::NoPath) << seed;
      EXPECT_EQ(v.termination, PlanTermination::NoPath) << seed;
      continue;
    }
    ASSERT_TRUE(a.ok()) << a.message;
    ASSERT_TRUE(v.ok()) << v.message;
    EXPECT_NEAR(a.path.length, best, 1e-6) << seed;
    EXPECT_GE(v.path.length, best - 1e-9) << seed;
    EXPECT_EQ(a.path.poses.size(), a.path_cells);
    expect_safe(g, a.path, 0.05);
    expect_safe(g, v.path, 0.05);
  }
}

TEST(GridPlanner, ClearanceCostKeepsAwayFromWalls) {
  // A wide opening near one wall: the clearance cost pays to keep off it.
  const NavigationGrid g = nav_test::wall_with_gap(80, 60, 0.1, 40, 2, 50);
  GridPlannerOptions o;
  o.method = GridPlannerMethod::AStar;
  o.robot_radius = 0.2;
  o.min_step = 0;
  o.clearance_weight = 0;
  const SE2d start(1.0, 0.6, 0), goal(7.0, 0.6, 0);
  const GridPlanResult shortest = plan_path(g, start, goal, o);
  o.clearance_weight = 4;
  o.clearance_distance = 1.0;
  const GridPlanResult careful = plan_path(g, start, goal, o);
  ASSERT_TRUE(shortest.ok() && careful.ok());
  double mean_short = 0, mean_careful = 0;
  for (double c : shortest.path.clearances) mean_short += c / shortest.path.clearances.size();
  for (double c : careful.path.clearances) mean_careful += c / careful.path.clearances.size();
  EXPECT_GT(mean_careful, mean_short + 0.1);
  EXPECT_GE(careful.path.length, shortest.path.length - 1e-9);
}

TEST(GridPlanner, NarrowGapHasNoPathForALargeRobot) {
  const NavigationGrid g = nav_test::wall_with_gap(60, 60, 0.1, 30, 25, 5);  // 0.5 m gap
  GridPlannerOptions o;
  o.robot_radius = 0.3;
  for (const auto method : {GridPlannerMethod::ValueIteration, GridPlannerMethod::AStar}) {
    o.method = method;
    const GridPlanResult r = plan_path(g, SE2d(1.0, 3.0, 0), SE2d(5.0, 3.0, 0), o);
    EXPECT_EQ(r.termination, PlanTermination::NoPath);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.message.find("no path"), std::string::npos) << r.message;
    EXPECT_TRUE(r.path.poses.empty());
    o.robot_radius = 0.2;
    const GridPlanResult small = plan_path(g, SE2d(1.0, 3.0, 0), SE2d(5.0, 3.0, 0), o);
    ASSERT_TRUE(small.ok()) << small.message;
    expect_safe(g, small.path, 0.2);
    o.robot_radius = 0.3;
  }
}

TEST(GridPlanner, BadEndpointsAreNamed) {
  const NavigationGrid g = nav_test::wall_with_gap(60, 60, 0.1, 30, 25, 10);
  GridPlannerOptions o;
  o.robot_radius = 0.25;
  const auto plan = [&](double x0, double y0, double x1, double y1) {
    return plan_path(g, SE2d(x0, y0, 0), SE2d(x1, y1, 0), o);
  };
  EXPECT_EQ(plan(-1, 3, 5, 3).termination, PlanTermination::StartOutsideMap);
  EXPECT_EQ(plan(1, 3, 5, 30).termination, PlanTermination::GoalOutsideMap);
  const GridPlanResult in_wall = plan(3.05, 0.5, 5, 3);
  EXPECT_EQ(in_wall.termination, PlanTermination::StartBlocked);
  EXPECT_NE(in_wall.message.find("in an obstacle"), std::string::npos) << in_wall.message;
  const GridPlanResult near_wall = plan(1, 3, 2.85, 0.5);
  EXPECT_EQ(near_wall.termination, PlanTermination::GoalBlocked);
  EXPECT_NE(near_wall.message.find("within the robot radius"), std::string::npos) << near_wall.message;
  EXPECT_EQ(plan(1, 3, 0.1, 3).termination, PlanTermination::GoalBlocked);  // near the map's edge
  const GridPlanResult same = plan(1.01, 3.01, 1.02, 3.04);
  ASSERT_TRUE(same.ok()) << same.message;
  EXPECT_EQ(same.path.poses.size(), 2u);
  EXPECT_NEAR(same.path.length, std::hypot(0.01, 0.03), 1e-12);
}

TEST(GridPlanner, LengthLimitStopsTheSearch) {
  const NavigationGrid g = nav_test::empty_room(200, 50, 0.1);
  GridPlannerOptions o;
  o.robot_radius = 0.2;
  o.max_path_length = 5;  // the goal is 16 m away
  for (const auto method : {GridPlannerMethod::ValueIteration, GridPlannerMethod::AStar}) {
    o.method = method;
    EXPECT_EQ(plan_path(g, SE2d(1, 2.5, 0), SE2d(17, 2.5, 0), o).termination, PlanTermination::TooLong);
    o.max_path_length = 20;
    EXPECT_TRUE(plan_path(g, SE2d(1, 2.5, 0), SE2d(17, 2.5, 0), o).ok());
    o.max_path_length = 5;
  }
}

TEST(GridPlanner, OptionsAreChecked) {
  const NavigationGrid g = nav_test::empty_room(10, 10, 0.1);
  const auto with = [&](auto change) {
    GridPlannerOptions o;
    o.robot_radius = 0.1;
    change(o);
    return plan_path(g, SE2d(0.3, 0.3, 0), SE2d(0.6, 0.6, 0), o);
  };
  EXPECT_THROW(with([](auto& o) { o.robot_radius = 0; }), InvalidArgument);
  EXPECT_THROW(with([](auto& o) { o.robot_radius = -1; }), InvalidArgument);
  EXPECT_THROW(with([](auto& o) { o.robot_radius = std::nan(""); }), InvalidArgument);
  EXPECT_THROW(with([](auto& o) { o.min_step = -0.1; }), InvalidArgument);
  EXPECT_THROW(with([](auto& o) { o.clearance_distance = 0; }), InvalidArgument);
  EXPECT_THROW(with([](auto& o) { o.clearance_weight = -1; }), InvalidArgument);
  EXPECT_THROW(with([](auto& o) { o.smoothing_iterations = -1; }), InvalidArgument);
  EXPECT_NO_THROW(with([](auto&) {}));
}

TEST(GridPlanner, SimplifyAndSmoothKeepThePathSafeAndShorten) {
  const NavigationGrid g = nav_test::random_world(80, 80, 0.1, 0.01, 21, 0.0, 0.0);
  GridPlannerOptions o;
  o.robot_radius = 0.15;
  o.method = GridPlannerMethod::AStar;
  const SE2d start(0.5, 0.5, 0), goal(7.5, 7.0, 0);
  const GridPlanResult raw = plan_path(g, start, goal, o);
  ASSERT_TRUE(raw.ok()) << raw.message;
  o.smoothing_iterations = 50;
  const GridPlanResult smooth = plan_path(g, start, goal, o);
  o.smoothing_iterations = 0;
  o.simplify = true;
  const GridPlanResult simple = plan_path(g, start, goal, o);
  ASSERT_TRUE(smooth.ok() && simple.ok());
  expect_safe(g, raw.path, o.robot_radius);
  expect_safe(g, smooth.path, o.robot_radius);
  expect_safe(g, simple.path, o.robot_radius);
  EXPECT_LE(smooth.path.length, raw.path.length + 1e-9);
  EXPECT_LE(simple.path.length, raw.path.length + 1e-9);
  EXPECT_LT(simple.path.poses.size(), raw.path.poses.size());
  // Interior poses head along their outgoing segment.
  const auto& p = simple.path.poses;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const Eigen::Vector2d d = p[i + 1].translation() - p[i].translation();
    EXPECT_NEAR(p[i].angle(), std::atan2(d.y(), d.x()), 1e-9);
  }
}

TEST(PathProcessing, ThinningKeepsMrptsMinimumStep) {
  const NavigationGrid g = nav_test::empty_room(100, 100, 0.1);
  PathPoints pts;
  for (int i = 0; i <= 50; ++i) pts.emplace_back(1.0 + 0.1 * i, 1.0);
  const PathPoints thin = thin_path(g, pts, 0.2, 0.45);
  ASSERT_GE(thin.size(), 2u);
  EXPECT_EQ(thin.front(), pts.front());
  EXPECT_EQ(thin.back(), pts.back());
  for (std::size_t i = 1; i + 1 < thin.size(); ++i) EXPECT_NEAR((thin[i] - thin[i - 1]).norm(), 0.5, 1e-9);
  const PathPoints dense = resample_path({Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0)}, 0.3);
  ASSERT_EQ(dense.size(), 5u);
  EXPECT_NEAR(dense[1].x(), 0.25, 1e-12);
  EXPECT_NEAR(path_length(dense), 1.0, 1e-12);
  EXPECT_THROW(resample_path(dense, 0.0), InvalidArgument);
}

}  // namespace
}  // namespace rove
