#include "rove/nav/navigation_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>

#include "nav_test_worlds.h"
#include "rove/core/error.h"
#include "rove/maps/occupancy_grid.h"

namespace rove {
namespace {

// Distance from p to the square of cell (x, y) of g.
double to_square(const NavigationGrid& g, const Eigen::Vector2d& p, int x, int y) {
  const double lx = g.x_min() + x * g.resolution(), ly = g.y_min() + y * g.resolution();
  const double dx = std::max({lx - p.x(), 0.0, p.x() - (lx + g.resolution())});
  const double dy = std::max({ly - p.y(), 0.0, p.y() - (ly + g.resolution())});
  return std::hypot(dx, dy);
}

TEST(NavigationGrid, ClearanceMatchesBruteForce) {
  const NavigationGrid g = nav_test::random_world(37, 23, 0.1, 0.05, 7);
  const int nx = 37, ny = 23;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      double best = std::numeric_limits<double>::infinity();
      // Obstacles, and the ring of cells just outside the grid.
      for (int v = -1; v <= ny; ++v) {
        for (int u = -1; u <= nx; ++u) {
          if (!g.occupied(u, v)) continue;
          if (u >= 0 && u < nx && v >= 0 && v < ny && !g.occupied(u, v)) continue;
          best = std::min(best, std::hypot(u - x, v - y) * 0.1);
        }
      }
      if (g.occupied(x, y)) best = 0;
      ASSERT_NEAR(g.clearance(x, y), best, 1e-5) << x << "," << y;
    }
  }
  EXPECT_EQ(g.clearance(-1, 0), 0.0f);
  EXPECT_TRUE(g.occupied(nx, 0));
}

TEST(NavigationGrid, DistanceToObstacleMatchesBruteForce) {
  const NavigationGrid g = nav_test::random_world(30, 20, 0.1, 0.03, 11);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(g.x_min() - 0.2, g.x_max() + 0.2), uy(g.y_min() - 0.2, g.y_max() + 0.2);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    double best = std::min({p.x() - g.x_min(), g.x_max() - p.x(), p.y() - g.y_min(), g.y_max() - p.y()});
    best = std::max(best, 0.0);
    for (int y = 0; y < 20; ++y)
      for (int x = 0; x < 30; ++x)
        if (g.occupied(x, y)) best = std::min(best, to_square(g, p, x, y));
    for (const double cap : {0.05, 0.3, 1.0, 10.0}) {
      ASSERT_NEAR(g.distance_to_obstacle(p, cap), std::min(best, cap), 1e-9) << p.transpose();
    }
  }
}

// A segment and an axis-aligned square intersect (Liang–Barsky clipping
// against the square grown by eps).
bool touches(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x0, double y0, double side) {
  const double eps = 1e-9;
  double t0 = 0, t1 = 1;
  const Eigen::Vector2d d = b - a;
  const double lo[2] = {x0 - eps, y0 - eps}, hi[2] = {x0 + side + eps, y0 + side + eps};
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

TEST(NavigationGrid, VisitSegmentVisitsExactlyTheCellsItCrosses) {
  const NavigationGrid g = nav_test::empty_room(20, 20, 0.5);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 11.0);
  std::uniform_int_distribution<int> grid_pt(0, 20);
  for (int i = 0; i < 400; ++i) {
    Eigen::Vector2d a(u(rng), u(rng)), b(u(rng), u(rng));
    if (i % 4 == 0) {  // through cell corners exactly
      a = Eigen::Vector2d(grid_pt(rng), grid_pt(rng)) * 0.5;
      b = a + Eigen::Vector2d(grid_pt(rng) - 10, grid_pt(rng) - 10) * 0.5;
    }
    std::vector<std::pair<int, int>> cells;
    EXPECT_TRUE(g.visit_segment(a, b, [&](int x, int y) {
      cells.emplace_back(x, y);
      return true;
    }));
    ASSERT_FALSE(cells.empty());
    EXPECT_EQ(cells.front(), std::make_pair(g.cell_x(a.x()), g.cell_y(a.y())));
    EXPECT_EQ(cells.back(), std::make_pair(g.cell_x(b.x()), g.cell_y(b.y())));
    const std::set<std::pair<int, int>> visited(cells.begin(), cells.end());
    EXPECT_EQ(visited.size(), cells.size()) << "a cell visited twice";
    for (const auto& [x, y] : cells) {
      EXPECT_TRUE(touches(a, b, x * 0.5, y * 0.5, 0.5)) << x << "," << y;
    }
    // Every cell a dense sampling of the segment lands in is visited.
    for (int k = 0; k <= 2000; ++k) {
      const Eigen::Vector2d p = a + (b - a) * (k / 2000.0);
      EXPECT_TRUE(visited.count({g.cell_x(p.x()), g.cell_y(p.y())})) << p.transpose();
    }
  }
}

TEST(NavigationGrid, UnknownCellsAreObstaclesAtMrptsThreshold) {
  OccupancyGrid occ(0.0f, 2.0f, 0.0f, 1.0f, 0.1f, 0.5f);  // all unknown
  occ.set_free_probability(3, 4, 0.9f);
  occ.set_free_probability(5, 5, 0.1f);
  const NavigationGrid g = NavigationGrid::from_occupancy(occ);
  EXPECT_FALSE(g.occupied(3, 4));
  EXPECT_TRUE(g.occupied(5, 5));
  EXPECT_TRUE(g.occupied(0, 0));
  const NavigationGrid lenient = NavigationGrid::from_occupancy(occ, 0.4f);
  EXPECT_FALSE(lenient.occupied(0, 0));
  EXPECT_TRUE(lenient.occupied(5, 5));
  EXPECT_NEAR(lenient.clearance(5, 7), 0.2, 1e-6);
  EXPECT_THROW(NavigationGrid::from_occupancy(occ, 1.5f), InvalidArgument);
  EXPECT_THROW(NavigationGrid::from_mask(2, 2, 0, 0, 0.0, std::vector<std::uint8_t>(4)), InvalidArgument);
  EXPECT_THROW(NavigationGrid::from_mask(2, 2, 0, 0, 0.1, std::vector<std::uint8_t>(3)), InvalidArgument);
}

TEST(NavigationGrid, SegmentFreeAgreesWithClearances) {
  const NavigationGrid g = nav_test::wall_with_gap(40, 40, 0.1, 20, 18, 6);
  // Through the gap's middle: clearance 0.3 at most there.
  const Eigen::Vector2d a(0.5, 2.1), b(3.5, 2.1);
  EXPECT_NEAR(g.segment_clearance(a, b), 0.3, 1e-6);
  EXPECT_TRUE(g.segment_free(a, b, 0.25));
  EXPECT_FALSE(g.segment_free(a, b, 0.3 + 1e-6));
  EXPECT_EQ(g.segment_clearance(Eigen::Vector2d(0.5, 0.5), Eigen::Vector2d(3.5, 0.5)), 0.0f);
}

}  // namespace
}  // namespace rove
