// Scan-to-grid matching of lidar SLAM against ground truth in the simulated
// building: the bicubic interpolation (values at the nodes, gradient against
// finite differences), the least-squares matcher, and branch-and-bound
// (the max grids against brute force, the bound's admissibility at every
// height, the best pose of the window against exhaustive search, a known
// offset found).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "rove/core/error.h"
#include "rove/slam/branch_and_bound_2d.h"
#include "rove/slam/grid_scan_matcher.h"
#include "rove/slam/probability_grid.h"
#include "sim_building.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

SE2d se2(const Eigen::Vector3d& p) { return SE2d(p.x(), p.y(), p.z()); }

// A submap of the building from `n` noiseless 360° scans around `center`
// (robot frame = grid frame), as lidar SLAM builds one.
ProbabilityGrid building_grid(const Eigen::Vector3d& center, int n = 10) {
  const auto walls = test::building({0, 0});
  std::mt19937_64 rng(1);
  ProbabilityGrid g(0.05);
  const GridScanInserter ins;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d pose = center + Eigen::Vector3d(0.1 * k, 0.05 * (k % 3), 0.02 * k);
    const auto pts = test::simulate_points(walls, pose, 720, 2 * std::numbers::pi, 0.0, rng);
    std::vector<Eigen::Vector2d> hits;
    for (const auto& p : pts) hits.push_back(se2(pose) * p);
    ins.insert(g, pose.head<2>(), hits);
  }
  return g;
}

TEST(GridScanMatcher, InterpolationPassesThroughTheCellsWithItsGradient) {
  const ProbabilityGrid g = building_grid({1.5, 1.5, 0.0});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 8.0);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector2d p(u(rng), u(rng) * 0.5);
    const Eigen::Vector2i c = g.cell_of(p);
    EXPECT_NEAR(interpolate_probability(g, g.cell_center(c.x(), c.y())), g.probability(c.x(), c.y()),
                1e-6);
    Eigen::Vector2d grad;
    interpolate_probability(g, p, &grad);
    const double h = 1e-6;
    for (int a = 0; a < 2; ++a) {
      Eigen::Vector2d d = Eigen::Vector2d::Zero();
      d[a] = h;
      const double num = (interpolate_probability(g, p + d) - interpolate_probability(g, p - d)) / (2 * h);
      EXPECT_NEAR(grad[a], num, 1e-4 * std::max(1.0, std::abs(num))) << k << " axis " << a;
    }
  }
}

// The grid's cells quantize the walls: the match lands within about half a
// cell of the truth (ICP refines it in lidar SLAM).
TEST(GridScanMatcher, RecoversThePoseFromANearbyGuess) {
  const ProbabilityGrid g = building_grid({1.5, 1.5, 0.0});
  const auto walls = test::building({0, 0});
  std::mt19937_64 rng(9);
  const Eigen::Vector3d truth(2.0, 1.6, 0.15);
  const auto pts = test::simulate_points(walls, truth, 180, std::numbers::pi, 0.01, rng);
  GridScanMatcherOptions o;
  o.translation_weight = 0.0;
  o.rotation_weight = 0.0;
  const SE2d guess(truth.x() + 0.04, truth.y() - 0.03, truth.z() + 1.5 * kDeg);
  const GridScanMatchResult r = match_scan_to_grid(g, pts, guess, o);
  EXPECT_NE(r.termination, RegistrationTermination::InvalidInput) << r.message;
  EXPECT_LT((r.T_grid_robot.translation() - truth.head<2>()).norm(), 0.035);
  EXPECT_LT(std::abs(r.T_grid_robot.angle() - truth.z()), 0.5 * kDeg);
  EXPECT_LT(r.final_cost, r.initial_cost);
  EXPECT_GT(r.score, grid_match_score(g, pts, guess));
  // The prior weights pull towards the guess: with them the estimate stays
  // nearer the guess.
  const GridScanMatchResult p = match_scan_to_grid(g, pts, guess, {});
  EXPECT_LT((p.T_grid_robot.translation() - guess.translation()).norm(),
            (r.T_grid_robot.translation() - guess.translation()).norm());
  // Nothing to match: the guess back, InvalidInput.
  const GridScanMatchResult e = match_scan_to_grid(g, std::vector<Eigen::Vector2d>{}, guess, o);
  EXPECT_EQ(e.termination, RegistrationTermination::InvalidInput);
  EXPECT_TRUE(e.T_grid_robot.is_approx(guess));
}

// Random grids with unknown cells for the max-grid and bound properties.
ProbabilityGrid random_grid(std::mt19937_64& rng) {
  ProbabilityGrid g(0.1);
  g.grow_to_include({-1.3, -0.7}, {1.9, 2.2}, 0.0);
  std::uniform_real_distribution<float> p(0.1f, 0.9f);
  std::bernoulli_distribution known(0.7);
  for (int cy = 0; cy < g.size_y(); ++cy)
    for (int cx = 0; cx < g.size_x(); ++cx)
      if (known(rng)) g.set_probability(cx, cy, p(rng));
  return g;
}

TEST(BranchAndBound, MaxGridsHoldTheWindowMaximum) {
  std::mt19937_64 rng(11);
  const ProbabilityGrid g = random_grid(rng);
  const PrecomputedGridStack s(g, 4);
  for (int h = 0; h <= 4; ++h) {
    const int w = 1 << h;
    for (int cy = -w - 1; cy < g.size_y() + 2; ++cy) {
      for (int cx = -w - 1; cx < g.size_x() + 2; ++cx) {
        std::uint8_t m = 0;
        for (int y = cy; y < cy + w; ++y)
          for (int x = cx; x < cx + w; ++x)
            m = std::max(m, PrecomputedGridStack::to_value(g.probability(x, y)));
        ASSERT_EQ(s.value(h, cx, cy), m) << "h " << h << " cell " << cx << ", " << cy;
      }
    }
  }
}

// The bound of every candidate at every height is at least the best score
// of the leaves below it (Hess Eq. 14 makes the bound admissible).
TEST(BranchAndBound, BoundIsAdmissibleAtEveryHeight) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.5);
  for (int trial = 0; trial < 4; ++trial) {
    const ProbabilityGrid g = random_grid(rng);
    const PrecomputedGridStack s(g, 3);
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i < 30; ++i) pts.emplace_back(u(rng), u(rng));
    const BranchAndBoundSearch search(s, pts, SE2d(0.2, 0.4, 0.3), {0.8, 5 * kDeg});
    const int w = search.linear_cells();
    for (int a = 0; a < search.num_angles(); a += 3) {
      for (int h = 1; h <= 3; ++h) {
        for (int dx = -w; dx <= w; ++dx) {
          for (int dy = -w; dy <= w; dy += 2) {
            double best_leaf = 0.0;
            for (int x = dx; x < std::min(dx + (1 << h), w + 1); ++x)
              for (int y = dy; y < std::min(dy + (1 << h), w + 1); ++y)
                best_leaf = std::max(best_leaf, search.score(0, a, x, y));
            ASSERT_GE(search.score(h, a, dx, dy) + 1e-12, best_leaf)
                << "trial " << trial << " h " << h << " a " << a << " d " << dx << "," << dy;
          }
        }
      }
    }
  }
}

// The search returns the best leaf of the window (exhaustive oracle).
TEST(BranchAndBound, FindsTheBestPoseOfTheWindow) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.5);
  for (int trial = 0; trial < 6; ++trial) {
    const ProbabilityGrid g = random_grid(rng);
    const PrecomputedGridStack s(g, 3);
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i < 25; ++i) pts.emplace_back(u(rng), u(rng));
    const BranchAndBoundSearch search(s, pts, SE2d(0.1, 0.3, -0.2), {0.7, 4 * kDeg});
    double best = 0.0;
    for (int a = 0; a < search.num_angles(); ++a)
      for (int dx = -search.linear_cells(); dx <= search.linear_cells(); ++dx)
        for (int dy = -search.linear_cells(); dy <= search.linear_cells(); ++dy)
          best = std::max(best, search.score(0, a, dx, dy));
    const BranchAndBoundResult r = search.search(0.1);
    ASSERT_TRUE(r.found);
    EXPECT_DOUBLE_EQ(r.score, best) << trial;
    // Nothing above a score no pose reaches.
    EXPECT_FALSE(search.search(best).found);
    // Excluding a disc around the best pose, the best of the rest (oracle).
    const double radius = 0.25;
    double rest = 0.0;
    for (int a = 0; a < search.num_angles(); ++a)
      for (int dx = -search.linear_cells(); dx <= search.linear_cells(); ++dx)
        for (int dy = -search.linear_cells(); dy <= search.linear_cells(); ++dy)
          if ((search.pose(a, dx, dy).translation() - r.T_grid_robot.translation()).norm() > radius + 1e-9)
            rest = std::max(rest, search.score(0, a, dx, dy));
    const BranchAndBoundResult second = search.search(0.1, r.T_grid_robot.translation(), radius);
    ASSERT_TRUE(second.found);
    EXPECT_DOUBLE_EQ(second.score, rest) << trial;
  }
}

TEST(GridScanMatcher, CorrelativeSearchFindsAFastTurn) {
  const ProbabilityGrid g = building_grid({1.5, 1.5, 0.0});
  const auto walls = test::building({0, 0});
  std::mt19937_64 rng(4);
  const Eigen::Vector3d truth(2.0, 1.6, 0.15);
  const auto pts = test::simulate_points(walls, truth, 180, std::numbers::pi, 0.01, rng);
  // 9° off: beyond the least-squares matcher's basin, inside the window.
  const SE2d guess(truth.x(), truth.y(), truth.z() + 9 * kDeg);
  const SE2d c = correlative_search_2d(g, pts, guess, {});
  EXPECT_LT(std::abs(c.angle() - truth.z()), 1.0 * kDeg);
  EXPECT_TRUE(c.translation().isApprox(guess.translation()));  // rotation only by default
  CorrelativeSearchOptions wide;
  wide.linear_window = 0.1;
  const SE2d cw = correlative_search_2d(g, pts, SE2d(truth.x() + 0.08, truth.y(), truth.z()), wide);
  EXPECT_LT((cw.translation() - truth.head<2>()).norm(), 0.06);
  CorrelativeSearchOptions bad;
  bad.angular_step = 0.0;
  EXPECT_THROW((void)correlative_search_2d(g, pts, guess, bad), InvalidArgument);
}

TEST(BranchAndBound, FindsAKnownOffsetInTheBuilding) {
  const ProbabilityGrid g = building_grid({9.0, 1.5, 0.0}, 12);
  const PrecomputedGridStack s(g, 6);
  const auto walls = test::building({0, 0});
  std::mt19937_64 rng(21);
  const Eigen::Vector3d truth(9.7, 1.4, 0.4);
  auto pts = test::simulate_points(walls, truth, 180, std::numbers::pi, 0.01, rng);
  const SE2d guess(truth.x() - 1.1, truth.y() + 0.7, truth.z() - 12 * kDeg);
  const BranchAndBoundResult r = branch_and_bound_match(s, pts, guess, {1.5, 20 * kDeg}, 0.5);
  ASSERT_TRUE(r.found);
  EXPECT_GT(r.score, 0.6);
  // Within a cell or two and a few angular steps: the best score of the
  // lattice, on walls quantized to cells.
  EXPECT_LT((r.T_grid_robot.translation() - truth.head<2>()).norm(), 0.1);
  EXPECT_LE(std::abs(r.T_grid_robot.angle() - truth.z()), 3 * r.angular_step);
  EXPECT_LT(r.candidates_scored, r.angles * static_cast<std::size_t>((2 * r.linear_cells + 1) *
                                                                      (2 * r.linear_cells + 1)) / 20);
  // Refined against the grid, it lands within half a cell of the truth.
  GridScanMatcherOptions o;
  o.translation_weight = 0.0;
  o.rotation_weight = 0.0;
  const GridScanMatchResult m = match_scan_to_grid(g, pts, r.T_grid_robot, o);
  EXPECT_LT((m.T_grid_robot.translation() - truth.head<2>()).norm(), 0.035);
  EXPECT_LT(std::abs(m.T_grid_robot.angle() - truth.z()), 0.5 * kDeg);
  // A window that does not hold the truth finds nothing that good.
  const SE2d far(truth.x() + 3.0, truth.y(), truth.z());
  EXPECT_FALSE(branch_and_bound_match(s, pts, far, {0.5, 5 * kDeg}, 0.6).found);
  EXPECT_THROW(BranchAndBoundSearch(s, std::vector<Eigen::Vector2d>{}, guess, {}), InvalidArgument);
  EXPECT_THROW(PrecomputedGridStack(g, 17), InvalidArgument);
}

}  // namespace
}  // namespace rove
