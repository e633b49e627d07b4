// OccupancyOctree::insert_point_cloud against a brute-force oracle of
// OctoMap's semantics, and against itself with every thread count.
#include <cmath>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "rove/octree_test_support.h"
#include "rove/core/error.h"
#include "rove/maps/occupancy_octree.h"

namespace rove {
namespace {

using octree_test::CellOracle;
using octree_test::expect_consistent;
using octree_test::expect_matches_oracle;
using octree_test::expect_same_tree;

// A room-like cloud: walls of a 10 x 8 x 3 m box around the origin, plus
// scattered points and a few far ones.
std::vector<Eigen::Vector3f> room_cloud(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const float a = u(rng), b = u(rng);
    switch (i % 5) {
      case 0: pts.emplace_back(-4.0f, -3.0f + 8.0f * a, -1.0f + 3.0f * b); break;
      case 1: pts.emplace_back(6.0f, -3.0f + 8.0f * a, -1.0f + 3.0f * b); break;
      case 2: pts.emplace_back(-4.0f + 10.0f * a, 5.0f, -1.0f + 3.0f * b); break;
      case 3: pts.emplace_back(-4.0f + 10.0f * a, -3.0f + 8.0f * b, -1.0f); break;
      default: pts.emplace_back(-6.0f + 14.0f * a, -5.0f + 12.0f * b, -1.0f + 4.0f * u(rng)); break;
    }
  }
  return pts;
}

TEST(OctreeInsertion, OneScanMatchesTheOracle) {
  const auto pts = room_cloud(3000, 1);
  const Eigen::Vector3d origin(0.11, -0.07, 0.5);
  OccupancyOctree t(0.1);
  const auto r = t.insert_point_cloud(pts, origin);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.points, pts.size());
  CellOracle oracle(t);
  oracle.insert_scan(pts, origin, -1.0);
  expect_matches_oracle(t, oracle);
  expect_consistent(t);
  std::size_t occupied = 0;
  for (const auto& [k, v] : oracle.cells()) occupied += v > 0 ? 1 : 0;
  EXPECT_EQ(r.occupied_updates, occupied);
  EXPECT_EQ(r.free_updates, oracle.cells().size() - occupied);
}

TEST(OctreeInsertion, RepeatedScansClampPruneAndMatchTheOracle) {
  const auto pts = room_cloud(2500, 2);
  OccupancyOctree t(0.2);
  CellOracle oracle(t);
  const Eigen::Vector3d origins[] = {{0, 0, 0}, {0.5, 0.3, 0.1}, {-0.4, 0.2, 0.3}, {0.05, -0.5, 0.2}};
  for (int round = 0; round < 3; ++round) {
    for (const auto& o : origins) {
      t.insert_point_cloud(pts, o, {.max_range = round == 1 ? 4.0 : -1.0});
      oracle.insert_scan(pts, o, round == 1 ? 4.0 : -1.0);
    }
  }
  expect_matches_oracle(t, oracle);
  expect_consistent(t);
  // Free space saturated and was pruned into coarser leaves.
  int coarse = 0;
  t.for_each_leaf([&](const OctreeLeaf& l) { coarse += l.depth < 16 ? 1 : 0; });
  EXPECT_GT(coarse, 100);
}

TEST(OctreeInsertion, EveryRayModeMatchesTheOracle) {
  const auto pts = room_cloud(1500, 3);
  OccupancyOctree t(0.1);
  CellOracle oracle(t);
  for (const Eigen::Vector3d& o : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0.1, 0.2)}) {
    t.insert_point_cloud(pts, o, {.mode = OctreeUpdateMode::EveryRay});
    oracle.insert_rays(pts, o);
  }
  expect_matches_oracle(t, oracle);
  expect_consistent(t);
}

TEST(OctreeInsertion, DiscretizedUsesCellCentres) {
  const auto pts = room_cloud(2000, 4);
  OccupancyOctree t(0.25);
  t.insert_point_cloud(pts, Eigen::Vector3d::Zero(), {.mode = OctreeUpdateMode::Discretized});
  // The same as inserting the distinct cell centres.
  std::vector<Eigen::Vector3f> centres;
  std::set<OctreeKey> seen;
  for (const auto& p : pts) {
    const OctreeKey k = t.key_checked(p.cast<double>());
    if (seen.insert(k).second) centres.push_back(t.center_of(k).cast<float>());
  }
  OccupancyOctree u(0.25);
  u.insert_point_cloud(centres, Eigen::Vector3d::Zero());
  expect_same_tree(t, u);
}

TEST(OctreeInsertion, ResultDoesNotDependOnTheThreadCount) {
  // Enough rays for the parallel path (more than two chunks).
  const auto pts = room_cloud(9000, 5);
  for (const auto mode : {OctreeUpdateMode::OncePerScan, OctreeUpdateMode::EveryRay}) {
    for (const auto arith : {OctreeRayArithmetic::Double, OctreeRayArithmetic::OctoMap}) {
      std::vector<OccupancyOctree> trees;
      for (int threads : {1, 2, 3, 4}) {
        OccupancyOctree t(0.1, {}, OctreeChannels::Color);
        t.enable_change_detection(true);
        for (const Eigen::Vector3d& o : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.45, -0.2, 0.3)}) {
          OctreeInsertOptions opt;
          opt.mode = mode;
          opt.arithmetic = arith;
          opt.num_threads = threads;
          opt.max_range = mode == OctreeUpdateMode::EveryRay ? -1.0 : 7.0;
          t.insert_point_cloud(pts, o, opt);
        }
        trees.push_back(std::move(t));
      }
      for (std::size_t i = 1; i < trees.size(); ++i) {
        SCOPED_TRACE(::testing::Message() << "mode " << int(mode) << " arithmetic " << int(arith) << " tree " << i);
        expect_same_tree(trees[0], trees[i]);
        const auto c0 = trees[0].changes(), ci = trees[i].changes();
        ASSERT_EQ(c0.size(), ci.size());
        for (std::size_t j = 0; j < c0.size(); ++j) {
          EXPECT_EQ(c0[j].key, ci[j].key);
          EXPECT_EQ(c0[j].created, ci[j].created);
        }
      }
      expect_consistent(trees[0]);
    }
  }
}

TEST(OctreeInsertion, ParallelScansMatchTheOracle) {
  const auto pts = room_cloud(9000, 6);
  OccupancyOctree t(0.1);
  CellOracle oracle(t);
  for (const Eigen::Vector3d& o : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0.5, 0.2)}) {
    t.insert_point_cloud(pts, o, {.max_range = 6.0, .num_threads = 3});
    oracle.insert_scan(pts, o, 6.0);
  }
  expect_matches_oracle(t, oracle);
  expect_consistent(t);
}

// Long rays in every direction: their box is too large for the dense cell
// sets (docs/octree.md), so the scan takes the sparse path, with one thread
// and with several.
TEST(OctreeInsertion, LongRaysInEveryDirectionTakeTheSparsePath) {
  std::mt19937_64 rng(12);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::uniform_real_distribution<float> r(12.0f, 20.0f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 4200; ++i) {
    const Eigen::Vector3f d = Eigen::Vector3f(g(rng), g(rng), g(rng)).normalized();
    pts.push_back(d * r(rng));
  }
  const Eigen::Vector3d origin(0.12, -0.31, 0.05);
  OccupancyOctree t1(0.1);
  t1.enable_change_detection(true);
  const auto r1 = t1.insert_point_cloud(pts, origin, {.max_range = 18.0});
  EXPECT_TRUE(r1.ok()) << r1.message;
  CellOracle oracle(t1);
  oracle.insert_scan(pts, origin, 18.0);
  expect_matches_oracle(t1, oracle);
  expect_consistent(t1);
  for (int threads : {2, 3}) {
    OccupancyOctree t(0.1);
    t.enable_change_detection(true);
    const auto r = t.insert_point_cloud(pts, origin, {.max_range = 18.0, .num_threads = threads});
    EXPECT_EQ(r.free_updates, r1.free_updates);
    EXPECT_EQ(r.occupied_updates, r1.occupied_updates);
    expect_same_tree(t1, t);
    EXPECT_EQ(t.changes().size(), t1.changes().size());
  }
}

TEST(OctreeInsertion, LazyThenInnerUpdateAndPruneEqualsEager) {
  const auto pts = room_cloud(2000, 7);
  OccupancyOctree eager(0.1), lazy(0.1);
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d o(0.1 * i, 0.0, 0.0);
    eager.insert_point_cloud(pts, o);
    lazy.insert_point_cloud(pts, o, {.lazy = true});
  }
  lazy.update_inner_occupancy();
  lazy.prune();
  expect_consistent(lazy);
  // Same finest cells with the same values.
  const std::vector<OctreeLeaf> le = eager.leaves();
  std::size_t mismatches = 0;
  for (const OctreeLeaf& l : le) {
    const auto n = lazy.search(l.key);
    if (!n || n->log_odds != l.log_odds) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0u);
}

TEST(OctreeInsertion, ChangeDetectionMatchesNewAndFlippedCells) {
  const auto pts = room_cloud(1000, 8);
  OccupancyOctree t(0.2);
  CellOracle oracle(t);
  t.insert_point_cloud(pts, Eigen::Vector3d::Zero());
  oracle.insert_scan(pts, Eigen::Vector3d::Zero(), -1.0);
  const auto before = oracle.cells();
  t.enable_change_detection(true);
  // Three other scans from elsewhere: cells seen occupied once and crossed
  // three times flip to free.
  const auto pts2 = room_cloud(1000, 18);
  const Eigen::Vector3d o2(0.7, 0.4, 0.1);
  for (int i = 0; i < 3; ++i) {
    t.insert_point_cloud(pts2, o2);
    oracle.insert_scan(pts2, o2, -1.0);
  }
  std::map<OctreeKey, bool> expected;  // key -> created
  for (const auto& [k, v] : oracle.cells()) {
    const auto old = before.find(k);
    if (old == before.end()) {
      expected[k] = true;
    } else if (t.is_occupied(old->second) != t.is_occupied(v)) {
      expected[k] = false;
    }
  }
  const auto got = t.changes();
  ASSERT_EQ(got.size(), expected.size());
  std::size_t i = 0, created = 0;
  for (const auto& [k, c] : expected) {
    EXPECT_EQ(got[i].key, k);
    EXPECT_EQ(got[i].created, c);
    created += c ? 1 : 0;
    ++i;
  }
  EXPECT_GT(created, 0u);
  EXPECT_LT(created, expected.size());
}

TEST(OctreeInsertion, ColouredCloudIntegratesPerPoint) {
  const auto pts = room_cloud(500, 9);
  std::vector<Rgb8> colors;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    colors.push_back(Rgb8{static_cast<std::uint8_t>(i % 251), static_cast<std::uint8_t>(i % 13),
                          static_cast<std::uint8_t>(200)});
  }
  OccupancyOctree t(0.1, {}, OctreeChannels::Color);
  t.insert_point_cloud(pts, colors, Eigen::Vector3d::Zero(), {}, OctreeColorUpdate::Set);
  // Set: the last point of each cell wins.
  std::map<OctreeKey, Rgb8> last;
  for (std::size_t i = 0; i < pts.size(); ++i) last[t.key_checked(pts[i].cast<double>())] = colors[i];
  for (const auto& [k, c] : last) {
    const auto got = t.color_at(k);
    ASSERT_TRUE(got.has_value());
    EXPECT_EQ(got->r, c.r);
    EXPECT_EQ(got->g, c.g);
  }
  EXPECT_THROW(t.insert_point_cloud(pts, std::span<const Rgb8>(colors).first(3), Eigen::Vector3d::Zero()),
               InvalidArgument);
}

TEST(OctreeInsertion, BadInputIsRejectedOrSkipped) {
  OccupancyOctree t(0.1);
  std::vector<Eigen::Vector3f> pts = {{1, 0, 0}, {std::nanf(""), 0, 0}, {2, 0, 0}};
  try {
    t.insert_point_cloud(pts, Eigen::Vector3d::Zero());
    ADD_FAILURE() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("point 1"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(t.empty());  // nothing inserted
  auto r = t.insert_point_cloud(pts, Eigen::Vector3d::Zero(), {.skip_invalid_points = true});
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.skipped_points, 1u);
  EXPECT_TRUE(t.search(Eigen::Vector3d(2.05, 0.05, 0.05)).has_value());
  // Beyond the tree (±3276.8 m at 0.1 m).
  const std::vector<Eigen::Vector3f> far = {{5000, 0, 0}};
  EXPECT_THROW(t.insert_point_cloud(far, Eigen::Vector3d::Zero()), InvalidArgument);
  // ... unless max_range cuts the ray inside it: then only free cells.
  OccupancyOctree u(0.1);
  r = u.insert_point_cloud(far, Eigen::Vector3d::Zero(), {.max_range = 2.05});
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.occupied_updates, 0u);
  EXPECT_EQ(r.free_updates, 20u);
  EXPECT_THROW(t.insert_point_cloud(pts, Eigen::Vector3d(std::nan(""), 0, 0), {.skip_invalid_points = true}),
               InvalidArgument);
  EXPECT_THROW(t.insert_point_cloud(pts, Eigen::Vector3d(1e6, 0, 0), {.skip_invalid_points = true}), InvalidArgument);
  EXPECT_THROW(t.insert_point_cloud(pts, Eigen::Vector3d::Zero(), {.num_threads = -1}), InvalidArgument);
  EXPECT_THROW(t.insert_point_cloud(pts, Eigen::Vector3d::Zero(), {.max_range = std::nan("")}), InvalidArgument);
  // Empty clouds are fine.
  OccupancyOctree e(0.1);
  r = e.insert_point_cloud(std::vector<Eigen::Vector3f>{}, Eigen::Vector3d::Zero());
  EXPECT_TRUE(r.ok());
}

}  // namespace
}  // namespace rove
