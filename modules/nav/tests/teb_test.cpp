#include "rove/nav/teb.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "nav_test_worlds.h"
#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/nav/navigation_run.h"
#include "rove/nav/teb_edges.h"

namespace rove {
namespace {

TimedElasticBand straight_band(double length, int n, double dt) {
  TimedElasticBand b;
  for (int i = 0; i < n; ++i) b.poses.emplace_back(length * i / (n - 1), 0.0, 0.0);
  b.dts.assign(static_cast<std::size_t>(n - 1), dt);
  return b;
}

bool finite(const TimedElasticBand& b) {
  for (const auto& p : b.poses) {
    if (!p.translation().allFinite() || !std::isfinite(p.angle())) return false;
  }
  for (double d : b.dts) {
    if (!std::isfinite(d) || d <= 0) return false;
  }
  return true;
}

TEST(Teb, FreeStraightBandBecomesTimeOptimalWithinTheLimits) {
  TebOptions o;
  o.no_outer_iterations = 6;
  o.no_inner_iterations = 10;
  TebPlanner teb(o);
  TimedElasticBand band = straight_band(4.0, 12, 1.0);  // slow at first: 4 m in 11 s
  const TebResult r = teb.optimize(band, Twist2{}, {}, {});
  ASSERT_TRUE(finite(band));
  EXPECT_LT(r.cost, r.initial_cost);
  // 4 m at 0.4 m/s takes 10 s plus the ramps at 0.5 m/s².
  EXPECT_GT(band.duration(), 4.0 / o.max_vel_x);
  EXPECT_LT(band.duration(), 4.0 / o.max_vel_x + 2.5);
  for (std::size_t i = 0; i + 1 < band.poses.size(); ++i) {
    const double v = (band.poses[i + 1].translation() - band.poses[i].translation()).norm() / band.dts[i];
    EXPECT_LE(v, o.max_vel_x + 0.02) << i;
    EXPECT_NEAR(band.poses[i].translation().y(), 0.0, 1e-3);
  }
  // Resized toward dt_ref.
  for (double dt : band.dts) EXPECT_LT(dt, o.dt_ref + o.dt_hysteresis + 1e-9);
}

TEST(Teb, BandKeepsItsDistanceFromAnObstacle) {
  TebOptions o;
  o.robot_radius = 0.2;
  o.min_obstacle_dist = 0.3;
  o.no_outer_iterations = 5;
  o.no_inner_iterations = 10;
  TebPlanner teb(o);
  TimedElasticBand band = straight_band(4.0, 15, 0.3);
  // A post just beside the straight line, and one exactly on a pose.
  const std::vector<TebObstacle> posts = {{{Eigen::Vector2d(2.0, 0.1)}}};
  teb.optimize(band, Twist2{}, posts, {});
  ASSERT_TRUE(finite(band));
  for (std::size_t i = 1; i + 1 < band.poses.size(); ++i) {
    const double d = (band.poses[i].translation() - Eigen::Vector2d(2.0, 0.1)).norm() - o.robot_radius;
    EXPECT_GT(d, 0.8 * o.min_obstacle_dist) << i;
  }
  TimedElasticBand on = straight_band(4.0, 15, 0.3);
  const Eigen::Vector2d exact = on.poses[7].translation();
  teb.optimize(on, Twist2{}, {{{exact}}}, {});
  ASSERT_TRUE(finite(on));
  for (std::size_t i = 1; i + 1 < on.poses.size(); ++i) {
    EXPECT_GT((on.poses[i].translation() - exact).norm(), o.robot_radius) << i;
  }
}

TEST(Teb, DegenerateBandsStayFinite) {
  TebPlanner teb;
  // Zero-length band: every pose the same.
  TimedElasticBand still;
  still.poses.assign(4, SE2d(1.0, 1.0, 0.3));
  still.dts.assign(3, 0.3);
  teb.optimize(still, Twist2{}, {{{Eigen::Vector2d(1.0, 1.0)}}}, {});
  EXPECT_TRUE(finite(still));
  // Start = goal through a cycle: reached, zero command.
  const SE2d at(2.0, 3.0, 0.5);
  const TebResult r = teb.plan(at, Twist2{}, {at}, {});
  EXPECT_EQ(r.termination, TebTermination::GoalReached);
  EXPECT_EQ(r.command, VelocityCommand{});
  EXPECT_TRUE(r.ok());
  // An empty plan.
  EXPECT_EQ(teb.plan(at, Twist2{}, {}, {}).termination, TebTermination::NoPlan);
  // A goal behind the robot: a finite command, turning.
  TebPlanner fresh;
  const TebResult back = fresh.plan(SE2d(0, 0, 0), Twist2{}, {SE2d(0, 0, 0), SE2d(-1.0, 0.0, std::numbers::pi)}, {});
  ASSERT_EQ(back.termination, TebTermination::Optimized) << back.message;
  EXPECT_TRUE(std::isfinite(back.command.vx) && std::isfinite(back.command.omega));
  EXPECT_TRUE(finite(fresh.band()));
}

TEST(Teb, ResizeSplitsAndMergesWithinTheSampleLimits) {
  TebOptions o;
  TimedElasticBand band = straight_band(3.0, 4, 1.0);
  resize_band(band, o);
  for (double dt : band.dts) EXPECT_LE(dt, o.dt_ref + o.dt_hysteresis);
  EXPECT_NEAR(band.duration(), 3.0, 1e-12);
  TimedElasticBand dense = straight_band(3.0, 60, 0.05);
  resize_band(dense, o);
  for (double dt : dense.dts) EXPECT_GE(dt, o.dt_ref - o.dt_hysteresis - 1e-12);
  EXPECT_NEAR(dense.duration(), 59 * 0.05, 1e-12);
  o.max_samples = 6;
  TimedElasticBand capped = straight_band(3.0, 4, 1.0);
  resize_band(capped, o);
  EXPECT_EQ(capped.poses.size(), 6u);
  EXPECT_TRUE(capped.poses.front().is_approx(SE2d(0, 0, 0)));
  EXPECT_TRUE(capped.poses.back().is_approx(SE2d(3, 0, 0)));
}

TEST(Teb, ClosestPointOfPointsSegmentsAndPolygons) {
  const Eigen::Vector2d p(1.0, 2.0);
  EXPECT_TRUE(closest_point({{Eigen::Vector2d(3, 4)}}, p).isApprox(Eigen::Vector2d(3, 4)));
  EXPECT_TRUE(closest_point({{Eigen::Vector2d(0, 0), Eigen::Vector2d(4, 0)}}, p).isApprox(Eigen::Vector2d(1, 0)));
  const TebObstacle square{{Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 0), Eigen::Vector2d(2, 1), Eigen::Vector2d(0, 1)}};
  EXPECT_TRUE(closest_point(square, p).isApprox(Eigen::Vector2d(1, 1)));
  EXPECT_TRUE(closest_point(square, Eigen::Vector2d(0.5, 0.5)).isApprox(Eigen::Vector2d(0.5, 0.5)));
  EXPECT_THROW(closest_point(TebObstacle{}, p), InvalidArgument);
  const auto thin = point_obstacles({Eigen::Vector2d(0.01, 0.01), Eigen::Vector2d(0.02, 0.03), Eigen::Vector2d(0.5, 0.5)}, 0.1);
  EXPECT_EQ(thin.size(), 2u);
}

TEST(Teb, OptionsAreCheckedAndReadFromAConfig) {
  TebOptions o;
  o.max_vel_x = 0;
  EXPECT_THROW(TebPlanner{o}, InvalidArgument);
  o = {};
  o.dt_hysteresis = o.dt_ref;
  EXPECT_THROW(TebPlanner{o}, InvalidArgument);
  o = {};
  o.min_samples = 2;
  EXPECT_THROW(TebPlanner{o}, InvalidArgument);
  const IniFile ini = IniFile::parse("[TEB]\nmax_vel_x = 0.8\nkinematics = car-like\nmin_turning_radius = 1.5\n", "teb.ini");
  const TebOptions read = TebOptions::from_config(ConfigSection(ini, "TEB"));
  EXPECT_EQ(read.max_vel_x, 0.8);
  EXPECT_EQ(read.kinematics, TebKinematics::CarLike);
  EXPECT_EQ(read.min_turning_radius, 1.5);
  const IniFile bad = IniFile::parse("[TEB]\nacc_lim_x = -1\n", "bad.ini");
  EXPECT_THROW(TebOptions::from_config(ConfigSection(bad, "TEB")), ConfigError);
}

// Closed loop: through the gap of a wall, the robot reaches the goal in the
// simulator without touching anything.
TEST(Teb, DrivesThroughAGapInTheSimulator) {
  const NavigationGrid world = nav_test::wall_with_gap(160, 100, 0.05, 80, 40, 24);  // 8 m × 5 m, 1.2 m gap
  NavigationRunOptions o;
  o.simulator.robot_radius = 0.25;
  o.simulator.limits.max_v = 0.6;
  o.teb.robot_radius = 0.25;
  o.teb.max_vel_x = 0.5;
  o.global.method = GridPlannerMethod::AStar;
  for (const auto& [start, goal] : {std::pair{SE2d(1.0, 1.0, 0.0), SE2d(7.0, 4.0, 0.0)},
                                    std::pair{SE2d(7.0, 1.0, std::numbers::pi / 2), SE2d(1.0, 4.0, 0.0)}}) {
    const NavigationRunResult r = run_navigation(world, start, goal, o);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_LT((r.driven.back().translation() - goal.translation()).norm(), o.goal_tolerance);
    EXPECT_GT(r.min_clearance, 0.0);
    EXPECT_EQ(r.replans, 0);
    EXPECT_GE(r.length, r.global.path.length * 0.9);
  }
}

}  // namespace
}  // namespace rove
