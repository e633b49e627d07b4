// OccupancyOctree: geometry, single-cell updates, pruning, queries, colours,
// statistics, bad input. Insertion of clouds: octree_insertion_test.cpp;
// OctoMap's own results: octree_octomap_test.cpp.
#include <cmath>
#include <limits>
#include <random>
#include <thread>

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

TEST(Octree, RejectsBadResolutionAndParameters) {
  for (double r : {0.0, -0.1, std::nan(""), std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::denorm_min(), 1e305}) {
    EXPECT_THROW(OccupancyOctree{r}, InvalidArgument) << r;
  }
  OccupancyOctreeParams p;
  p.prob_hit = 0.3;
  EXPECT_THROW((OccupancyOctree{0.1, p}), InvalidArgument);
  p = {};
  p.clamping_min = 0.99;
  EXPECT_THROW((OccupancyOctree{0.1, p}), InvalidArgument);
  p = {};
  p.prob_miss = 1.0;
  EXPECT_THROW((OccupancyOctree{0.1, p}), InvalidArgument);
}

TEST(Octree, LogOddsAreOctoMapsFloats) {
  const OccupancyOctree t(0.1);
  // OctoMap 1.9.7: (float) log(p / (1 - p)).
  EXPECT_EQ(t.hit_log_odds(), static_cast<float>(std::log(0.7 / 0.3)));
  EXPECT_FLOAT_EQ(t.hit_log_odds(), 0.8472979f);
  EXPECT_FLOAT_EQ(t.miss_log_odds(), -0.4054651f);
  EXPECT_FLOAT_EQ(t.clamp_min_log_odds(), -2.0000279f);
  EXPECT_FLOAT_EQ(t.clamp_max_log_odds(), 3.5110307f);
  EXPECT_EQ(t.threshold_log_odds(), 0.0f);
  EXPECT_TRUE(t.is_occupied(0.0f));  // OctoMap: occupied when >= threshold
  EXPECT_FALSE(t.is_occupied(-1e-6f));
  EXPECT_NEAR(octree_probability(t.clamp_max_log_odds()), 0.971, 1e-7);
}

TEST(Octree, KeysAndCentres) {
  const OccupancyOctree t(0.25);
  EXPECT_EQ(t.key_checked({0.0, 0.0, 0.0}), (OctreeKey{32768, 32768, 32768}));
  EXPECT_EQ(t.key_checked({-1e-9, 0.2499, 0.25}), (OctreeKey{32767, 32768, 32769}));
  const Eigen::Vector3d c = t.center_of(OctreeKey{32767, 32768, 32769});
  EXPECT_DOUBLE_EQ(c.x(), -0.125);
  EXPECT_DOUBLE_EQ(c.y(), 0.125);
  EXPECT_DOUBLE_EQ(c.z(), 0.375);
  // Coarser depths: the node of 2^(16-d) cells around the key.
  EXPECT_DOUBLE_EQ(t.center_of(OctreeKey{32768, 32768, 32768}, 15).x(), 0.25);
  EXPECT_DOUBLE_EQ(t.center_of(OctreeKey{32767, 32767, 32767}, 15).x(), -0.25);
  EXPECT_DOUBLE_EQ(t.center_of(OctreeKey{32767, 32767, 32767}, 0).x(), 0.0);
  EXPECT_DOUBLE_EQ(t.node_size(0), 0.25 * 65536);
  // The edges of the tree.
  const double half = 32768 * 0.25;
  EXPECT_TRUE(t.key_of({-half, 0, 0}).has_value());
  EXPECT_EQ(t.key_of({-half, 0, 0})->x, 0);
  EXPECT_EQ(t.key_of({half - 1e-9, 0, 0})->x, 65535);
  EXPECT_FALSE(t.key_of({half, 0, 0}).has_value());
  EXPECT_FALSE(t.key_of({-half - 1e-9, 0, 0}).has_value());
  EXPECT_FALSE(t.key_of({std::nan(""), 0, 0}).has_value());
  EXPECT_FALSE(t.key_of({1e300, 0, 0}).has_value());
  EXPECT_THROW(t.key_checked({0, std::numeric_limits<double>::infinity(), 0}), InvalidArgument);
  EXPECT_THROW(t.search(Eigen::Vector3d(1e6, 0, 0)), InvalidArgument);
  EXPECT_EQ(octree_child_index(OctreeKey{32768, 32767, 32768}, 0), 5u);
  EXPECT_EQ(octree_key_at_depth(OctreeKey{32771, 5, 65535}, 14), (OctreeKey{32768, 4, 65532}));
}

TEST(Octree, SingleUpdatesFollowTheSensorModelAndClamp) {
  OccupancyOctree t(0.1);
  const OctreeKey k{100, 200, 300};
  EXPECT_FALSE(t.search(k).has_value());
  t.update_node(k, true);
  auto n = t.search(k);
  ASSERT_TRUE(n.has_value());
  EXPECT_EQ(n->log_odds, t.hit_log_odds());
  EXPECT_EQ(n->depth, 16);
  EXPECT_EQ(t.num_nodes(), 17u);  // root + one path
  for (int i = 0; i < 10; ++i) t.update_node(k, true);
  EXPECT_EQ(t.search(k)->log_odds, t.clamp_max_log_odds());
  t.update_node(k, false);
  EXPECT_EQ(t.search(k)->log_odds, t.clamp_max_log_odds() + t.miss_log_odds());
  // The root holds the maximum of the tree.
  t.update_node(OctreeKey{100, 200, 301}, false);
  EXPECT_EQ(t.search(k, 0)->log_odds, t.clamp_max_log_odds() + t.miss_log_odds());
  t.set_node_value(k, -100.0f);
  EXPECT_EQ(t.search(k)->log_odds, t.clamp_min_log_odds());
  EXPECT_EQ(t.search(k, 0)->log_odds, t.miss_log_odds());
  EXPECT_THROW(t.update_node(k, std::nanf("")), InvalidArgument);
  expect_consistent(t);
}

TEST(Octree, EightEqualCellsArePrunedAndExpandedBack) {
  OccupancyOctree t(0.1);
  for (std::uint16_t i = 0; i < 8; ++i) {
    t.update_node(OctreeKey{static_cast<std::uint16_t>(i & 1), static_cast<std::uint16_t>((i >> 1) & 1),
                            static_cast<std::uint16_t>((i >> 2) & 1)},
                  true);
  }
  // 8 cells merged into their parent at depth 15: root + 15 nodes.
  EXPECT_EQ(t.num_nodes(), 16u);
  EXPECT_EQ(t.num_leaves(), 1u);
  auto n = t.search(OctreeKey{1, 0, 1});
  ASSERT_TRUE(n.has_value());
  EXPECT_EQ(n->depth, 15);
  EXPECT_EQ(n->log_odds, t.hit_log_odds());
  // A change to one cell expands the pruned leaf again.
  t.update_node(OctreeKey{1, 1, 1}, false);
  EXPECT_EQ(t.num_nodes(), 24u);
  EXPECT_EQ(t.search(OctreeKey{1, 0, 1})->depth, 16);
  EXPECT_EQ(t.search(OctreeKey{1, 1, 1})->log_odds, t.hit_log_odds() + t.miss_log_odds());
  // expand() then prune() gives the same tree back.
  OccupancyOctree copy = t;
  t.expand();
  EXPECT_EQ(t.search(OctreeKey{1000, 1000, 1000}), std::nullopt);
  t.prune();
  expect_same_tree(t, copy);
  expect_consistent(t);
}

TEST(Octree, RandomUpdatesMatchTheCellOracle) {
  std::mt19937_64 rng(7);
  OccupancyOctree t(0.05);
  CellOracle oracle(t);
  std::uniform_int_distribution<int> coord(32760, 32775);
  for (int i = 0; i < 20000; ++i) {
    const OctreeKey k{static_cast<std::uint16_t>(coord(rng)), static_cast<std::uint16_t>(coord(rng)),
                      static_cast<std::uint16_t>(coord(rng))};
    const float d = (rng() % 3 == 0) ? t.hit_log_odds() : t.miss_log_odds();
    t.update_node(k, d);
    oracle.update(k, d);
  }
  expect_matches_oracle(t, oracle);
  expect_consistent(t);
}

TEST(Octree, MaxLikelihoodAndInnerUpdate) {
  OccupancyOctree t(0.1);
  t.update_node(OctreeKey{5, 5, 5}, true);
  t.update_node(OctreeKey{5, 5, 6}, false);
  t.to_max_likelihood();
  EXPECT_EQ(t.search(OctreeKey{5, 5, 5})->log_odds, t.clamp_max_log_odds());
  EXPECT_EQ(t.search(OctreeKey{5, 5, 6})->log_odds, t.clamp_min_log_odds());
  EXPECT_EQ(t.search(OctreeKey{5, 5, 5}, 0)->log_odds, t.clamp_max_log_odds());
  t.update_inner_occupancy();
  expect_consistent(t);
}

TEST(Octree, CastRayStopsAtWallsUnknownAndRange) {
  OccupancyOctree t(0.1);
  // Free corridor along +x from the origin to x = 1, wall at x = 1.0..1.1.
  for (std::uint16_t x = 32768; x < 32778; ++x) t.update_node(OctreeKey{x, 32768, 32768}, false);
  t.update_node(OctreeKey{32778, 32768, 32768}, true);
  auto r = t.cast_ray({0.05, 0.05, 0.05}, {1, 0, 0});
  EXPECT_TRUE(r.hit());
  EXPECT_EQ(r.key, (OctreeKey{32778, 32768, 32768}));
  EXPECT_NEAR(r.end.x(), 1.05, 1e-12);
  r = t.cast_ray({0.05, 0.05, 0.05}, {1, 0, 0}, {.max_range = 0.5});
  EXPECT_EQ(r.termination, OctreeRayCastTermination::MaxRange);
  EXPECT_EQ(r.key.x, 32774);  // first centre beyond 0.5 m
  r = t.cast_ray({0.05, 0.05, 0.05}, {-1, 0, 0});
  EXPECT_EQ(r.termination, OctreeRayCastTermination::Unknown);
  EXPECT_EQ(r.key.x, 32767);
  r = t.cast_ray({0.05, 0.05, 0.05}, {0, 1, 0}, {.ignore_unknown = true, .max_range = 3.0});
  EXPECT_EQ(r.termination, OctreeRayCastTermination::MaxRange);
  r = t.cast_ray({0.05, 0.05, 0.05}, {0, 0, -1}, {.ignore_unknown = true});
  EXPECT_EQ(r.termination, OctreeRayCastTermination::EdgeOfMap);
  EXPECT_EQ(r.key.z, 0);
  r = t.cast_ray({1.05, 0.05, 0.05}, {0, 1, 0});  // starts in the wall
  EXPECT_TRUE(r.hit());
  EXPECT_THROW(t.cast_ray({0, 0, 0}, {0, 0, 0}), InvalidArgument);
  EXPECT_THROW(t.cast_ray({0, 0, 0}, {std::nan(""), 1, 0}), InvalidArgument);
  EXPECT_THROW(t.cast_ray({1e9, 0, 0}, {1, 0, 0}), InvalidArgument);
}

TEST(Octree, RayKeysFollowTheSegment) {
  const OccupancyOctree t(0.1);
  EXPECT_TRUE(t.ray_keys({0.01, 0.01, 0.01}, {0.02, 0.05, 0.09}).empty());  // one cell
  const auto keys = t.ray_keys({0.05, 0.05, 0.05}, {0.55, 0.05, 0.05});
  ASSERT_EQ(keys.size(), 5u);  // origin's cell first, end's cell excluded
  for (std::size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(keys[i], (OctreeKey{static_cast<std::uint16_t>(32768 + i), 32768, 32768}));
  // Every step moves to a face neighbour, and the ray ends next to its end cell.
  const Eigen::Vector3d a(-1.234, 0.77, 0.31), b(2.5, -1.9, 1.05);
  const auto ks = t.ray_keys(a, b);
  ASSERT_FALSE(ks.empty());
  EXPECT_EQ(ks.front(), t.key_checked(a));
  for (std::size_t i = 1; i < ks.size(); ++i) {
    int manhattan = 0;
    for (int ax = 0; ax < 3; ++ax) manhattan += std::abs(int(ks[i][ax]) - int(ks[i - 1][ax]));
    EXPECT_EQ(manhattan, 1);
  }
  const OctreeKey e = t.key_checked(b);
  int last = 0;
  for (int ax = 0; ax < 3; ++ax) last += std::abs(int(ks.back()[ax]) - int(e[ax]));
  EXPECT_EQ(last, 1);
  EXPECT_THROW(t.ray_keys({0, 0, 0}, {1e7, 0, 0}), InvalidArgument);
}

TEST(Octree, LeafIterationAndBoxes) {
  OccupancyOctree t(0.1);
  t.update_node(OctreeKey{32768, 32768, 32768}, true);   // (0.05, 0.05, 0.05)
  t.update_node(OctreeKey{32800, 32768, 32768}, false);  // (3.25, ...)
  const auto leaves = t.leaves();
  ASSERT_EQ(leaves.size(), 2u);
  EXPECT_EQ(t.num_leaves(), 2u);
  std::vector<OctreeLeaf> in_box;
  t.for_each_leaf_in_box({-0.5, -0.5, -0.5}, {1, 1, 1}, [&](const OctreeLeaf& l) { in_box.push_back(l); });
  ASSERT_EQ(in_box.size(), 1u);
  EXPECT_EQ(in_box[0].key, (OctreeKey{32768, 32768, 32768}));
  Eigen::Vector3d lo, hi;
  t.metric_bounds(lo, hi);
  EXPECT_NEAR(lo.x(), 0.0, 1e-12);
  EXPECT_NEAR(hi.x(), 3.3, 1e-12);
  EXPECT_NEAR(hi.y(), 0.1, 1e-12);
  OccupancyOctree empty(0.1);
  empty.metric_bounds(lo, hi);
  EXPECT_GT(lo.x(), hi.x());
}

TEST(Octree, PreorderRoundTripAndMalformedLists) {
  OccupancyOctree t(0.1);
  std::mt19937_64 rng(3);
  for (int i = 0; i < 500; ++i) {
    t.update_node(OctreeKey{static_cast<std::uint16_t>(32760 + rng() % 20), static_cast<std::uint16_t>(32760 + rng() % 20),
                            static_cast<std::uint16_t>(32760 + rng() % 20)},
                  rng() % 2 == 0);
  }
  std::vector<OctreeNodeRecord> nodes;
  t.for_each_node([&](const OctreeNodeRecord& r) { nodes.push_back(r); });
  OccupancyOctree u(0.1);
  u.assign_preorder(nodes);
  expect_same_tree(t, u);
  // Inner values may be left for the tree to compute.
  for (auto& r : nodes) {
    if (r.child_mask != 0) r.log_odds = std::nanf("");
  }
  OccupancyOctree w(0.1);
  w.assign_preorder(nodes);
  expect_same_tree(t, w);
  // Too few, too many, too deep.
  auto shorter = nodes;
  shorter.pop_back();
  EXPECT_THROW(w.assign_preorder(shorter), InvalidArgument);
  EXPECT_TRUE(w.empty());
  auto longer = nodes;
  longer.push_back(nodes.back());
  EXPECT_THROW(w.assign_preorder(longer), InvalidArgument);
  std::vector<OctreeNodeRecord> deep(18);
  for (auto& r : deep) r.child_mask = 1;
  deep.back().child_mask = 0;
  EXPECT_THROW(w.assign_preorder(deep), InvalidArgument);
}

TEST(Octree, ColoursFollowOctoMapsRules) {
  OccupancyOctree t(0.1, {}, OctreeChannels::Color);
  const OctreeKey a{10, 10, 10}, b{10, 10, 11};
  EXPECT_FALSE(t.update_color(a, Rgb8{1, 2, 3}, OctreeColorUpdate::Set));  // unknown cell
  t.update_node(a, true);
  t.update_node(b, true);
  EXPECT_TRUE(t.update_color(a, Rgb8{100, 50, 10}, OctreeColorUpdate::Integrate));  // first: taken as is
  EXPECT_EQ(t.color_at(a)->r, 100);
  t.update_color(a, Rgb8{200, 0, 0}, OctreeColorUpdate::Average);
  EXPECT_EQ(t.color_at(a)->r, 150);
  EXPECT_EQ(t.color_at(a)->g, 25);
  const double p = octree_probability(t.hit_log_odds());
  t.update_color(a, Rgb8{0, 0, 0}, OctreeColorUpdate::Integrate);
  EXPECT_EQ(t.color_at(a)->r, static_cast<std::uint8_t>(150.0 * p));
  t.update_color(b, Rgb8{50, 60, 70}, OctreeColorUpdate::Set);
  // The parent: mean of the children that have a colour.
  const auto parent_color = [&] {
    std::optional<Rgb8> c;
    t.for_each_node([&](const OctreeNodeRecord& r) {
      if (r.depth == 15) c = r.color;
    });
    return *c;
  };
  EXPECT_EQ(parent_color().r, (static_cast<int>(150.0 * p) + 50) / 2);
  EXPECT_FALSE(OccupancyOctree(0.1).color_at(a).has_value());
  OccupancyOctree plain(0.1);
  plain.update_node(a, true);
  EXPECT_THROW(plain.update_color(a, Rgb8{}, OctreeColorUpdate::Set), InvalidArgument);
}

TEST(Octree, StatisticsCountEveryMeasurementAndBlockPruning) {
  OccupancyOctree t(0.1, {}, OctreeChannels::Statistics);
  const OctreeKey k{3, 3, 3};
  for (int i = 0; i < 12; ++i) t.update_node(k, true);  // clamps after 5, still counted
  t.update_node(k, false);
  EXPECT_EQ(t.statistics_at(k)->hits, 12u);
  EXPECT_EQ(t.statistics_at(k)->misses, 1u);
  // Equal values but different counts: not pruned.
  for (std::uint16_t i = 0; i < 8; ++i) {
    const OctreeKey c{static_cast<std::uint16_t>(16 + (i & 1)), static_cast<std::uint16_t>(16 + ((i >> 1) & 1)),
                      static_cast<std::uint16_t>(16 + ((i >> 2) & 1))};
    t.set_node_value(c, 1.0f);
    if (i == 0) t.update_node(c, 0.0f);
  }
  EXPECT_EQ(t.search(OctreeKey{16, 16, 16})->depth, 16);
}

TEST(Octree, ChangeDetectionRecordsNewAndFlippedCells) {
  OccupancyOctree t(0.1);
  t.enable_change_detection(true);
  const OctreeKey a{1, 1, 1}, b{1, 1, 2};
  t.update_node(a, true);
  t.reset_changes();
  t.update_node(a, false);  // 0.85 - 0.41: still occupied
  t.update_node(a, false);  // 0.04: still occupied
  EXPECT_TRUE(t.changes().empty());
  t.update_node(a, false);  // flips to free
  t.update_node(b, false);  // new
  auto c = t.changes();
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].key, a);
  EXPECT_FALSE(c[0].created);
  EXPECT_EQ(c[1].key, b);
  EXPECT_TRUE(c[1].created);
  t.update_node(a, true);  // flips back: forgotten, as OctoMap
  t.update_node(a, true);
  c = t.changes();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].key, b);
}

TEST(Octree, ConcurrentReadsSeeTheSameTree) {
  OccupancyOctree t(0.1);
  std::mt19937_64 rng(11);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 3000; ++i) {
    pts.emplace_back(std::uniform_real_distribution<float>(-4, 4)(rng), std::uniform_real_distribution<float>(-4, 4)(rng),
                     std::uniform_real_distribution<float>(-1, 2)(rng));
  }
  t.insert_point_cloud(pts, Eigen::Vector3d(0.01, 0.02, 0.03));
  const auto queries = [&](int seed) {
    std::mt19937_64 g(static_cast<std::uint64_t>(seed));
    std::vector<float> out;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3d p(std::uniform_real_distribution<double>(-5, 5)(g),
                              std::uniform_real_distribution<double>(-5, 5)(g),
                              std::uniform_real_distribution<double>(-2, 3)(g));
      const auto n = t.search(p);
      out.push_back(n ? n->log_odds : 99.0f);
      const auto r = t.cast_ray({0.01, 0.02, 0.03}, p, {.max_range = 6.0});
      out.push_back(static_cast<float>(r.key.x + r.key.y + r.key.z) + static_cast<float>(r.termination));
    }
    return out;
  };
  std::vector<std::vector<float>> serial, parallel(4);
  for (int s = 0; s < 4; ++s) serial.push_back(queries(s));
  std::vector<std::thread> threads;
  for (int s = 0; s < 4; ++s) threads.emplace_back([&, s] { parallel[static_cast<std::size_t>(s)] = queries(s); });
  for (auto& th : threads) th.join();
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace rove
