#pragma once
// Helpers of the octree tests: a brute-force oracle of OctoMap's update
// semantics over finest cells, structural checks, tree comparison.
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "rove/maps/occupancy_octree.h"

namespace rove::octree_test {

/// Finest cells and their log-odds, updated one at a time as OctoMap's
/// updateNode does (float sum, clamped; a cell at the clamp it is pushed
/// towards stays as it is).
class CellOracle {
 public:
  explicit CellOracle(const OccupancyOctree& tree) : tree_(&tree) {}

  void update(const OctreeKey& k, float delta) {
    auto it = cells_.find(k);
    if (it == cells_.end()) it = cells_.emplace(k, 0.0f).first;
    float& v = it->second;
    if ((delta >= 0 && v >= tree_->clamp_max_log_odds()) || (delta <= 0 && v <= tree_->clamp_min_log_odds())) return;
    v += delta;
    if (v < tree_->clamp_min_log_odds()) {
      v = tree_->clamp_min_log_odds();
    } else if (v > tree_->clamp_max_log_odds()) {
      v = tree_->clamp_max_log_odds();
    }
  }

  /// One scan as OctoMap's insertPointCloud: each cell once, occupied wins.
  void insert_scan(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3d& origin, double max_range) {
    std::set<OctreeKey> occupied, free;
    for (const auto& pf : points) {
      const Eigen::Vector3d p = pf.cast<double>();
      Eigen::Vector3d end = p;
      bool hit = true;
      const Eigen::Vector3d d = p - origin;
      const double len = std::sqrt(d.x() * d.x() + d.y() * d.y() + d.z() * d.z());
      if (max_range >= 0 && len > max_range) {
        hit = false;
        const Eigen::Vector3d u(d.x() / len, d.y() / len, d.z() / len);
        end = Eigen::Vector3d(origin.x() + u.x() * max_range, origin.y() + u.y() * max_range,
                              origin.z() + u.z() * max_range);
      }
      for (const OctreeKey& k : tree_->ray_keys(origin, end)) free.insert(k);
      if (hit) occupied.insert(tree_->key_checked(p));
    }
    for (const OctreeKey& k : free) {
      if (!occupied.count(k)) update(k, tree_->miss_log_odds());
    }
    for (const OctreeKey& k : occupied) update(k, tree_->hit_log_odds());
  }

  /// One scan as OctoMap's insertPointCloudRays: ray after ray.
  void insert_rays(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3d& origin) {
    for (const auto& pf : points) {
      const Eigen::Vector3d p = pf.cast<double>();
      for (const OctreeKey& k : tree_->ray_keys(origin, p)) update(k, tree_->miss_log_odds());
      update(tree_->key_checked(p), tree_->hit_log_odds());
    }
  }

  const std::map<OctreeKey, float>& cells() const { return cells_; }

 private:
  const OccupancyOctree* tree_;
  std::map<OctreeKey, float> cells_;
};

/// Every oracle cell has its value in the tree, and the tree knows no other
/// finest cell.
inline void expect_matches_oracle(const OccupancyOctree& tree, const CellOracle& oracle) {
  std::size_t mismatches = 0;
  for (const auto& [k, v] : oracle.cells()) {
    const auto n = tree.search(k);
    if (!n || !n->leaf || n->log_odds != v) {
      if (++mismatches <= 5) {
        ADD_FAILURE() << "cell (" << k.x << ", " << k.y << ", " << k.z << "): oracle " << v << ", tree "
                      << (n ? std::to_string(n->log_odds) + " at depth " + std::to_string(n->depth) : "unknown");
      }
    }
  }
  EXPECT_EQ(mismatches, 0u);
  double covered = 0;
  tree.for_each_leaf([&](const OctreeLeaf& l) { covered += std::pow(8.0, kOctreeDepth - l.depth); });
  EXPECT_EQ(covered, static_cast<double>(oracle.cells().size()));
}

/// Inner nodes hold the maximum of their children; unless `lazy`, no node
/// has 8 leaf children of equal value (the tree is pruned).
inline void expect_consistent(const OccupancyOctree& tree, bool pruned = true) {
  std::vector<OctreeNodeRecord> nodes;
  tree.for_each_node([&](const OctreeNodeRecord& r) { nodes.push_back(r); });
  EXPECT_EQ(nodes.size(), tree.num_nodes());
  std::size_t i = 0;
  std::size_t bad_max = 0, unpruned = 0;
  struct Info {
    float v;
    bool leaf;
  };
  std::function<Info()> parse = [&]() -> Info {
    const OctreeNodeRecord r = nodes[i++];
    if (r.child_mask == 0) return {r.log_odds, true};
    std::vector<Info> ch;
    for (int c = 0; c < 8; ++c) {
      if ((r.child_mask >> c) & 1) ch.push_back(parse());
    }
    float m = -std::numeric_limits<float>::max();
    bool equal_leaves = ch.size() == 8;
    for (const Info& c : ch) {
      m = std::max(m, c.v);
      equal_leaves = equal_leaves && c.leaf && c.v == ch[0].v;
    }
    if (m != r.log_odds) ++bad_max;
    if (equal_leaves) ++unpruned;
    return {r.log_odds, false};
  };
  if (!nodes.empty()) parse();
  EXPECT_EQ(i, nodes.size());
  EXPECT_EQ(bad_max, 0u) << "inner nodes that are not the maximum of their children";
  if (pruned) {
    EXPECT_EQ(unpruned, 0u) << "nodes with 8 equal leaf children";
  }
}

/// The trees hold the same nodes with the same values (bit for bit).
inline void expect_same_tree(const OccupancyOctree& a, const OccupancyOctree& b) {
  std::vector<OctreeNodeRecord> na, nb;
  a.for_each_node([&](const OctreeNodeRecord& r) { na.push_back(r); });
  b.for_each_node([&](const OctreeNodeRecord& r) { nb.push_back(r); });
  ASSERT_EQ(na.size(), nb.size());
  EXPECT_EQ(a.num_nodes(), b.num_nodes());
  std::size_t diff = 0;
  for (std::size_t i = 0; i < na.size(); ++i) {
    const bool same = na[i].key == nb[i].key && na[i].depth == nb[i].depth && na[i].child_mask == nb[i].child_mask &&
                      std::memcmp(&na[i].log_odds, &nb[i].log_odds, sizeof(float)) == 0 &&
                      na[i].color.r == nb[i].color.r && na[i].color.g == nb[i].color.g &&
                      na[i].color.b == nb[i].color.b && na[i].statistics == nb[i].statistics;
    if (!same && ++diff <= 3) {
      ADD_FAILURE() << "node " << i << " differs";
    }
  }
  EXPECT_EQ(diff, 0u);
}

}  // namespace rove::octree_test
