// TiledGrid: its insertion against insert_scan on a flat OccupancyGrid (the
// oracle), its likelihood field against GridLikelihoodModel, its distances
// against brute force, and copy-on-write sharing as properties.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "rove/core/error.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/maps/tiled_grid.h"
#include "rove/poses/pose3.h"

namespace rove {
namespace {

constexpr float kRes = 0.05f;

// The world is shifted by kOff so that the flat oracle grid can start at
// the origin: its cell boundaries are then the tiled grid's to the last bit.
constexpr double kOff = 20.0;

// Range from p along angle a to the walls of the room [−4, 6] × [−3, 5]
// with a pillar [1, 1.6] × [1, 1.6] (shifted by kOff).
double room_range(double px, double py, double a) {
  px -= kOff;
  py -= kOff;
  const double dx = std::cos(a), dy = std::sin(a);
  double best = std::numeric_limits<double>::infinity();
  const auto slab = [&](double x0, double x1, double y0, double y1, bool inside) {
    // Ray against the axis-aligned box: exit distance from inside, entry from outside.
    double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 2; ++k) {
      const double o = k == 0 ? px : py, d = k == 0 ? dx : dy;
      const double lo = k == 0 ? x0 : y0, hi = k == 0 ? x1 : y1;
      if (std::abs(d) < 1e-12) {
        if (o < lo || o > hi) return;
        continue;
      }
      double ta = (lo - o) / d, tb = (hi - o) / d;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (t0 > t1) return;
    const double t = inside ? t1 : t0;
    if (t > 0) best = std::min(best, t);
  };
  slab(-4, 6, -3, 5, true);
  slab(1, 1.6, 1, 1.6, false);
  return best;
}

RangeScan2D room_scan(const SE2d& pose, std::mt19937_64& rng, int rays = 181) {
  std::normal_distribution<double> noise(0.0, 0.01);
  RangeScan2D s;
  s.aperture = std::numbers::pi;
  s.max_range = 20.0f;
  std::vector<float> r;
  for (int i = 0; i < rays; ++i) {
    const double a = pose.angle() - std::numbers::pi / 2 + std::numbers::pi * i / (rays - 1);
    const double d = room_range(pose.translation().x(), pose.translation().y(), a);
    r.push_back(d < 20.0 && (i % 37) != 5 ? static_cast<float>(d + noise(rng)) : 0.0f);
  }
  s.set_ranges(std::move(r));
  return s;
}

// Poses off the cells' boundaries: a sensor exactly on a boundary falls in
// one cell or the other with the last bit of the grid's float origin.
std::vector<SE2d> poses() {
  std::vector<SE2d> out;
  for (const auto& [x, y, a] : {std::array<double, 3>{0.013, 0.021, 0.0}, {0.717, 0.331, 0.6},
                                {-1.512, 2.009, -2.0}, {3.027, -1.011, 2.5}, {0.219, 3.483, 1.2}}) {
    out.emplace_back(x + kOff, y + kOff, a);
  }
  return out;
}

// A flat grid on the same lattice, large enough never to grow.
OccupancyGrid flat_grid() { return OccupancyGrid(0.0f, 40.0f, 0.0f, 40.0f, kRes); }

// At most `tolerance` of the flat grid's known cells differ.
void expect_same_cells(const TiledGrid& tiled, const OccupancyGrid& flat, double tolerance = 0.0) {
  std::size_t compared = 0, differ = 0;
  for (std::uint32_t y = 0; y < flat.size_y(); ++y) {
    for (std::uint32_t x = 0; x < flat.size_x(); ++x) {
      const int cx = static_cast<int>(std::lround(flat.x_min() / kRes)) + static_cast<int>(x);
      const int cy = static_cast<int>(std::lround(flat.y_min() / kRes)) + static_cast<int>(y);
      const std::int8_t a = flat.cell(static_cast<int>(x), static_cast<int>(y));
      differ += a != tiled.cell(cx, cy) ? 1 : 0;
      compared += a != 0 ? 1 : 0;
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_LE(static_cast<double>(differ), tolerance * static_cast<double>(compared));
}

TEST(TiledGrid, InsertionEqualsFlatInsertion) {
  for (const bool widening : {false, true}) {
    std::mt19937_64 rng(3);
    GridInsertionOptions opt;
    opt.widening_beams_with_distance = widening;
    opt.max_distance_insertion = 15.0f;
    TiledGrid tiled(kRes);
    OccupancyGrid flat = flat_grid();
    for (const SE2d& p : poses()) {
      const RangeScan2D scan = room_scan(p, rng);
      const TiledInsertResult r = insert_scan(tiled, scan, p, opt);
      EXPECT_TRUE(r.insertion.inserted());
      insert_scan(flat, scan, Pose3(Pose2(p.translation().x(), p.translation().y(), p.angle())), opt);
    }
    ASSERT_EQ(flat.size_x(), 800u) << "the flat oracle grew";
    // Thin rays: the same cells. Widening beams cut their triangles'
    // corners at float cell boundaries, so two flat grids of different
    // origins already differ in a few cells (the window is one).
    expect_same_cells(tiled, flat, widening ? 2e-3 : 0.0);
    // Every tile's occupied bits, kept per written cell, are its cells'.
    std::size_t tiles = 0;
    for (int ty = -2; ty < 40 / kRes / GridTile::kSide + 2; ++ty) {
      for (int tx = -2; tx < 40 / kRes / GridTile::kSide + 2; ++tx) {
        const GridTile* t = tiled.tile_at(tx * GridTile::kSide, ty * GridTile::kSide);
        if (t == nullptr) continue;
        GridTile fresh = *t;
        EXPECT_FALSE(fresh.update_occupied()) << tx << " " << ty;
        ++tiles;
      }
    }
    EXPECT_EQ(tiles, tiled.tile_count());
    // The export holds the same cells.
    const OccupancyGrid exported = tiled.to_occupancy_grid();
    TiledGrid back(kRes);
    back.assign(exported);
    EXPECT_TRUE(back == tiled);
  }
}

TEST(TiledGrid, DistancesMatchBruteForce) {
  std::mt19937_64 rng(5);
  TiledGrid g(kRes);
  std::uniform_int_distribution<int> cell(-70, 70);
  std::vector<std::pair<int, int>> occupied;
  for (int i = 0; i < 60; ++i) {
    const int x = cell(rng), y = cell(rng);
    g.set_cell(x, y, -100);
    occupied.emplace_back(x, y);
  }
  g.set_cell(3, 3, 50);  // free cells are not occupied
  for (int i = 0; i < 3000; ++i) {
    const int x = cell(rng), y = cell(rng);
    for (const int r : {0, 3, 9, 31}) {
      std::uint32_t best = std::numeric_limits<std::uint32_t>::max();
      for (const auto& [ox, oy] : occupied) {
        if (!g.occupied(ox, oy)) continue;
        best = std::min<std::uint32_t>(best, static_cast<std::uint32_t>((ox - x) * (ox - x) + (oy - y) * (oy - y)));
      }
      const std::uint32_t got = g.squared_distance_to_occupied(x, y, r);
      if (best <= static_cast<std::uint32_t>(r * r)) {
        ASSERT_EQ(got, best) << x << " " << y << " r " << r;
      } else {
        ASSERT_GT(got, static_cast<std::uint32_t>(r * r));
      }
    }
  }
}

TEST(TiledGrid, LikelihoodEqualsFlatModel) {
  std::mt19937_64 rng(7);
  GridInsertionOptions ins;
  TiledGrid tiled(kRes);
  OccupancyGrid flat = flat_grid();
  for (const SE2d& p : poses()) {
    const RangeScan2D scan = room_scan(p, rng);
    insert_scan(tiled, scan, p, ins);
    insert_scan(flat, scan, Pose3(Pose2(p.translation().x(), p.translation().y(), p.angle())), ins);
  }
  for (const bool average : {false, true}) {
    GridLikelihoodOptions lo;
    lo.lf_max_corrs_distance = 0.3f;
    lo.lf_std_hit = 0.2f;
    lo.lf_alternate_average_method = average;
    const GridLikelihoodModel<std::int8_t> model(flat, lo, ins);
    const TiledLikelihoodField field(kRes, lo, ins);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 200; ++i) {
      const SE2d pose(kOff + 0.5 + u(rng), kOff + 1.0 + u(rng), 3.0 * u(rng));
      const RangeScan2D scan = room_scan(pose, rng);
      const SE2d guess(pose.translation().x() + 0.1 * u(rng), pose.translation().y() + 0.1 * u(rng),
                       pose.angle() + 0.05 * u(rng));
      const double expected = model.log_likelihood(model.prepare(scan), guess);
      const double got = field.log_likelihood(tiled, field.prepare(scan), guess);
      ASSERT_NEAR(got, expected, 1e-9 * std::max(1.0, std::abs(expected))) << i;
    }
  }
  GridLikelihoodOptions wide;
  wide.lf_max_corrs_distance = 2.0f;
  EXPECT_THROW(TiledLikelihoodField(kRes, wide), InvalidArgument);
  GridLikelihoodOptions other;
  other.method = GridLikelihoodMethod::Consensus;
  EXPECT_THROW(TiledLikelihoodField(kRes, other), InvalidArgument);
}

// log_likelihood_above: the exact value unless it may stop, and when it
// stops, an upper bound of the exact value below the floor asked for.
// The room seen from every test pose, and the likelihood field the
// proposal tests use on it.
TiledGrid room_tiled_grid(std::mt19937_64& rng, const GridInsertionOptions& ins) {
  TiledGrid tiled(kRes);
  for (const SE2d& p : poses()) insert_scan(tiled, room_scan(p, rng), p, ins);
  return tiled;
}
TiledLikelihoodField room_field(const GridInsertionOptions& ins) {
  GridLikelihoodOptions lo;
  lo.lf_max_corrs_distance = 0.3f;
  lo.lf_std_hit = 0.05f;
  return TiledLikelihoodField(kRes, lo, ins);
}

TEST(TiledGrid, LikelihoodAboveAFloorStopsOnlyBelowIt) {
  std::mt19937_64 rng(11);
  GridInsertionOptions ins;
  TiledGrid tiled = room_tiled_grid(rng, ins);
  const TiledLikelihoodField field = room_field(ins);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int stopped = 0;
  for (int i = 0; i < 200; ++i) {
    const SE2d pose(kOff + 0.5 + u(rng), kOff + 1.0 + u(rng), 3.0 * u(rng));
    const TiledScanPoints pts = field.prepare(room_scan(pose, rng));
    // Far from the pose half of the time: most points miss the walls.
    const double off = i % 2 == 0 ? 0.02 : 0.6;
    const SE2d guess(pose.translation().x() + off * u(rng), pose.translation().y() + off * u(rng),
                     pose.angle() + off * u(rng));
    const double exact = field.log_likelihood(tiled, pts, guess);
    for (const double floor : {-std::numeric_limits<double>::infinity(), exact - 1.0}) {
      ASSERT_EQ(field.log_likelihood_above(tiled, pts, guess, floor), exact) << i;
    }
    for (const double margin : {0.5, 5.0, 50.0}) {
      const double got = field.log_likelihood_above(tiled, pts, guess, exact + margin);
      if (got != exact) {
        ++stopped;
        ASSERT_GE(got, exact - 1e-9) << i;
        ASSERT_LT(got, exact + margin) << i;
      }
    }
  }
  EXPECT_GT(stopped, 50);
}

TEST(TiledGrid, DistanceMemoGivesTheSameLikelihoods) {
  std::mt19937_64 rng(13);
  GridInsertionOptions ins;
  TiledGrid tiled = room_tiled_grid(rng, ins);
  const TiledLikelihoodField field = room_field(ins);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // A large memo and one of 16 slots (8 kept, the rest computed each time).
  TiledDistanceMemo memo, tiny(4);
  const double none = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 20; ++i) {
    const SE2d pose(kOff + 0.5 + u(rng), kOff + 1.0 + u(rng), 3.0 * u(rng));
    const TiledScanPoints pts = field.prepare(room_scan(pose, rng));
    // A proposal: the memo cleared once (the points' windows placed afresh),
    // then nearby poses whose points share cells.
    memo.clear();
    tiny.clear();
    for (int k = 0; k < 30; ++k) {
      const SE2d guess(pose.translation().x() + 0.05 * u(rng), pose.translation().y() + 0.05 * u(rng),
                       pose.angle() + 0.02 * u(rng));
      const double exact = field.log_likelihood(tiled, pts, guess);
      ASSERT_EQ(field.log_likelihood_above(tiled, pts, guess, none, memo), exact) << i << " " << k;
      ASSERT_EQ(field.log_likelihood_above(tiled, pts, guess, none, tiny), exact) << i << " " << k;
      const double floor = exact + 5.0;
      ASSERT_EQ(field.log_likelihood_above(tiled, pts, guess, floor, memo),
                field.log_likelihood_above(tiled, pts, guess, floor));
    }
  }
  EXPECT_GT(memo.window_hits() + memo.hits(), 2 * memo.misses());  // most lookups found their cell
  EXPECT_GT(memo.window_hits(), memo.hits());  // most of them in the points' windows
  // Poses far apart with one scan and no clear(): the points leave their
  // windows, so the table answers (or, 8 slots full, does not).
  TiledDistanceMemo wide, wide_tiny(4);
  const SE2d center(kOff + 0.5, kOff + 1.0, 0.2);
  const TiledScanPoints far_pts = field.prepare(room_scan(center, rng));
  for (int k = 0; k < 60; ++k) {
    const SE2d guess(center.translation().x() + 0.6 * u(rng), center.translation().y() + 0.6 * u(rng),
                     center.angle() + 0.3 * u(rng));
    const double exact = field.log_likelihood(tiled, far_pts, guess);
    ASSERT_EQ(field.log_likelihood_above(tiled, far_pts, guess, none, wide), exact) << k;
    ASSERT_EQ(field.log_likelihood_above(tiled, far_pts, guess, none, wide_tiny), exact) << k;
  }
  EXPECT_GT(wide.hits(), wide.window_hits());
  EXPECT_GT(wide_tiny.misses(), wide.misses());
  // After an insertion the memo is cleared and agrees with the new grid.
  const SE2d extra(kOff + 2.0, kOff + 2.0, 0.3);
  insert_scan(tiled, room_scan(extra, rng), extra, ins);
  memo.clear();
  const TiledScanPoints pts = field.prepare(room_scan(extra, rng));
  EXPECT_EQ(field.log_likelihood_above(tiled, pts, extra, none, memo),
            field.log_likelihood(tiled, pts, extra));
  EXPECT_THROW(TiledDistanceMemo(3), InvalidArgument);
}

TEST(TiledGrid, CopiesShareTilesAndWritesNeverLeak) {
  std::mt19937_64 rng(11);
  TiledGrid a(kRes);
  const SE2d p0(kOff, kOff, 0.0);
  insert_scan(a, room_scan(p0, rng), p0);
  const std::size_t tiles = a.tile_count();
  ASSERT_GT(tiles, 10u);
  const TiledGrid before = a;
  TiledGrid b = a;  // a resampled copy
  {
    const TiledGrid* both[] = {&a, &b};
    EXPECT_EQ(TiledGrid::distinct_tiles(both), tiles);  // copying costs no tile
  }
  // A write through b copies only the tiles it changes.
  const SE2d p1(kOff + 2.0, kOff + 1.0, 1.0);
  const TiledInsertResult r = insert_scan(b, room_scan(p1, rng), p1);
  EXPECT_GT(r.tiles_changed, 0u);
  EXPECT_EQ(r.tiles_copied, r.tiles_changed - (b.tile_count() - tiles));
  EXPECT_TRUE(a == before);  // a's cells did not change
  EXPECT_FALSE(a == b);
  const TiledGrid* both[] = {&a, &b};
  EXPECT_EQ(TiledGrid::distinct_tiles(both), tiles + r.tiles_changed);
  // Untouched tiles are still the same storage.
  std::size_t shared = 0;
  for (int cy = 320; cy < 520; cy += 32) {
    for (int cx = 310; cx < 530; cx += 32) {
      if (a.tile_at(cx, cy) != nullptr && a.tile_at(cx, cy) == b.tile_at(cx, cy)) ++shared;
    }
  }
  EXPECT_GT(shared, 0u);
  // set_cell on a shared tile copies it too.
  TiledGrid c = a;
  ASSERT_NE(a.tile_at(400, 400), nullptr);
  ASSERT_EQ(a.tile_at(400, 400), c.tile_at(400, 400));
  c.set_cell(400, 400, -120);
  EXPECT_EQ(a.cell(400, 400), before.cell(400, 400));
  EXPECT_EQ(c.cell(400, 400), -120);
  EXPECT_TRUE(c.occupied(400, 400));
  EXPECT_NE(a.tile_at(400, 400), c.tile_at(400, 400));
}

TEST(TiledGrid, DeclinedScanChangesNothing) {
  std::mt19937_64 rng(2);
  TiledGrid g(kRes);
  RangeScan2D scan = room_scan(SE2d(0, 0, 0), rng);
  scan.T_robot_sensor = Pose3(0, 0, 0, 0, 0.5, 0);  // pitched
  const TiledInsertResult r = insert_scan(g, scan, SE2d(0, 0, 0));
  EXPECT_EQ(r.insertion.status, GridInsertStatus::NotHorizontal);
  EXPECT_TRUE(g.empty());
  EXPECT_EQ(g.tile_count(), 0u);
  EXPECT_THROW(TiledGrid(0.0f), InvalidArgument);
  EXPECT_THROW(g.squared_distance_to_occupied(0, 0, 32), InvalidArgument);
}

// Reserving the extent beforehand changes no cell and holds no tile.
TEST(TiledGrid, ReserveKeepsTheSameCells) {
  RangeScan2D scan;
  scan.aperture = std::numbers::pi;
  std::vector<float> ranges(181);
  for (std::size_t i = 0; i < ranges.size(); ++i) ranges[i] = 3.0f + 0.02f * static_cast<float>(i % 17);
  scan.set_ranges(ranges);
  TiledGrid a(0.05f), b(0.05f);
  b.reserve(-20.0, 40.0, -30.0, 25.0);
  EXPECT_EQ(b.tile_count(), 0u);
  EXPECT_TRUE(b.empty());
  for (int k = 0; k < 5; ++k) {
    const SE2d pose(3.0 * k, -1.5 * k, 0.4 * k);
    insert_scan(a, scan, pose);
    insert_scan(b, scan, pose);
  }
  EXPECT_TRUE(a == b);
  EXPECT_THROW(b.reserve(1.0, 0.0, 0.0, 1.0), InvalidArgument);
  EXPECT_THROW(b.reserve(0.0, std::nan(""), 0.0, 1.0), InvalidArgument);
  EXPECT_THROW(b.reserve(0.0, 1e12, 0.0, 1.0), InvalidArgument);
}

// Rays through walls: a wall of occupied cells across the rays' path.
TEST(TiledGrid, RaysThroughOccupiedCountsRaysThatCrossAWall) {
  TiledGrid g(0.1f);
  // A wall at x ∈ [2.0, 2.1) m for y ∈ [−1, 1) m, and one at y ∈ [−5.0, −4.9)
  // for x ∈ [−8, −2): the second in negative cells, across tiles.
  for (int cy = -10; cy < 10; ++cy) g.set_cell(20, cy, -100);
  for (int cx = -80; cx < -20; ++cx) g.set_cell(cx, -50, -100);
  RangeScan2D scan;
  scan.aperture = 0.2;
  scan.set_ranges({5.0f, 5.0f, 5.0f});
  // Returns 5 m away, beyond the wall: every ray crossed it.
  RaysThroughOccupied r = rays_through_occupied(g, scan, SE2d(), 0.5);
  EXPECT_EQ(r.rays, 3u);
  EXPECT_EQ(r.through, 3u);
  EXPECT_DOUBLE_EQ(r.fraction(), 1.0);
  // The margin stops the segments before the wall (at 1.5 m).
  r = rays_through_occupied(g, scan, SE2d(), 3.5);
  EXPECT_EQ(r.rays, 3u);
  EXPECT_EQ(r.through, 0u);
  // Returns shorter than the margin are not counted at all.
  r = rays_through_occupied(g, scan, SE2d(), 6.0);
  EXPECT_EQ(r.rays, 0u);
  EXPECT_EQ(r.fraction(), 0.0);
  // Returns on the wall itself: the free part stops short of it.
  scan.set_ranges({2.05f, 2.05f, 2.05f});
  r = rays_through_occupied(g, scan, SE2d(), 0.5);
  EXPECT_EQ(r.through, 0u);
  // One ray of three beyond the wall.
  scan.set_ranges({1.5f, 4.0f, 1.5f});
  r = rays_through_occupied(g, scan, SE2d(), 0.2);
  EXPECT_EQ(r.rays, 3u);
  EXPECT_EQ(r.through, 1u);
  // Turned away from the wall: nothing in the way.
  scan.set_ranges({5.0f, 5.0f, 5.0f});
  EXPECT_EQ(rays_through_occupied(g, scan, SE2d(0.0, 0.0, std::numbers::pi), 0.5).through, 0u);
  // Looking down (−y) from (−4.95, −3.05): through the second wall at −5 m,
  // in negative cells and across a tile boundary.
  r = rays_through_occupied(g, scan, SE2d(-4.95, -3.05, -std::numbers::pi / 2), 0.5);
  EXPECT_EQ(r.through, 3u);
  // The sensor's offset on the robot counts: 2.5 m ahead of the robot the
  // sensor is past the first wall already.
  scan.T_robot_sensor = Pose3(2.5, 0.0, 0.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(rays_through_occupied(g, scan, SE2d(), 0.5).through, 0u);
  // Bad input.
  EXPECT_THROW(rays_through_occupied(g, scan, SE2d(), -1.0), InvalidArgument);
  EXPECT_THROW(rays_through_occupied(g, scan, SE2d(), std::nan("")), InvalidArgument);
  EXPECT_THROW(rays_through_occupied(g, scan, SE2d(std::nan(""), 0.0, 0.0), 0.5), InvalidArgument);
}

}  // namespace
}  // namespace rove
