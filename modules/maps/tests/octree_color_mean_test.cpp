// OctreeColorMean: each leaf takes the mean colour of the points in it.
#include <map>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/maps/octree_color_mean.h"

namespace rove {
namespace {

struct Mean {
  int r = 0, g = 0, b = 0, n = 0;
};

TEST(OctreeColorMean, LeavesTakeTheMeanColourOfTheirPoints) {
  const double res = 0.1;
  OccupancyOctree t(res, {}, OctreeChannels::Color);
  // Two clouds: points in scattered cells, several per cell, and one point
  // in each of the 8 cells of a node at depth 15 (0.2 m) that ends pruned.
  std::vector<Eigen::Vector3f> a, b;
  std::vector<Rgb8> ca, cb;
  for (int i = 0; i < 60; ++i) {
    const float x = 0.05f + 0.1f * static_cast<float>(i % 7), y = -0.35f + 0.1f * static_cast<float>(i % 5);
    (i % 2 == 0 ? a : b).emplace_back(x + 0.01f * static_cast<float>(i % 3), y, 1.23f);
    (i % 2 == 0 ? ca : cb)
        .push_back(Rgb8{static_cast<std::uint8_t>(3 * i), static_cast<std::uint8_t>(250 - 4 * i),
                        static_cast<std::uint8_t>(i * i % 256)});
  }
  for (int c = 0; c < 8; ++c) {
    b.emplace_back(2.05f + 0.1f * static_cast<float>(c & 1), 2.05f + 0.1f * static_cast<float>((c >> 1) & 1),
                   2.05f + 0.1f * static_cast<float>(c >> 2));
    cb.push_back(Rgb8{static_cast<std::uint8_t>(10 * c + 1), static_cast<std::uint8_t>(200 - c), 17});
  }
  a.emplace_back(std::nanf(""), 0.0f, 0.0f);  // skipped
  ca.push_back(Rgb8{0, 0, 0});
  OctreeColorMean means(res);
  EXPECT_EQ(means.add(a, ca), a.size() - 1);
  EXPECT_EQ(means.add(b, cb), b.size());
  for (const auto* cloud : {&a, &b}) {
    OctreeInsertOptions o;
    o.skip_invalid_points = true;
    t.insert_point_cloud(*cloud, Eigen::Vector3d(0.0, 0.0, 0.0), o);
  }
  // The 8 cells were hit once and crossed by no ray: one pruned leaf.
  const auto pruned = t.search(OctreeKey{static_cast<std::uint16_t>(32768 + 20), static_cast<std::uint16_t>(32768 + 20),
                                         static_cast<std::uint16_t>(32768 + 20)});
  ASSERT_TRUE(pruned.has_value());
  EXPECT_EQ(pruned->depth, 15);

  // Expected: the points' colours summed per leaf (the leaf that holds each
  // point's cell), rounded to the nearest integer.
  std::map<std::pair<OctreeKey, int>, Mean> want;
  const auto add = [&](const std::vector<Eigen::Vector3f>& pts, const std::vector<Rgb8>& cols) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto k = t.key_of(pts[i].cast<double>());
      if (!k) continue;
      const int depth = t.search(*k)->depth;
      Mean& m = want[{octree_key_at_depth(*k, depth), depth}];
      m.r += cols[i].r, m.g += cols[i].g, m.b += cols[i].b, ++m.n;
    }
  };
  add(a, ca);
  add(b, cb);
  EXPECT_EQ(means.apply(t), want.size());
  const auto round_div = [](int s, int n) { return (s + n / 2) / n; };
  int multi = 0;
  for (const auto& [leaf, m] : want) {
    const auto c = t.color_at(leaf.first);
    ASSERT_TRUE(c.has_value());
    EXPECT_EQ(c->r, round_div(m.r, m.n));
    EXPECT_EQ(c->g, round_div(m.g, m.n));
    EXPECT_EQ(c->b, round_div(m.b, m.n));
    multi += m.n > 1 ? 1 : 0;
  }
  EXPECT_GT(multi, 5);
  // The pruned leaf: the mean of its 8 points, (36, 196.5 -> 197, 17).
  const auto pc = t.color_at(OctreeKey{32788, 32788, 32788});
  ASSERT_TRUE(pc.has_value());
  EXPECT_EQ(pc->r, 36);
  EXPECT_EQ(pc->g, 197);
  EXPECT_EQ(pc->b, 17);
  // The order of points and clouds does not matter.
  OccupancyOctree u(res, {}, OctreeChannels::Color);
  for (const auto* cloud : {&b, &a}) {
    OctreeInsertOptions o;
    o.skip_invalid_points = true;
    u.insert_point_cloud(*cloud, Eigen::Vector3d(0.0, 0.0, 0.0), o);
  }
  OctreeColorMean reversed(res);
  reversed.add(b, cb);
  reversed.add(a, ca);
  reversed.apply(u);
  for (const auto& [leaf, m] : want) EXPECT_EQ(u.color_at(leaf.first)->g, t.color_at(leaf.first)->g);
}

TEST(OctreeColorMean, PreconditionsAreChecked) {
  EXPECT_THROW(OctreeColorMean(0.0), InvalidArgument);
  OctreeColorMean m(0.1);
  const std::vector<Eigen::Vector3f> p = {{1, 2, 3}};
  EXPECT_THROW(m.add(p, {}), InvalidArgument);
  m.add(p, std::vector<Rgb8>{{1, 2, 3}});
  OccupancyOctree plain(0.1);
  EXPECT_THROW(m.apply(plain), InvalidArgument);
  OccupancyOctree other(0.2, {}, OctreeChannels::Color);
  EXPECT_THROW(m.apply(other), InvalidArgument);
}

}  // namespace
}  // namespace rove
