// Properties and oracles for the occupancy grid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <limits>
#include <utility>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/maps/grid_clearance.h"
#include "rove/maps/grid_entropy.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/occupancy_grid.h"

namespace rove {
namespace {

TEST(GridLogOdds, TablesAreMonotoneAndRoundTrip) {
  const auto& lut = LogOddsLut<std::int8_t>::instance();
  EXPECT_EQ(lut.p2l(0.5f), 0);
  EXPECT_FLOAT_EQ(lut.l2p(0), 0.5f);
  for (int l = -127; l < 127; ++l) {
    EXPECT_LT(lut.l2p(static_cast<std::int8_t>(l)), lut.l2p(static_cast<std::int8_t>(l + 1)));
  }
  EXPECT_EQ(lut.l2p(-128), lut.l2p(-127));
  for (float p = 0.0f; p <= 1.0f; p += 0.01f) EXPECT_NEAR(lut.l2p(lut.p2l(p)), p, 0.04f);
}

TEST(OccupancyGrid, ResizeKeepsContentAndWorldPositions) {
  OccupancyGrid g(-1, 1, -1, 1, 0.1f);
  g.set_free_probability(g.x_to_idx(0.33), g.y_to_idx(-0.47), 0.9f);
  const float before = g.free_probability_at(0.33, -0.47);
  g.resize(-7.3f, 2.0f, -1.0f, 9.1f);
  EXPECT_LE(g.x_min(), -7.3f);
  EXPECT_GE(g.y_max(), 9.1f);
  EXPECT_EQ(g.free_probability_at(0.33, -0.47), before);
  EXPECT_EQ(g.free_probability_at(-6.0, 8.0), 0.5f);
  EXPECT_THROW(g.resize(1.0f, 0.0f, 0.0f, 1.0f), InvalidArgument);
  EXPECT_THROW(OccupancyGrid(0, 1, 0, 1, -0.1f), InvalidArgument);
  EXPECT_THROW(g.set_free_probability(0, 0, std::nanf("")), InvalidArgument);
}

// Growths in every direction, most of them within the capacity the first
// one reserved (rows move in place): each cell keeps its value at its world
// position and every new cell holds the fill value of its growth.
TEST(OccupancyGrid, RepeatedGrowthKeepsEveryCell) {
  std::mt19937 rng(3);
  OccupancyGrid g(-1, 1, -0.5f, 1.5f, 0.1f);
  std::uniform_int_distribution<int> val(-128, 127);
  for (auto& c : g.mutable_cells()) c = static_cast<std::int8_t>(val(rng));
  std::uniform_real_distribution<float> grow(0.0f, 0.6f);
  std::uniform_int_distribution<int> side(0, 15);
  for (int k = 0; k < 40; ++k) {
    SCOPED_TRACE(k);
    const OccupancyGrid before = g;
    const int s = side(rng);  // which limits move, as bits
    const float p_fill = k % 2 ? 0.5f : 0.3f;
    g.resize(s & 1 ? g.x_min() - grow(rng) : g.x_min(), s & 2 ? g.x_max() + grow(rng) : g.x_max(),
             s & 4 ? g.y_min() - grow(rng) : g.y_min(), s & 8 ? g.y_max() + grow(rng) : g.y_max(),
             p_fill, false);
    const std::int8_t fill = LogOddsLut<std::int8_t>::instance().p2l(p_fill);
    for (int y = 0; y < static_cast<int>(g.size_y()); ++y) {
      for (int x = 0; x < static_cast<int>(g.size_x()); ++x) {
        const float wx = g.idx_to_x(static_cast<std::size_t>(x));
        const float wy = g.idx_to_y(static_cast<std::size_t>(y));
        const int ox = before.x_to_idx(wx), oy = before.y_to_idx(wy);
        const std::int8_t want = before.contains(ox, oy) && wx > before.x_min() && wy > before.y_min()
                                     ? before.cell(ox, oy)
                                     : fill;
        ASSERT_EQ(g.cell(x, y), want) << "cell (" << x << ", " << y << ") of " << g.size_x()
                                      << " x " << g.size_y();
      }
    }
    // Fresh random content, so that the next growth moves distinct values.
    for (auto& c : g.mutable_cells()) c = static_cast<std::int8_t>(val(rng));
  }
}

TEST(GridClearance, DistanceTransformMatchesBruteForce) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    OccupancyGrid g(0, 3.0f + trial % 4, 0, 2.0f + trial % 3, 0.1f);
    std::uniform_int_distribution<int> ux(0, static_cast<int>(g.size_x()) - 1),
        uy(0, static_cast<int>(g.size_y()) - 1);
    const int n_occ = trial % 7;
    for (int k = 0; k < n_occ; ++k) g.set_free_probability(ux(rng), uy(rng), 0.0f);
    const auto d2 = squared_distance_to_occupied(g, std::int8_t{0});
    for (int y = 0; y < static_cast<int>(g.size_y()); ++y) {
      for (int x = 0; x < static_cast<int>(g.size_x()); ++x) {
        std::uint64_t best = std::numeric_limits<std::uint64_t>::max();
        for (int v = 0; v < static_cast<int>(g.size_y()); ++v)
          for (int u = 0; u < static_cast<int>(g.size_x()); ++u)
            if (g.cell(u, v) < 0)
              best = std::min<std::uint64_t>(best, static_cast<std::uint64_t>((u - x) * (u - x) + (v - y) * (v - y)));
        ASSERT_EQ(d2[g.index(x, y)], best) << x << "," << y;
      }
    }
  }
}

// The transform delivered row by row: every row once, the same values as
// the whole transform (and as brute force, above), on sparse and dense
// obstacles, single rows and columns, and a grid without obstacles.
TEST(GridClearance, RowsByRowEqualTheWholeTransform) {
  std::mt19937 rng(13);
  const std::pair<float, float> sizes[] = {{0.1f, 2.0f}, {2.0f, 0.1f}, {3.3f, 2.7f}, {0.1f, 0.1f}};
  for (int trial = 0; trial < 24; ++trial) {
    const auto [w, h] = sizes[trial % 4];
    OccupancyGrid g(0, w, 0, h, 0.1f);
    std::bernoulli_distribution occupied(trial < 8 ? 0.02 : trial < 16 ? 0.5 : 0.0);
    for (auto& c : g.mutable_cells()) c = occupied(rng) ? std::int8_t{-100} : std::int8_t{100};
    const auto whole = squared_distance_to_occupied(g, std::int8_t{0});
    std::vector<int> seen(g.size_y(), 0);
    squared_distance_rows(g, std::int8_t{0}, [&](std::uint32_t y, std::span<const std::uint64_t> d2) {
      ASSERT_LT(y, g.size_y());
      ASSERT_EQ(d2.size(), g.size_x());
      ++seen[y];
      for (std::uint32_t x = 0; x < g.size_x(); ++x) {
        ASSERT_EQ(d2[x], whole[g.index(static_cast<int>(x), static_cast<int>(y))]) << x << "," << y;
      }
    });
    for (std::uint32_t y = 0; y < g.size_y(); ++y) EXPECT_EQ(seen[y], 1) << "row " << y;
    if (trial >= 16) {
      for (const auto v : whole) ASSERT_EQ(v, std::numeric_limits<std::uint64_t>::max());
    }
  }
}

RangeScan2D straight_scan(float range) {
  RangeScan2D s;
  s.aperture = 0.1;
  s.set_ranges(std::vector<float>(3, range));
  return s;
}

TEST(GridInsertion, RayFreesCellsAndMarksHit) {
  OccupancyGrid g(-5, 5, -5, 5, 0.1f);
  const auto r = insert_scan(g, straight_scan(2.0f), Pose2(0.05, 0.05, 0.0));
  ASSERT_TRUE(r.inserted());
  EXPECT_GT(g.free_probability_at(1.0, 0.05), 0.5f);
  EXPECT_LT(g.free_probability_at(2.05, 0.05), 0.5f);
  EXPECT_EQ(g.free_probability_at(3.0, 0.05), 0.5f);
  RangeScan2D tilted = straight_scan(2.0f);
  tilted.T_robot_sensor = Pose3(0, 0, 0, 0, 0.3, 0);
  EXPECT_EQ(insert_scan(g, tilted, Pose2()).status, GridInsertStatus::NotHorizontal);
  RangeScan2D bad = straight_scan(2.0f);
  bad.ranges[1] = std::nanf("");
  EXPECT_TRUE(insert_scan(g, bad, Pose2()).inserted());  // NaN ray is skipped, not inserted
}

// Ground truth: a scan taken in a square room, ranges exact at the scan's
// own ray angles (RangeScan2D::ray_angle). In the default arithmetic every
// ray marks the cell of its true hit occupied; MRPT's geometry (rays spaced
// aperture / N instead of aperture / (N − 1)) misses where its angles have
// drifted from the true ones.
TEST(GridInsertion, DefaultGeometryMarksTheTrueHitCells) {
  const double half = 6.025;  // walls in the middle of 5 cm cells
  const Pose2 pose(0.31, -0.22, 0.4);
  RangeScan2D scan;
  scan.aperture = 3.14159265358979323846;
  std::vector<float> ranges(361, 1.0f);
  scan.set_ranges(ranges);  // (ray_angle needs the ray count)
  std::vector<Eigen::Vector2d> hits;
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const double a = pose.phi() + scan.ray_angle(i);
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    const double tx = d.x() > 0 ? (half - pose.x()) / d.x() : (-half - pose.x()) / d.x();
    const double ty = d.y() > 0 ? (half - pose.y()) / d.y() : (-half - pose.y()) / d.y();
    const double r = std::min(std::abs(d.x()) > 1e-12 ? tx : 1e9, std::abs(d.y()) > 1e-12 ? ty : 1e9);
    ranges[i] = static_cast<float>(r);
    hits.push_back(pose.translation() + r * d);
  }
  scan.set_ranges(ranges);
  std::size_t counted[2] = {0, 0};
  for (const Arithmetic arithmetic : {Arithmetic::Double, Arithmetic::Mrpt}) {
    OccupancyGrid g(-10, 10, -10, 10, 0.05f);
    GridInsertionOptions o;
    o.arithmetic = arithmetic;
    ASSERT_TRUE(insert_scan(g, scan, pose, o).inserted());
    std::size_t& n = counted[arithmetic == Arithmetic::Mrpt ? 1 : 0];
    for (const auto& h : hits) n += g.free_probability_at(h.x(), h.y()) < 0.5f;
  }
  std::printf("true hit cells marked occupied: %zu of %zu (double), %zu (MRPT's geometry)\n",
              counted[0], hits.size(), counted[1]);
  EXPECT_GE(counted[0], hits.size() - 2);  // (a hit on a cell corner may round either way)
  EXPECT_GT(counted[0], counted[1]);
}

// MRPT computes the occupied update 3·L in the cell type: above p ≈ 0.9 it
// wraps around for int8 cells (p = 0.95: 3 × 47 = 141 → −115, and the cell
// arithmetic wraps again). Only Arithmetic::Mrpt reproduces that; the
// default saturates the strength at 127.
TEST(GridInsertion, StrongOccupiedUpdateSaturatesUnlessMrpt) {
  RangeScan2D scan;
  scan.aperture = 0.1;
  scan.set_ranges(std::vector<float>(3, 2.0f));
  // Only the middle ray: in MRPT's geometry all three end in the same cell,
  // and a second wrapped update would take it to the minimum anyway.
  scan.valid = {false, true, false};
  GridInsertionOptions o;
  o.max_occupancy_update_certainty = 0.95f;
  o.consider_invalid_ranges_as_free_space = false;
  std::int8_t hit[2] = {0, 0};
  for (const Arithmetic arithmetic : {Arithmetic::Double, Arithmetic::Mrpt}) {
    OccupancyGrid g(-5, 5, -5, 5, 0.1f);
    const auto at = g.index(g.x_to_idx(2.05), g.y_to_idx(0.05));
    g.mutable_cells()[at] = 20;  // somewhat free before the hit
    o.arithmetic = arithmetic;
    ASSERT_TRUE(insert_scan(g, scan, Pose2(0.05, 0.05, 0.0), o).inserted());
    hit[arithmetic == Arithmetic::Mrpt ? 1 : 0] = g.cells()[at];
  }
  EXPECT_EQ(hit[0], 20 - 127);  // saturated strength
  // MRPT: 3·L = 135 held in int8 is −121, so the update is 20 − (−121),
  // wrapped to −115: a strongly hit cell reads as free.
  EXPECT_EQ(hit[1], static_cast<std::int8_t>(20 + 121));
}

TEST(GridOptions, LoadFromIniAndReportErrors) {
  const IniFile ini = IniFile::parse(
      "[g_insertOpts]\nmaxDistanceInsertion=20\nhorizontalTolerance=1\nwideningBeamsWithDistance=1\n"
      "[g_likelihoodOpts]\nlikelihoodMethod=lmConsensus\nLF_decimation=3\nfoo=1\n"
      "[bad]\ndecimation=0\n",
      "test.ini");
  const auto io = GridInsertionOptions::from_config(ConfigSection(ini, "g_insertOpts"));
  EXPECT_EQ(io.max_distance_insertion, 20.0f);
  EXPECT_NEAR(io.horizontal_tolerance, 3.14159265 / 180, 1e-7);
  EXPECT_TRUE(io.widening_beams_with_distance);
  const auto lo = GridLikelihoodOptions::from_config(ConfigSection(ini, "g_likelihoodOpts"));
  EXPECT_EQ(lo.method, GridLikelihoodMethod::Consensus);
  EXPECT_EQ(lo.lf_decimation, 3u);
  EXPECT_EQ(ini.unread_keys("g_likelihoodOpts"), std::vector<std::string>{"foo"});
  EXPECT_THROW(GridInsertionOptions::from_config(ConfigSection(ini, "bad")), ConfigError);
}

TEST(GridLikelihood, BatchEqualsSingleAndStaleGridIsRejected) {
  OccupancyGrid g(-5, 5, -5, 5, 0.05f);
  RangeScan2D s;
  s.aperture = 3.14159;
  std::vector<float> r(181);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = 2.0f + 0.5f * std::sin(0.1f * i);
  s.set_ranges(r);
  insert_scan(g, s, Pose2(0.1, 0.2, 0.3));
  for (int m = 0; m <= 6; ++m) {
    GridLikelihoodOptions o;
    o.method = static_cast<GridLikelihoodMethod>(m);
    GridLikelihoodModel<std::int8_t> model(g, o);
    const auto p = model.prepare(s);
    const std::vector<Pose2> poses{Pose2(0.1, 0.2, 0.3), Pose2(0.3, 0.1, 0.2), Pose2(1e9, 0, 0)};
    std::vector<double> out(poses.size());
    model.log_likelihood(p, poses, out);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      EXPECT_EQ(out[i], model.log_likelihood(p, poses[i])) << m;
      EXPECT_FALSE(std::isnan(out[i])) << m;
    }
    if (m == 4) {
      EXPECT_GT(out[0], out[1]);  // the true pose explains the scan best
    }
  }
  GridLikelihoodModel<std::int8_t> model(g);
  g.fill(0.5f);
  EXPECT_THROW(model.log_likelihood(model.prepare(s), Pose2()), InvalidArgument);
  model.refresh();
  EXPECT_NO_THROW(model.log_likelihood(model.prepare(s), Pose2()));
}

}  // namespace
}  // namespace rove

namespace rove {
namespace {

// Binary entropy of a probability, in double (the oracle for the float
// table).
double binary_entropy(double p) {
  return (p <= 0 || p >= 1) ? 0.0 : -p * std::log(p) - (1 - p) * std::log(1 - p);
}

template <typename Cell>
void check_entropy_properties() {
  using Grid = OccupancyGridT<Cell>;
  // Unknown everywhere: ln 2 per cell, nothing mapped.
  Grid unknown(0, 2, 0, 1, 0.1f);
  const std::size_t n = unknown.cells().size();
  ASSERT_EQ(n, 200u);
  const GridEntropy u = grid_entropy(unknown);
  EXPECT_NEAR(u.entropy, n * std::log(2.0), 1e-5);
  EXPECT_EQ(u.mapped_cells, 0u);
  EXPECT_EQ(u.information, 0.0);
  EXPECT_EQ(u.mean_entropy, 0.0);
  EXPECT_EQ(u.mapped_area, 0.0);
  // MRPT's table counts the same unknown cells as mapped and certain.
  const GridEntropy um = grid_entropy(unknown, EntropyTable::Mrpt);
  EXPECT_EQ(um.entropy, 0.0);
  EXPECT_EQ(um.mapped_cells, n);
  EXPECT_NEAR(um.information, static_cast<double>(n), 1e-9);

  // Cells at chosen probabilities: the sums of their entropies, mapped
  // cells those clearly away from 0.5, information 1 − h/ln 2 each.
  Grid g(0, 2, 0, 1, 0.1f);
  const auto& lut = LogOddsLut<Cell>::instance();
  const float probs[] = {0.02f, 0.3f, 0.45f, 0.499f, 0.8f, 0.97f};
  double H = 0, I = 0;
  std::uint64_t mapped = 0;
  for (std::size_t i = 0; i < std::size(probs); ++i) {
    const Cell c = lut.p2l(probs[i]);
    g.set_cell(static_cast<int>(i), 3, c);
    const double h = binary_entropy(lut.l2p(c));
    H += h;
    if (h < std::log(2.0) - 0.001) {
      ++mapped;
      I += 1 - h / std::log(2.0);
    }
  }
  H += (n - std::size(probs)) * std::log(2.0);
  const GridEntropy e = grid_entropy(g);
  EXPECT_NEAR(e.entropy, H, 1e-4);
  EXPECT_EQ(e.mapped_cells, mapped);
  EXPECT_EQ(mapped, 5u);  // all but p = 0.499
  EXPECT_NEAR(e.information, I, 1e-5);
  EXPECT_NEAR(e.mean_entropy, e.entropy / mapped, 1e-12);
  EXPECT_NEAR(e.mean_information, e.information / mapped, 1e-12);
  EXPECT_NEAR(e.mapped_area, mapped * 0.01, 1e-6);

  // Saturated cells carry almost one unit of information each.
  Grid sat(0, 1, 0, 1, 0.5f);
  for (Cell& c : sat.mutable_cells()) c = LogOddsTraits<Cell>::kMax;
  const GridEntropy s = grid_entropy(sat);
  EXPECT_EQ(s.mapped_cells, sat.cells().size());
  EXPECT_GT(s.mean_information, 0.99);
  EXPECT_LE(s.mean_information, 1.0);
}

TEST(GridEntropy, PropertiesOn8BitCells) { check_entropy_properties<std::int8_t>(); }
TEST(GridEntropy, PropertiesOn16BitCells) { check_entropy_properties<std::int16_t>(); }

}  // namespace
}  // namespace rove

namespace rove {
namespace {

// The feature transform names a cell at the exact nearest distance.
TEST(GridClearance, NearestOccupiedCellIsAtTheNearestDistance) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    OccupancyGrid g(0, 3.0f + trial % 4, 0, 2.0f + trial % 3, 0.1f);
    std::uniform_int_distribution<int> ux(0, static_cast<int>(g.size_x()) - 1),
        uy(0, static_cast<int>(g.size_y()) - 1);
    for (int k = 0; k < trial % 9; ++k) g.set_free_probability(ux(rng), uy(rng), 0.0f);
    const auto d2 = squared_distance_to_occupied(g, std::int8_t{0});
    const auto site = nearest_occupied_cell(g, std::int8_t{0});
    const auto nx = static_cast<std::int64_t>(g.size_x());
    for (std::size_t i = 0; i < site.size(); ++i) {
      if (trial % 9 == 0) {
        ASSERT_EQ(site[i], kNoOccupiedCell);
        continue;
      }
      ASSERT_NE(site[i], kNoOccupiedCell);
      ASSERT_LT(g.cells()[site[i]], 0) << "not an occupied cell";
      const std::int64_t dx = static_cast<std::int64_t>(i) % nx - site[i] % nx;
      const std::int64_t dy = static_cast<std::int64_t>(i) / nx - site[i] / nx;
      ASSERT_EQ(static_cast<std::uint64_t>(dx * dx + dy * dy), d2[i]) << i;
    }
  }
}

// A corridor between two walls: the diagram is its center line, with half
// the width as clearance; nothing near the walls.
TEST(GridVoronoi, CorridorCenterLine) {
  for (const int width : {20, 21}) {
    OccupancyGrid g(0, 6.0f, 0, 0.1f * (width + 1), 0.1f);
    const int nx = static_cast<int>(g.size_x());
    ASSERT_EQ(static_cast<int>(g.size_y()), width + 1);
    for (int x = 0; x < nx; ++x) {
      g.set_free_probability(x, 0, 0.0f);
      g.set_free_probability(x, width, 0.0f);
      for (int y = 1; y < width; ++y) g.set_free_probability(x, y, 1.0f);
    }
    const VoronoiDiagram vd = voronoi_diagram(g);
    ASSERT_EQ(vd.size_x, g.size_x());
    for (int x = 0; x < nx; ++x) {
      int on = 0;
      for (int y = 0; y <= width; ++y) {
        if (!vd.on(x, y)) continue;
        ++on;
        // Width 20: row 10 is equidistant; width 21: rows 10 and 11 are
        // half a cell off, one of them is kept.
        EXPECT_LE(std::abs(2 * y - width), 1) << "x " << x << " y " << y;
        EXPECT_NEAR(vd.clearance[g.index(x, y)], 0.1f * std::min(y, width - y), 1e-5f);
      }
      EXPECT_EQ(on, 1) << "column " << x << ", width " << width;
    }
    EXPECT_EQ(vd.cells, static_cast<std::size_t>(nx));
    // A robot wider than the corridor's half width: no diagram left.
    VoronoiOptions wide;
    wide.min_clearance = 0.1f * (width / 2) + 0.01f;
    EXPECT_EQ(voronoi_diagram(g, wide).cells, 0u);
  }
}

// Every diagram cell on random obstacles lies between two obstacles seen
// far apart, within a cell of equidistance; clearances are the distance
// transform's; no obstacle and a full grid give no diagram.
TEST(GridVoronoi, CellsAreNearlyEquidistantToTwoSeparatedObstacles) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 12; ++trial) {
    OccupancyGrid g(0, 4.0f, 0, 3.0f, 0.1f);
    for (std::int8_t& c : g.mutable_cells()) c = LogOddsTraits<std::int8_t>::kMax;
    std::uniform_int_distribution<int> ux(0, static_cast<int>(g.size_x()) - 1),
        uy(0, static_cast<int>(g.size_y()) - 1);
    std::vector<std::pair<int, int>> obstacles;
    for (int k = 0; k < 3 + trial; ++k) {
      const int x = ux(rng), y = uy(rng);
      g.set_free_probability(x, y, 0.0f);
      obstacles.emplace_back(x, y);
    }
    const VoronoiDiagram vd = voronoi_diagram(g);
    const std::vector<float> clearance = clearance_map(g);
    EXPECT_GT(vd.cells, 0u) << trial;
    std::size_t counted = 0;
    for (int y = 0; y < static_cast<int>(g.size_y()); ++y) {
      for (int x = 0; x < static_cast<int>(g.size_x()); ++x) {
        if (!vd.on(x, y)) continue;
        ++counted;
        const float c = vd.clearance[g.index(x, y)];
        ASSERT_NEAR(c, clearance[g.index(x, y)], 1e-5f);
        // Two obstacles: the nearest (at the clearance) and one within a
        // cell's diagonal of it, more than 1.75 × (clearance − √2 cells)
        // from the first.
        const double d = c / 0.1;
        bool found = false;
        for (const auto& [ax, ay] : obstacles) {
          const double da = std::hypot(ax - x, ay - y);
          if (std::abs(da - d) > 1e-6) continue;
          for (const auto& [bx, by] : obstacles) {
            const double db = std::hypot(bx - x, by - y);
            if (db - d <= std::sqrt(2.0) + 1e-9 &&
                std::hypot(ax - bx, ay - by) > 1.75 * (d - std::sqrt(2.0)))
              found = true;
          }
        }
        ASSERT_TRUE(found) << "trial " << trial << " cell " << x << "," << y;
      }
    }
    EXPECT_EQ(counted, vd.cells);
  }
  OccupancyGrid empty(0, 1, 0, 1, 0.1f, 1.0f);
  EXPECT_EQ(voronoi_diagram(empty).cells, 0u);
  OccupancyGrid full(0, 1, 0, 1, 0.1f, 0.0f);
  EXPECT_EQ(voronoi_diagram(full).cells, 0u);
  VoronoiOptions bad;
  bad.min_separation = 0;
  EXPECT_THROW(voronoi_diagram(empty, bad), InvalidArgument);
}

}  // namespace
}  // namespace rove
