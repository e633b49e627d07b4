// octree_export: the occupied cells of an OccupancyOctree as a point cloud
// and a horizontal slice as an occupancy grid, checked cell by cell against
// the tree's own queries.
#include "rove/maps/octree_export.h"

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

// A tree with scattered cells: some hit (occupied), some missed (free), and
// a block of 8 occupied siblings that pruning merges into one leaf.
OccupancyOctree scattered_tree(OctreeChannels channels = OctreeChannels::None) {
  OccupancyOctree t(0.1, {}, channels);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> d(32768 - 20, 32768 + 20);
  for (int i = 0; i < 400; ++i) {
    const OctreeKey k{static_cast<std::uint16_t>(d(rng)), static_cast<std::uint16_t>(d(rng)),
                      static_cast<std::uint16_t>(32768 + (i % 3))};
    t.update_node(k, i % 4 != 0);
  }
  for (int c = 0; c < 8; ++c) {
    const OctreeKey k{static_cast<std::uint16_t>(32800 + (c & 1)), static_cast<std::uint16_t>(32800 + ((c >> 1) & 1)),
                      static_cast<std::uint16_t>(32768 + ((c >> 2) & 1))};
    t.update_node(k, true);
  }
  return t;
}

TEST(OctreeExport, CloudHoldsTheCentreOfEveryOccupiedLeaf) {
  const OccupancyOctree t = scattered_tree();
  std::vector<Eigen::Vector3d> expected;
  bool pruned_block = false;
  t.for_each_leaf([&](const OctreeLeaf& l) {
    if (t.is_occupied(l.log_odds)) expected.push_back(t.center_of(l.key, l.depth));
    pruned_block = pruned_block || (l.depth == kOctreeDepth - 1 && l.key.x == 32800);
  });
  ASSERT_TRUE(pruned_block);  // the 8 siblings are one leaf
  const PointCloud cloud = octree_occupied_cloud(t);
  ASSERT_EQ(cloud.size(), expected.size());
  EXPECT_FALSE(cloud.has_colors());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_TRUE(cloud.points()[i].isApprox(expected[i].cast<float>())) << i;
    EXPECT_TRUE(t.is_occupied(t.search(cloud.points()[i].cast<double>())->log_odds));
  }
}

TEST(OctreeExport, FinestCellsSplitPrunedLeaves) {
  const OccupancyOctree t = scattered_tree();
  const PointCloud coarse = octree_occupied_cloud(t);
  OctreeCloudOptions o;
  o.finest_cells = true;
  const PointCloud fine = octree_occupied_cloud(t, o);
  EXPECT_EQ(fine.size(), coarse.size() + 7);  // the pruned block gives 8 points instead of 1
  std::set<std::tuple<int, int, int>> keys;
  for (const auto& p : fine.points()) {
    const OctreeKey k = t.key_checked(p.cast<double>());
    EXPECT_TRUE(t.center_of(k).cast<float>().isApprox(p));
    EXPECT_TRUE(t.is_occupied(t.search(k)->log_odds));
    keys.insert({k.x, k.y, k.z});
  }
  EXPECT_EQ(keys.size(), fine.size());  // every finest cell once
  o.max_points = coarse.size();
  EXPECT_THROW((void)octree_occupied_cloud(t, o), ResourceError);
  o.finest_cells = false;
  o.max_points = coarse.size() - 1;
  EXPECT_THROW((void)octree_occupied_cloud(t, o), ResourceError);
}

TEST(OctreeExport, CloudCarriesTheLeafColours) {
  OccupancyOctree t(0.1, {}, OctreeChannels::Color);
  const OctreeKey a{32768, 32768, 32768}, b{32770, 32768, 32768};
  t.update_node(a, true);
  t.update_node(b, true);
  ASSERT_TRUE(t.update_color(a, Rgb8{10, 20, 30}, OctreeColorUpdate::Set));
  const PointCloud cloud = octree_occupied_cloud(t);
  ASSERT_EQ(cloud.size(), 2u);
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors()[0], (Rgb8{10, 20, 30}));
  EXPECT_EQ(cloud.colors()[1], (Rgb8{255, 255, 255}));  // no colour measured: OctoMap's white
}

// Every grid cell against the tree's answer at the cell's centre.
void expect_slice_matches(const OccupancyOctree& t, const OccupancyGrid& g, double z) {
  std::size_t known = 0;
  for (std::uint32_t iy = 0; iy < g.size_y(); ++iy) {
    for (std::uint32_t ix = 0; ix < g.size_x(); ++ix) {
      const double x = g.x_min() + (ix + 0.5) * g.resolution(), y = g.y_min() + (iy + 0.5) * g.resolution();
      const auto n = t.search(Eigen::Vector3d(x, y, z));
      const float p_free = g.free_probability(static_cast<int>(ix), static_cast<int>(iy));
      if (!n) {
        EXPECT_EQ(p_free, 0.5f) << x << " " << y;
        continue;
      }
      ++known;
      EXPECT_NEAR(p_free, 1.0 - octree_probability(n->log_odds), 0.02) << x << " " << y;
      EXPECT_EQ(p_free < 0.5f, t.is_occupied(n->log_odds)) << x << " " << y;
    }
  }
  EXPECT_GT(known, 0u);
}

TEST(OctreeExport, SliceHoldsTheCellsAtItsHeight) {
  const OccupancyOctree t = scattered_tree();
  for (const double z : {0.01, 0.15, 0.25}) {
    SCOPED_TRACE(z);
    const OccupancyGrid g = octree_slice(t, z);
    EXPECT_FLOAT_EQ(g.resolution(), 0.1f);
    Eigen::Vector3d lo, hi;
    t.metric_bounds(lo, hi);
    EXPECT_LE(g.x_min(), lo.x() + 1e-4);
    EXPECT_GE(g.x_max(), hi.x() - 1e-4);
    expect_slice_matches(t, g, z);
  }
}

TEST(OctreeExport, SliceClipsLeavesLargerThanItsArea) {
  // One free cell far away keeps the rest of the tree unknown; a block of
  // 8^4 equal cells is pruned into one leaf 1.6 m wide that the area cuts.
  OccupancyOctree t(0.1);
  for (int x = 0; x < 16; ++x) {
    for (int y = 0; y < 16; ++y) {
      for (int z = 0; z < 16; ++z) {
        t.update_node(OctreeKey{static_cast<std::uint16_t>(32768 + x), static_cast<std::uint16_t>(32768 + y),
                                static_cast<std::uint16_t>(32768 + z)},
                      false);
      }
    }
  }
  ASSERT_EQ(t.num_leaves(), 1u);
  OctreeSliceOptions o;
  o.area = Eigen::Vector4d(-0.5, 0.75, 0.42, 3.0);
  const OccupancyGrid g = octree_slice(t, 0.5, o);
  EXPECT_NEAR(g.x_min(), -0.5, 1e-5);
  EXPECT_NEAR(g.y_min(), 0.7, 1e-5);
  EXPECT_NEAR(g.x_max(), 0.5, 1e-5);
  EXPECT_NEAR(g.y_max(), 3.0, 1e-5);
  expect_slice_matches(t, g, 0.5);
  // An area beyond the tree's extent is clipped to it.
  o.area = Eigen::Vector4d(-1e9, -1e9, -3276.0, -3276.0);
  const OccupancyGrid edge = octree_slice(t, 0.5, o);
  EXPECT_NEAR(edge.x_min(), -3276.8, 1e-3);
  o.max_cells = 10;
  EXPECT_THROW((void)octree_slice(t, 0.5, o), ResourceError);
}

TEST(OctreeExport, SliceRejectsBadHeightsAndAreas) {
  const OccupancyOctree t = scattered_tree();
  for (const double z : {std::nan(""), std::numeric_limits<double>::infinity(), 1e6}) {
    EXPECT_THROW((void)octree_slice(t, z), InvalidArgument) << z;
  }
  OctreeSliceOptions o;
  o.area = Eigen::Vector4d(1.0, 0.0, 0.0, 1.0);
  EXPECT_THROW((void)octree_slice(t, 0.0, o), InvalidArgument);
  o.area = Eigen::Vector4d(0.0, 0.0, std::nan(""), 1.0);
  EXPECT_THROW((void)octree_slice(t, 0.0, o), InvalidArgument);
  o.area = Eigen::Vector4d(1e6, 1e6, 2e6, 2e6);
  EXPECT_THROW((void)octree_slice(t, 0.0, o), InvalidArgument);
  // An empty tree gives one unknown cell.
  const OccupancyGrid g = octree_slice(OccupancyOctree(0.1), 0.0);
  EXPECT_EQ(g.size_x() * g.size_y(), 1u);
  EXPECT_TRUE(g.empty());
}

}  // namespace
}  // namespace rove
