#pragma once
// Readers of the OctoMap reference files (data/reference/octomap/, formats
// in data/reference/README.md) and of scan.dat.bz2, for the octree tests.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "rove/octree_reference_cases.h"
#include "rove/scan_dat.h"
#include "rove/maps/occupancy_octree.h"
#include "rove/serialization/gzip_stream.h"
#include "rove/test_data.h"

namespace rove::octree_test {

/// A reference file, decompressed, read front to back.
class RefReader {
 public:
  explicit RefReader(const std::string& name) {
    GzipFileInStream in(test_data::bundled_file("reference/octomap/" + name));
    std::byte buf[65536];
    for (std::size_t n; (n = in.read_some(buf)) > 0;) {
      const auto* p = reinterpret_cast<const char*>(buf);
      bytes_.insert(bytes_.end(), p, p + n);
    }
  }
  template <typename T>
  T get() {
    if (pos_ + sizeof(T) > bytes_.size()) throw std::runtime_error("reference file truncated");
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  void expect_magic(const char* magic) {
    ASSERT_GE(bytes_.size(), 8u);
    EXPECT_EQ(std::string(bytes_.data(), 8), std::string(magic));
    pos_ = 8;
  }
  bool at_end() const { return pos_ == bytes_.size(); }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
  std::size_t pos_ = 0;
};

/// An OCTTREE1 file: OctoMap's nodes in depth-first pre-order.
struct RefTree {
  double resolution = 0;
  std::uint64_t nodes = 0;
  std::uint64_t leaves = 0;
  std::vector<float> log_odds;      // per node
  std::vector<std::uint8_t> masks;  // per node
};

inline RefTree read_ref_tree(const std::string& name) {
  RefReader r(name);
  r.expect_magic("OCTTREE1");
  RefTree t;
  t.resolution = r.get<double>();
  t.nodes = r.get<std::uint64_t>();
  t.leaves = r.get<std::uint64_t>();
  std::vector<float> palette(r.get<std::uint32_t>());
  for (float& v : palette) v = r.get<float>();
  for (std::uint64_t i = 0; i < t.nodes; ++i) {
    t.log_odds.push_back(palette.at(r.get<std::uint16_t>()));
    t.masks.push_back(r.get<std::uint8_t>());
  }
  EXPECT_TRUE(r.at_end());
  return t;
}

/// Compares a tree with OctoMap's node by node (structure exactly, log-odds
/// within `tolerance`).
inline void expect_tree_matches(const OccupancyOctree& tree, const RefTree& ref, float tolerance = 1e-4f) {
  EXPECT_EQ(tree.resolution(), ref.resolution);
  EXPECT_EQ(tree.num_nodes(), ref.nodes);
  EXPECT_EQ(tree.num_leaves(), ref.leaves);
  std::size_t i = 0, bad_mask = 0, bad_value = 0;
  float worst = 0.0f;
  tree.for_each_node([&](const OctreeNodeRecord& n) {
    if (i < ref.nodes) {
      if (n.child_mask != ref.masks[i]) ++bad_mask;
      const float d = std::abs(n.log_odds - ref.log_odds[i]);
      worst = std::max(worst, d);
      if (!(d <= tolerance)) ++bad_value;
    }
    ++i;
  });
  EXPECT_EQ(i, ref.nodes);
  EXPECT_EQ(bad_mask, 0u) << "nodes whose children differ from OctoMap's";
  EXPECT_EQ(bad_value, 0u) << "nodes whose log-odds differ from OctoMap's by more than " << tolerance
                           << " (worst " << worst << ")";
}

/// The header of an OCTRAYS1 / OCTQUER1 file: the cases' generator.
struct RefCases {
  octree_reference::Box box;
  std::uint64_t seed = 0;
  std::uint64_t n = 0;
};

inline RefCases read_cases_header(RefReader& r) {
  RefCases c;
  EXPECT_EQ(r.get<std::uint32_t>(), octree_reference::kCasesVersion);
  c.seed = r.get<std::uint64_t>();
  for (float& v : c.box.lo) v = r.get<float>();
  for (float& v : c.box.hi) v = r.get<float>();
  c.n = r.get<std::uint64_t>();
  return c;
}

/// Compares cast_ray (OctoMap arithmetic) with the rays of an OCTRAYS1 file;
/// returns the number of rays compared.
inline std::size_t expect_rays_match(const OccupancyOctree& tree, const std::string& name) {
  RefReader r(name);
  r.expect_magic("OCTRAYS1");
  const RefCases cases = read_cases_header(r);
  octree_reference::SplitMix64 g{cases.seed};
  std::size_t bad = 0, hits = 0;
  for (std::uint64_t i = 0; i < cases.n; ++i) {
    const auto c = octree_reference::random_ray(g, cases.box, i);
    const bool hit = r.get<std::uint8_t>() != 0;
    OctreeKey key;
    key.x = r.get<std::uint16_t>();
    key.y = r.get<std::uint16_t>();
    key.z = r.get<std::uint16_t>();
    OctreeRayCastOptions opt;
    opt.ignore_unknown = c.ignore_unknown;
    opt.max_range = c.max_range;
    opt.arithmetic = OctreeRayArithmetic::OctoMap;
    const auto res = tree.cast_ray(Eigen::Vector3d(c.origin[0], c.origin[1], c.origin[2]),
                                   Eigen::Vector3d(c.direction[0], c.direction[1], c.direction[2]), opt);
    hits += hit ? 1 : 0;
    if (res.hit() != hit || res.key != key) {
      if (++bad <= 5) {
        ADD_FAILURE() << "ray " << i << ": OctoMap " << hit << " at (" << key.x << "," << key.y << "," << key.z
                      << "), rove " << res.hit() << " at (" << res.key.x << "," << res.key.y << "," << res.key.z << ")";
      }
    }
  }
  EXPECT_EQ(bad, 0u);
  EXPECT_GT(hits, cases.n / 20);
  EXPECT_TRUE(r.at_end());
  return static_cast<std::size_t>(cases.n);
}

}  // namespace rove::octree_test
