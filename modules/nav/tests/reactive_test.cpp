#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "nav_test_worlds.h"
#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/nav/holonomic.h"
#include "rove/nav/navigation_run.h"
#include "rove/nav/ptg.h"
#include "rove/nav/reactive_navigator.h"
#include "rove/nav/teb_edges.h"

namespace rove {
namespace {

PtgOptions small_ptg(PtgFamily family) {
  PtgOptions o;
  o.family = family;
  o.ref_distance = 4.0;
  o.num_paths = 31;
  o.resolution = 0.05;
  o.robot_radius = 0.3;
  return o;
}

TEST(Ptg, CircularArcsLieOnTheirCircles) {
  const Ptg ptg(small_ptg(PtgFamily::DiffDriveC));
  EXPECT_NEAR(ptg.alpha(15), 0.0, 1e-12);
  for (int k = 0; k < ptg.path_count(); ++k) {
    EXPECT_EQ(ptg.alpha_to_index(ptg.alpha(k)), k);
    const VelocityCommand c = ptg.command(k);
    EXPECT_NEAR(c.vx, 1.0, 1e-12);
    EXPECT_NEAR(c.omega, ptg.options().w_max * ptg.alpha(k) / std::numbers::pi, 1e-12);
    for (double d = 0.5; d < ptg.path_length(k); d += 0.5) {
      const Eigen::Vector2d p = ptg.pose_at(k, d).translation();
      if (std::abs(c.omega) < 1e-9) {
        EXPECT_NEAR(p.y(), 0.0, 1e-5);
      } else {
        const double R = c.vx / c.omega;  // center (0, R)
        EXPECT_NEAR((p - Eigen::Vector2d(0, R)).norm(), std::abs(R), 1e-3) << k << " " << d;
      }
    }
  }
}

TEST(Ptg, FamiliesEndOnTheirHeadings) {
  const Ptg cs(small_ptg(PtgFamily::DiffDriveCS));
  const Ptg ccs(small_ptg(PtgFamily::DiffDriveCCS));
  const Ptg alpha(small_ptg(PtgFamily::DiffDriveAlpha));
  for (int k : {3, 10, 20, 27}) {
    const double a = cs.alpha(k);
    EXPECT_NEAR(cs.pose_at(k, cs.path_length(k)).angle(), a, 0.05) << k;
    EXPECT_NEAR(ccs.pose_at(k, ccs.path_length(k)).angle(), a, 0.05) << k;
    // C|C,S starts backward.
    EXPECT_LT(ccs.pose_at(k, 0.1).translation().x(), 0.0) << k;
    // α-A turns toward α.
    EXPECT_LT(std::abs(teb::wrap_angle(alpha.pose_at(k, alpha.path_length(k)).angle() - a)), 0.3) << k;
  }
}

TEST(Ptg, FreeDistancesMatchMarchingTheFootprint) {
  for (const auto family : {PtgFamily::DiffDriveC, PtgFamily::DiffDriveAlpha, PtgFamily::DiffDriveCS}) {
    const Ptg ptg(small_ptg(family));
    const std::vector<Eigen::Vector2d> obstacles = {{2.0, 0.1}, {1.0, 1.5}, {-0.5, -1.2}, {3.0, -2.0}};
    std::vector<double> free;
    ptg.free_distances(obstacles, free);
    ASSERT_EQ(free.size(), 31u);
    for (int k = 0; k < ptg.path_count(); ++k) {
      // Oracle: the first distance at which an obstacle is within `radius`.
      const auto hit = [&](double radius) {
        for (double d = 0; d <= ptg.path_length(k); d += 0.005) {
          const Eigen::Vector2d p = ptg.pose_at(k, d).translation();
          for (const auto& o : obstacles) {
            if ((o - p).norm() <= radius) return d;
          }
        }
        return ptg.path_length(k);
      };
      // Obstacles count at their cells' centers, at most half a cell
      // diagonal (0.036 m) from the points: the free distance lies between
      // the oracle's for radii 0.036 m smaller and larger, give or take a
      // sample.
      EXPECT_LE(free[static_cast<std::size_t>(k)], hit(0.3 - 0.036) + 0.03) << k;
      EXPECT_GE(free[static_cast<std::size_t>(k)], hit(0.3 + 0.036) - 0.03) << k;
    }
    int k = 0;
    double d = 0;
    const Eigen::Vector2d on = ptg.pose_at(20, 1.5).translation();
    EXPECT_LT(ptg.inverse_map(on, k, d), 1e-6);
    EXPECT_NEAR((ptg.pose_at(k, d).translation() - on).norm(), 0.0, 1e-6);
  }
  // inverse_map and distance_to_path against scanning every sample.
  const Ptg ptg(small_ptg(PtgFamily::DiffDriveAlpha));
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int t = 0; t < 50; ++t) {
    const Eigen::Vector2d p(u(rng), u(rng));
    double best = std::numeric_limits<double>::infinity();
    for (int j = 0; j < ptg.path_count(); ++j) {
      double along = std::numeric_limits<double>::infinity();
      // Every sample (pose_at rounds to the nearest one and clamps at the end).
      for (int m = 0; m <= static_cast<int>(ptg.path_length(j) / 0.025) + 2; ++m) {
        along = std::min(along, (ptg.pose_at(j, 0.025 * m).translation() - p).norm());
      }
      best = std::min(best, along);
      EXPECT_NEAR(ptg.distance_to_path(j, ptg.path_length(j), p), along, 1e-5) << j;
    }
    int k = 0;
    double d = 0;
    const double e = ptg.inverse_map(p, k, d);
    EXPECT_NEAR(e, best, 1e-5);
    EXPECT_NEAR((ptg.pose_at(k, d).translation() - p).norm(), e, 1e-5);
  }
  // An obstacle the footprint already holds (0.25 m ahead, radius 0.3):
  // forward it blocks at once, backward it does not.
  PtgOptions back_options = small_ptg(PtgFamily::DiffDriveC);
  back_options.k = -1;
  const Ptg forward(small_ptg(PtgFamily::DiffDriveC)), backward(back_options);
  std::vector<double> f, b;
  forward.free_distances({Eigen::Vector2d(0.25, 0.0)}, f);
  backward.free_distances({Eigen::Vector2d(0.25, 0.0)}, b);
  EXPECT_LT(f[15], 0.05);
  EXPECT_NEAR(b[15], backward.path_length(15), 1e-9);
  PtgOptions bad = small_ptg(PtgFamily::DiffDriveC);
  bad.num_paths = 2;
  EXPECT_THROW(Ptg{bad}, InvalidArgument);
}

std::vector<double> open_space(int n) { return std::vector<double>(static_cast<std::size_t>(n), 1.0); }

TEST(Holonomic, OpenSpaceHeadsForTheTarget) {
  const std::vector<double> free = open_space(61);
  const HolonomicInput in{free, 0.6, 0.8, -1};
  const int kt = static_cast<int>(std::lround(0.5 * (61 * (1 + 0.6 / std::numbers::pi) - 1)));
  for (const HolonomicOutput out : {holonomic_vff(in, {}), holonomic_nd(in, {}), holonomic_full_eval(in, {})}) {
    EXPECT_LE(std::abs(out.direction - kt), 1);
    EXPECT_NEAR(out.speed, 1.0, 1e-12);
  }
  // Near the target each slows down.
  const HolonomicInput close{free, 0.6, 0.05, -1};
  EXPECT_LT(holonomic_vff(close, {}).speed, 1.0);
  EXPECT_LT(holonomic_nd(close, {}).speed, 1.0);
  EXPECT_LT(holonomic_full_eval(close, {}).speed, 1.0);
  EXPECT_THROW(holonomic_vff(HolonomicInput{std::vector<double>{1.0, 1.0}, 0, 1, -1}, {}), InvalidArgument);
}

TEST(Holonomic, BlockedTargetDirectionIsAvoided) {
  // A wall across the target direction (directions 25..35 of 61 free for
  // 0.1 only): every method picks a free direction.
  std::vector<double> free = open_space(61);
  for (int k = 22; k <= 38; ++k) free[static_cast<std::size_t>(k)] = 0.1;
  const HolonomicInput in{free, 0.0, 0.5, -1};
  for (const HolonomicOutput out : {holonomic_vff(in, {}), holonomic_nd(in, {}), holonomic_full_eval(in, {})}) {
    EXPECT_GT(free[static_cast<std::size_t>(out.direction)], 0.5) << out.direction;
    EXPECT_GT(out.speed, 0.0);
  }
}

TEST(ReactiveNavigator, ReadsMrptsConfigUnchanged) {
  const IniFile ini = IniFile::load("/usr/share/mrpt/config_files/navigation-ptgs/reactive2d_config.ini");
  std::vector<IgnoredConfigKey> ignored;
  const ReactiveNavigatorOptions o = ReactiveNavigatorOptions::from_config(ini, &ignored);
  EXPECT_EQ(o.holonomic, HolonomicMethod::FullEval);
  ASSERT_EQ(o.ptgs.size(), 3u);
  EXPECT_EQ(o.ptgs[0].family, PtgFamily::DiffDriveC);
  EXPECT_EQ(o.ptgs[1].family, PtgFamily::DiffDriveAlpha);
  EXPECT_EQ(o.ptgs[2].k, -1.0);
  EXPECT_EQ(o.ptgs[2].score_priority, 0.5);
  EXPECT_EQ(o.ptgs[0].num_paths, 121);
  EXPECT_NEAR(o.ptgs[0].w_max, 60 * std::numbers::pi / 180, 1e-12);
  EXPECT_EQ(o.ptgs[0].robot_radius, 0.5);
  EXPECT_EQ(o.ref_distance, 10.0);
  EXPECT_EQ(o.full_eval.phases.size(), 3u);
  EXPECT_EQ(o.nd.factor_weights[2], 2.0);
  EXPECT_EQ(o.vff.target_attractive_force, 20.0);
  EXPECT_FALSE(ignored.empty());
  // Another scalarization is refused, naming its key.
  const IniFile changed = IniFile::parse(
      "[CMultiObjMotionOpt_Scalarization]\nscalar_score_formula = 2*target_distance\n", "changed.ini");
  try {
    ReactiveNavigatorOptions::from_config(changed);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "scalar_score_formula");
  }
  const IniFile typo = IniFile::parse("[CHolonomicVFF]\nTARGET_ATTRACTIVE_FORCES = 3\n", "typo.ini");
  EXPECT_THROW(ReactiveNavigatorOptions::from_config(typo), ConfigError);
}

TEST(ReactiveNavigator, MovesTowardTheTargetAndStopsThere) {
  ReactiveNavigatorOptions o = ReactiveNavigatorOptions::defaults(0.3);
  for (auto& p : o.ptgs) p.ref_distance = 4.0, p.num_paths = 41;
  ReactiveNavigator nav(o);
  const ReactiveResult ahead = nav.step(SE2d(0, 0, 0), {}, Eigen::Vector2d(3, 0.2), 0.1);
  ASSERT_EQ(ahead.termination, ReactiveTermination::Moving) << ahead.message;
  EXPECT_GT(ahead.command.vx, 0.5);
  EXPECT_FALSE(ahead.trajectory.empty());
  const ReactiveResult behind = nav.step(SE2d(0, 0, 0), {}, Eigen::Vector2d(-3, 0.5), 0.1);
  ASSERT_TRUE(behind.ok());
  EXPECT_GT(std::abs(behind.command.omega), 0.1);
  EXPECT_EQ(nav.step(SE2d(1, 1, 0), {}, Eigen::Vector2d(1.05, 1.0), 0.1).termination, ReactiveTermination::TargetReached);
  // Surrounded at arm's length: blocked, zero command.
  std::vector<Eigen::Vector2d> ring;
  for (int i = 0; i < 72; ++i) ring.emplace_back(0.32 * std::cos(i * 0.0873), 0.32 * std::sin(i * 0.0873));
  const ReactiveResult boxed = nav.step(SE2d(0, 0, 0), ring, Eigen::Vector2d(3, 0), 0.1);
  EXPECT_EQ(boxed.termination, ReactiveTermination::Blocked);
  EXPECT_EQ(boxed.command, VelocityCommand{});
}

TEST(ReactiveNavigator, DrivesThroughAGapInTheSimulator) {
  const NavigationGrid world = nav_test::wall_with_gap(160, 100, 0.05, 80, 38, 28);  // 1.4 m gap
  for (const auto method : {HolonomicMethod::FullEval, HolonomicMethod::NearnessDiagram, HolonomicMethod::Vff}) {
    NavigationRunOptions o;
    o.planner = LocalPlannerKind::Reactive;
    o.simulator.robot_radius = 0.25;
    o.reactive = ReactiveNavigatorOptions::defaults(0.35);
    o.reactive.holonomic = method;
    for (auto& p : o.reactive.ptgs) p.ref_distance = 5.0, p.num_paths = 61;
    o.global.method = GridPlannerMethod::AStar;
    const NavigationRunResult r = run_navigation(world, SE2d(1.0, 1.0, 0.0), SE2d(7.0, 4.0, 0.0), o);
    EXPECT_TRUE(r.ok()) << to_string(method) << ": " << r.message;
    EXPECT_NE(r.termination, NavigationTermination::Collision) << to_string(method);
  }
}

}  // namespace
}  // namespace rove
