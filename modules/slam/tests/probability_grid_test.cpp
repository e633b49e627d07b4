// The submap grid of lidar SLAM: value coding, growth, the odds update
// (Hess et al. 2016, Eqs. 2-3) and the ray traversal against a dense
// sampling oracle; the scan preprocessing filters.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <utility>

#include "rove/core/error.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/slam/probability_grid.h"
#include "rove/slam/scan_points_2d.h"

namespace rove {
namespace {

double odds(double p) { return p / (1.0 - p); }

TEST(ProbabilityGrid, ValuesCodeTheProbabilityRange) {
  EXPECT_FLOAT_EQ(ProbabilityGrid::value_to_probability(ProbabilityGrid::kUnknown),
                  ProbabilityGrid::kMinProbability);
  EXPECT_EQ(ProbabilityGrid::probability_to_value(0.1f), 1);
  EXPECT_EQ(ProbabilityGrid::probability_to_value(0.9f), ProbabilityGrid::kMaxValue);
  EXPECT_EQ(ProbabilityGrid::probability_to_value(0.0f), 1);  // clamped
  EXPECT_EQ(ProbabilityGrid::probability_to_value(1.0f), ProbabilityGrid::kMaxValue);
  for (const float p : {0.1f, 0.25f, 0.5f, 0.55f, 0.77f, 0.9f}) {
    EXPECT_NEAR(ProbabilityGrid::value_to_probability(ProbabilityGrid::probability_to_value(p)), p,
                1e-4);
  }
  // The update marker does not change the probability a value reads as.
  const std::uint16_t v = ProbabilityGrid::probability_to_value(0.6f);
  EXPECT_EQ(ProbabilityGrid::value_to_probability(v | ProbabilityGrid::kUpdateMarker),
            ProbabilityGrid::value_to_probability(v));
  EXPECT_THROW((void)ProbabilityGrid::probability_to_value(std::nanf("")), InvalidArgument);
  EXPECT_THROW(ProbabilityGrid(0.0), InvalidArgument);
}

TEST(ProbabilityGrid, GrowingKeepsEveryCellWhereItIs) {
  ProbabilityGrid g(0.05);
  g.grow_to_include({-1.0, -1.0}, {1.0, 1.0}, 0.0);
  const Eigen::Vector2i c = g.cell_of({0.32, -0.71});
  g.set_probability(c.x(), c.y(), 0.8f);
  const Eigen::Vector2d center = g.cell_center(c.x(), c.y());
  EXPECT_TRUE((center - Eigen::Vector2d(0.325, -0.725)).norm() < 1e-9);
  g.grow_to_include({-30.0, 2.0}, {-29.0, 40.0});
  const Eigen::Vector2i c2 = g.cell_of({0.32, -0.71});
  EXPECT_NEAR(g.probability(c2.x(), c2.y()), 0.8f, 1e-4);
  EXPECT_EQ(g.known_cells(), 1u);
  const Eigen::Vector2i far = g.cell_of({-29.5, 39.0});
  EXPECT_TRUE(g.contains(far.x(), far.y()));
  EXPECT_FALSE(g.known(far.x(), far.y()));
  EXPECT_FLOAT_EQ(g.probability(-5, -5), ProbabilityGrid::kMinProbability);  // outside
  EXPECT_THROW(g.set_probability(-1, 0, 0.5f), InvalidArgument);
  EXPECT_THROW(g.grow_to_include({1.0, 0.0}, {0.0, 1.0}), InvalidArgument);
}

// Hess Eq. 3 applied k times to the hit cell; the cells of the ray get the
// miss update once per scan even when several rays cross them.
TEST(GridScanInserter, OddsUpdateOncePerScan) {
  GridInsertionOdds o;
  o.hit_probability = 0.55;
  o.miss_probability = 0.49;
  const GridScanInserter ins(o);
  ProbabilityGrid g(0.1);
  const Eigen::Vector2d origin(0.05, 0.05);
  // Three rays to the same hit cell: one hit update, one miss update per cell.
  const std::vector<Eigen::Vector2d> hits = {{2.04, 0.05}, {2.05, 0.06}, {2.06, 0.04}};
  ins.insert(g, origin, hits);
  const Eigen::Vector2i h = g.cell_of({2.05, 0.05});
  EXPECT_NEAR(g.probability(h.x(), h.y()), 0.55, 1e-4);
  const Eigen::Vector2i m = g.cell_of({1.05, 0.05});
  EXPECT_NEAR(g.probability(m.x(), m.y()), 0.49, 1e-4);
  for (int k = 2; k <= 6; ++k) {
    ins.insert(g, origin, hits);
    const double o_hit = std::pow(odds(0.55), k), o_miss = std::pow(odds(0.49), k);
    EXPECT_NEAR(g.probability(h.x(), h.y()), o_hit / (1 + o_hit), 2e-4) << k;
    EXPECT_NEAR(g.probability(m.x(), m.y()), o_miss / (1 + o_miss), 2e-4) << k;
  }
  // No marker left behind.
  for (const std::uint16_t v : g.values()) EXPECT_EQ(v & ProbabilityGrid::kUpdateMarker, 0);
  // Saturation at the range's ends.
  for (int k = 0; k < 200; ++k) ins.insert(g, origin, hits);
  EXPECT_FLOAT_EQ(g.probability(h.x(), h.y()), ProbabilityGrid::kMaxProbability);
  EXPECT_NEAR(g.probability(m.x(), m.y()), ProbabilityGrid::kMinProbability, 1e-6);
}

// The cells a ray updates are those a dense sampling of the segment visits,
// minus the hit's own cell; a hit is never overwritten by another ray's miss.
TEST(GridScanInserter, RaysVisitTheCellsTheSegmentCrosses) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  const GridScanInserter ins;
  for (int trial = 0; trial < 40; ++trial) {
    ProbabilityGrid g(0.1);
    const Eigen::Vector2d origin(u(rng), u(rng)), end(u(rng), u(rng));
    ins.insert(g, origin, std::vector<Eigen::Vector2d>{end});
    std::set<std::pair<int, int>> expected;
    const Eigen::Vector2i e = g.cell_of(end);
    for (int k = 0; k <= 200000; ++k) {
      const Eigen::Vector2i c = g.cell_of(origin + (end - origin) * (k / 200000.0));
      if (c != e) expected.insert({c.x(), c.y()});
    }
    std::set<std::pair<int, int>> got;
    for (int cy = 0; cy < g.size_y(); ++cy)
      for (int cx = 0; cx < g.size_x(); ++cx)
        if (g.known(cx, cy) && !(cx == e.x() && cy == e.y())) got.insert({cx, cy});
    // Dense sampling can miss a corner the segment only grazes: every sampled
    // cell must be traced, and at most a few more.
    for (const auto& c : expected) EXPECT_TRUE(got.count(c)) << trial;
    EXPECT_LE(got.size(), expected.size() + 2) << trial;
    EXPECT_NEAR(g.probability(e.x(), e.y()), 0.55, 1e-4);
  }
  // Free space without a hit: misses only.
  ProbabilityGrid g(0.1);
  GridInsertionOdds no_free;
  no_free.insert_free_space = false;
  GridScanInserter(no_free).insert(g, {0, 0}, std::vector<Eigen::Vector2d>{{1.0, 0.0}},
                                   std::vector<Eigen::Vector2d>{{0.0, 3.0}});
  EXPECT_EQ(g.known_cells(), 1u);
}

TEST(GridInsertionOdds, RejectsProbabilitiesOnTheWrongSide) {
  GridInsertionOdds o;
  o.hit_probability = 0.5;
  EXPECT_THROW(GridScanInserter{o}, InvalidArgument);
  o = {};
  o.miss_probability = 0.6;
  EXPECT_THROW(GridScanInserter{o}, InvalidArgument);
}

TEST(ScanPoints2D, KeepsTheRangeIntervalAndThinsByVoxel) {
  RangeScan2D scan;
  scan.aperture = std::numbers::pi;
  scan.max_range = 80.0f;
  // 181 rays: 0.02 m (too close), 1 m, 40 m (beyond max_range 30), NaN, repeated.
  std::vector<float> r;
  for (int i = 0; i < 181; ++i) {
    const float v[4] = {0.02f, 1.0f, 40.0f, std::nanf("")};
    r.push_back(v[i % 4]);
  }
  scan.set_ranges(r);
  ScanPointsOptions o;
  o.max_range = 30.0;
  o.voxel_size = 0.0;
  const ScanPoints2D p = scan_points_2d(scan, o);
  EXPECT_EQ(p.rays, 181u);
  EXPECT_EQ(p.valid_rays, 136u);  // 46 + 45 + 45 finite ranges
  EXPECT_EQ(p.in_range_rays, 45u);
  EXPECT_EQ(p.points.size(), 45u);
  for (const auto& q : p.points) EXPECT_NEAR(q.norm(), 1.0, 1e-6);
  EXPECT_NEAR(p.max_point_range, 1.0, 1e-6);
  // A 0.5 m voxel merges neighbours; the centroids stay on the arc's hull.
  o.voxel_size = 0.5;
  const ScanPoints2D v = scan_points_2d(scan, o);
  EXPECT_LT(v.points.size(), 20u);
  EXPECT_GT(v.points.size(), 3u);
  for (const auto& q : v.points) EXPECT_LE(q.norm(), 1.0 + 1e-9);
  o.max_range = 0.01;
  EXPECT_THROW((void)scan_points_2d(scan, o), InvalidArgument);
}

TEST(ScanPoints2D, VoxelFilterAveragesEachVoxel) {
  const std::vector<Eigen::Vector2d> pts = {{0.1, 0.1}, {0.3, 0.3}, {1.2, 0.1}, {-0.1, 0.0},
                                            {std::nan(""), 0.0}};
  const auto f = voxel_filter_2d(pts, 1.0);
  ASSERT_EQ(f.size(), 3u);
  // Ordered by voxel (y, then x): (-1, 0), (0, 0), (1, 0).
  EXPECT_TRUE(f[0].isApprox(Eigen::Vector2d(-0.1, 0.0)));
  EXPECT_TRUE(f[1].isApprox(Eigen::Vector2d(0.2, 0.2)));
  EXPECT_TRUE(f[2].isApprox(Eigen::Vector2d(1.2, 0.1)));
  EXPECT_EQ(voxel_filter_2d(pts, 0.0).size(), 4u);
  EXPECT_THROW((void)voxel_filter_2d(pts, -1.0), InvalidArgument);
}

TEST(ScanPoints2D, AdaptiveFilterKeepsAtLeastTheTarget) {
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < 2000; ++i) pts.emplace_back(0.01 * i, std::sin(0.01 * i));
  AdaptiveVoxelFilterOptions o;
  o.max_length = 2.0;
  o.min_num_points = 150;
  o.max_range = 100.0;
  const auto f = adaptive_voxel_filter_2d(pts, o);
  EXPECT_GE(f.size(), 150u);
  EXPECT_LT(f.size(), 400u);  // the bisection thins as far as it can
  // Few points: all of them, within the range.
  o.min_num_points = 5000;
  EXPECT_EQ(adaptive_voxel_filter_2d(pts, o).size(), 2000u);
  o.max_range = 5.0;
  EXPECT_LT(adaptive_voxel_filter_2d(pts, o).size(), 2000u);
  // A coarse voxel that already leaves enough points is used as is.
  o = {};
  o.min_num_points = 10;
  o.max_length = 1.0;
  EXPECT_EQ(adaptive_voxel_filter_2d(pts, o).size(), voxel_filter_2d(pts, 1.0).size());
}

}  // namespace
}  // namespace rove
