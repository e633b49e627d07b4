// The octree's ray walk and dense cell sets (internal headers): the walk
// against a plain transcription of the DDA rule it implements, the dense
// set against std::set, and the Morton order against the tree's child order.
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "../src/octree_dense_cells.h"
#include "../src/octree_rays.h"

namespace rove::detail {
namespace {

// The DDA rule written out with arrays (OctoMap's computeRayKeys as
// docs/octree.md states it): from the origin's cell, step along the axis
// whose border comes first (ties: t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ?
// 1 : 2)); stop on the end's cell, past the segment's length, or at the
// tree's edge.
template <typename P>
std::vector<OctreeKey> reference_walk(const P o[3], const P e[3], double res) {
  OctreeKey ko, ke;
  EXPECT_TRUE(point_to_key(1.0 / res, o, ko) && point_to_key(1.0 / res, e, ke));
  std::vector<OctreeKey> out;
  if (ko == ke) return out;
  out.push_back(ko);
  P dir[3] = {e[0] - o[0], e[1] - o[1], e[2] - o[2]};
  const P length = static_cast<P>(norm3(dir));
  if (!(length > P(0))) return out;
  for (P& d : dir) d /= length;
  int step[3];
  double t_max[3], t_delta[3];
  dda_setup(o, dir, ko, res, std::is_same_v<P, float>, step, t_max, t_delta);
  if (step[0] == 0 && step[1] == 0 && step[2] == 0) return out;
  int k[3] = {ko.x, ko.y, ko.z};
  while (true) {
    int a = 0;
    if (t_max[0] < t_max[1]) {
      a = t_max[0] < t_max[2] ? 0 : 2;
    } else {
      a = t_max[1] < t_max[2] ? 1 : 2;
    }
    k[a] += step[a];
    t_max[a] += t_delta[a];
    if (k[a] < 0 || k[a] > 0xFFFF) return out;
    const OctreeKey cur{static_cast<std::uint16_t>(k[0]), static_cast<std::uint16_t>(k[1]),
                        static_cast<std::uint16_t>(k[2])};
    if (cur == ke) return out;
    if (std::min({t_max[0], t_max[1], t_max[2]}) > static_cast<double>(length)) return out;
    out.push_back(cur);
  }
}

// Segments that stress the walk: random ones, ends on cell borders and
// centres, axis-parallel and diagonal ones (ties at cell corners), short ones.
template <typename P>
std::vector<std::array<P, 6>> test_segments(double res, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  std::vector<std::array<P, 6>> out;
  for (std::size_t i = 0; i < n; ++i) {
    double s[6];
    for (double& v : s) v = u(rng);
    switch (i % 6) {
      case 1:
        for (double& v : s) v = std::round(v / (0.5 * res)) * 0.5 * res;  // borders and centres
        break;
      case 2:
        s[4] = s[1], s[5] = s[2];  // along x
        break;
      case 3: {
        const double d = s[3] - s[0];  // diagonal through cell corners
        for (int a = 0; a < 3; ++a) s[a] = std::round(s[a] / res) * res, s[3 + a] = s[a] + d * (a == 1 ? -1 : 1);
        break;
      }
      case 4:
        for (int a = 0; a < 3; ++a) s[3 + a] = s[a] + 0.3 * res * (s[3 + a] > 0 ? 1 : -1);  // short
        break;
      default:
        break;
    }
    std::array<P, 6> seg{};
    for (int j = 0; j < 6; ++j) seg[static_cast<std::size_t>(j)] = static_cast<P>(s[j]);
    out.push_back(seg);
  }
  return out;
}

template <typename P>
void expect_walk_matches_reference(double res) {
  std::size_t cells = 0;
  for (const auto& s : test_segments<P>(res, 20000, 11)) {
    OctreeKey ko, ke;
    ASSERT_TRUE(point_to_key(1.0 / res, s.data(), ko) && point_to_key(1.0 / res, s.data() + 3, ke));
    std::vector<OctreeKey> got;
    std::vector<int> axes;
    traverse_ray(s.data(), s.data() + 3, ko, ke, res, [&](const OctreeKey& k, int axis) {
      got.push_back(k);
      axes.push_back(axis);
    });
    const std::vector<OctreeKey> want = reference_walk(s.data(), s.data() + 3, res);
    ASSERT_EQ(got, want) << "segment (" << s[0] << ", " << s[1] << ", " << s[2] << ") -> (" << s[3] << ", " << s[4]
                         << ", " << s[5] << ")";
    // The axis reported is the one the cell was entered along.
    for (std::size_t i = 0; i < got.size(); ++i) {
      if (i == 0) {
        EXPECT_EQ(axes[i], -1);
        continue;
      }
      ASSERT_GE(axes[i], 0);
      EXPECT_EQ(std::abs(int(got[i][axes[i]]) - int(got[i - 1][axes[i]])), 1);
    }
    cells += got.size();
  }
  EXPECT_GT(cells, 100000u);
}

TEST(OctreeRays, WalkEqualsThePlainDdaInDouble) { expect_walk_matches_reference<double>(0.1); }
TEST(OctreeRays, WalkEqualsThePlainDdaInFloat) { expect_walk_matches_reference<float>(0.05); }

// Depth-first order of cells: compare the child indices from the root down.
bool before_in_tree(const OctreeKey& a, const OctreeKey& b) {
  for (int d = 0; d < kOctreeDepth; ++d) {
    const unsigned ca = octree_child_index(a, d), cb = octree_child_index(b, d);
    if (ca != cb) return ca < cb;
  }
  return false;
}

TEST(OctreeRays, MortonCodesSortInTreeOrder) {
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> u(0, 0xFFFF), near(-40, 40);
  for (int i = 0; i < 100000; ++i) {
    const OctreeKey a{static_cast<std::uint16_t>(u(rng)), static_cast<std::uint16_t>(u(rng)),
                      static_cast<std::uint16_t>(u(rng))};
    OctreeKey b = a;
    if (i % 2 == 0) {
      b = {static_cast<std::uint16_t>(u(rng)), static_cast<std::uint16_t>(u(rng)), static_cast<std::uint16_t>(u(rng))};
    } else {
      for (int ax = 0; ax < 3; ++ax) b[ax] = static_cast<std::uint16_t>(std::clamp(a[ax] + near(rng), 0, 0xFFFF));
    }
    ASSERT_EQ(morton_code(a) < morton_code(b), before_in_tree(a, b));
    ASSERT_EQ(morton_code(a) == morton_code(b), a == b);
  }
}

// Rays from one origin into a dense set, against the cells traverse_ray lists.
struct DenseScan {
  std::vector<std::array<double, 6>> segments;
  std::set<OctreeKey> crossed, ends;
  OctreeKey lo{0xFFFF, 0xFFFF, 0xFFFF}, hi{0, 0, 0};
};

DenseScan dense_scan(double res, std::uint64_t seed) {
  DenseScan s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const double o[3] = {0.13, -0.41, 0.27};
  for (int i = 0; i < 3000; ++i) {
    std::array<double, 6> seg{o[0], o[1], o[2], u(rng), u(rng), 0.3 * u(rng)};
    OctreeKey ko, ke;
    point_to_key(1.0 / res, seg.data(), ko);
    point_to_key(1.0 / res, seg.data() + 3, ke);
    traverse_ray(seg.data(), seg.data() + 3, ko, ke, res, [&](const OctreeKey& k, int) { s.crossed.insert(k); });
    s.ends.insert(ke);
    for (const OctreeKey& k : {ko, ke}) {
      for (int a = 0; a < 3; ++a) {
        s.lo[a] = std::min(s.lo[a], k[a]);
        s.hi[a] = std::max(s.hi[a], k[a]);
      }
    }
    s.segments.push_back(seg);
  }
  for (int a = 0; a < 3; ++a) s.lo[a] = static_cast<std::uint16_t>(s.lo[a] - 2), s.hi[a] = static_cast<std::uint16_t>(s.hi[a] + 2);
  return s;
}

void mark_segments(DenseCellSet& set, const DenseScan& s, double res, std::size_t begin, std::size_t end) {
  DenseCellSet::Marker marker(set);
  for (std::size_t i = begin; i < end; ++i) {
    const auto& seg = s.segments[i];
    OctreeKey ko, ke;
    point_to_key(1.0 / res, seg.data(), ko);
    point_to_key(1.0 / res, seg.data() + 3, ke);
    walk_ray(seg.data(), seg.data() + 3, ko, ke, res, marker);
  }
}

// The cells of a set in its listing order, with their tags.
std::vector<std::pair<OctreeKey, bool>> listed(const DenseCellSet& set) {
  std::vector<std::pair<OctreeKey, bool>> out;
  for (const auto& b : set.blocks_in_tree_order()) {
    set.for_each_in_block(b.index, [&](const OctreeKey& k, bool tagged) { out.emplace_back(k, tagged); });
  }
  return out;
}

TEST(OctreeRays, DenseSetHoldsTheWalkedCellsInTreeOrder) {
  const double res = 0.05;
  const DenseScan s = dense_scan(res, 5);
  DenseCellSet set(s.lo, s.hi);
  for (const OctreeKey& k : s.ends) set.tag(k);
  mark_segments(set, s, res, 0, s.segments.size());
  EXPECT_FALSE(set.overflowed());
  const auto cells = listed(set);
  std::set<OctreeKey> all(s.crossed);
  all.insert(s.ends.begin(), s.ends.end());
  ASSERT_EQ(cells.size(), all.size());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    EXPECT_TRUE(all.count(cells[i].first));
    EXPECT_EQ(cells[i].second, s.ends.count(cells[i].first) == 1);
    if (i > 0) {
      ASSERT_LT(morton_code(cells[i - 1].first), morton_code(cells[i].first));
    }
  }
  EXPECT_GE(DenseCellSet::bytes_for(s.lo, s.hi), (s.hi.x - s.lo.x + 1) * (s.hi.y - s.lo.y + 1) * (s.hi.z - s.lo.z + 1) / 8);
}

TEST(OctreeRays, DenseSetsMergeIntoTheUnion) {
  const double res = 0.1;
  const DenseScan s = dense_scan(res, 6);
  DenseCellSet whole(s.lo, s.hi), first(s.lo, s.hi), second(s.lo, s.hi);
  const std::size_t half = s.segments.size() / 2;
  mark_segments(whole, s, res, 0, s.segments.size());
  mark_segments(first, s, res, 0, half);
  mark_segments(second, s, res, half, s.segments.size());
  EXPECT_NE(listed(first), listed(whole));
  const std::size_t w = first.words();
  first.merge_marks(second, 0, w / 3);
  first.merge_marks(second, w / 3, w);
  EXPECT_EQ(listed(first), listed(whole));
}

TEST(OctreeRays, CellsOutsideTheBoxAreReportedNotWritten) {
  const double res = 0.1;
  const DenseScan s = dense_scan(res, 7);
  // A box that holds the origin but not every ray's cells.
  OctreeKey hi = s.hi;
  hi.x = static_cast<std::uint16_t>(s.lo.x + (s.hi.x - s.lo.x) / 2);
  DenseCellSet set(s.lo, hi);
  mark_segments(set, s, res, 0, s.segments.size());
  EXPECT_TRUE(set.overflowed());
  for (const auto& [k, tagged] : listed(set)) {
    EXPECT_LE(k.x, ((hi.x >> DenseCellSet::kBlockShift) + 1) << DenseCellSet::kBlockShift);
    EXPECT_TRUE(s.crossed.count(k));
  }
  DenseCellSet other(s.lo, hi);
  other.tag(OctreeKey{static_cast<std::uint16_t>(s.hi.x + 100), s.lo.y, s.lo.z});
  EXPECT_TRUE(other.overflowed());
  EXPECT_TRUE(listed(other).empty());
}

}  // namespace
}  // namespace rove::detail
