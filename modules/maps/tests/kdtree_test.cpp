#include "rove/maps/kdtree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/cpu.h"
#include "rove/core/error.h"
#include "rove/maps/point_cloud.h"
#include "rove/maps/point_cloud_concept.h"
#include "rove/maps_oracles.h"

namespace rove {
namespace {

// A user cloud type adapted through ADL, as the concept promises.
namespace user {
struct Xyz {
  double x, y, z;
};
struct MyCloud {
  std::vector<Xyz> pts;
};
std::size_t point_count(const MyCloud& c) { return c.pts.size(); }
Eigen::Vector3d point_at(const MyCloud& c, std::size_t i) {
  return {c.pts[i].x, c.pts[i].y, c.pts[i].z};
}
}  // namespace user

static_assert(PointCloudLike<PointCloud>);
static_assert(PointCloudLike<std::vector<Eigen::Vector3f>>);
static_assert(PointCloudLike<std::vector<Eigen::Vector2d>>);
static_assert(PointCloudLike<user::MyCloud>);
static_assert(!PointCloudLike<std::vector<float>>);
static_assert(cloud_dim_v<std::vector<Eigen::Vector2f>> == 2);
static_assert(std::is_same_v<cloud_scalar_t<user::MyCloud>, double>);

using test_oracles::brute_all;
using test_oracles::expect_same_knn;

template <int Dim, typename Scalar>
void random_check(std::size_t n, std::size_t leaf, unsigned seed, bool with_nans, bool quantized) {
  using P = Eigen::Matrix<Scalar, Dim, 1>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-10, 10);
  std::vector<P> pts(n);
  for (auto& p : pts)
    for (int k = 0; k < Dim; ++k)
      p[k] = static_cast<Scalar>(quantized ? std::round(u(rng)) : u(rng));  // quantized: many ties
  if (with_nans)
    for (std::size_t i = 0; i < n; i += 7) pts[i][i % Dim] = std::numeric_limits<Scalar>::quiet_NaN();
  KdTree<Dim, Scalar> tree(pts, KdTreeOptions{leaf});
  ASSERT_EQ(tree.source_size(), n);
  for (int t = 0; t < 50; ++t) {
    P q;
    for (int k = 0; k < Dim; ++k) q[k] = static_cast<Scalar>(u(rng) * 1.2);
    const auto all = brute_all<Dim, Scalar>(pts, q);
    ASSERT_EQ(tree.size(), all.size());
    // nearest
    auto nn = tree.nearest(q);
    ASSERT_TRUE(nn.has_value());
    EXPECT_EQ(nn->sq_distance, all[0].sq_distance);
    // k-nearest for several k, on both sides of every size of the small
    // k-nearest sets (8, 12, 16, 24, 32)
    for (std::size_t k : {1u, 2u, 5u, 8u, 9u, 10u, 12u, 13u, 16u, 17u, 24u, 25u, 32u, 33u, 70u})
      expect_same_knn(tree.knn(q, k), all, k);
    // radius (inclusive): the set must be exactly the brute-force one
    const Scalar r = static_cast<Scalar>(0.5 + (t % 5));
    auto got = tree.radius(q, r);
    std::vector<std::uint32_t> want;
    for (auto& a : all)
      if (a.sq_distance <= r * r) want.push_back(a.index);
    std::vector<std::uint32_t> got_idx;
    for (auto& g : got) got_idx.push_back(g.index);
    for (std::size_t i = 1; i < got.size(); ++i) EXPECT_LE(got[i - 1].sq_distance, got[i].sq_distance);
    std::sort(got_idx.begin(), got_idx.end());
    std::sort(want.begin(), want.end());
    EXPECT_EQ(got_idx, want);
    // k-nearest within a distance: the brute-force ones inside r, at most k
    for (std::size_t k : {1u, 5u, 12u, 20u, 33u}) {
      std::vector<Neighbor<Scalar>> inside;
      for (auto& a : all)
        if (a.sq_distance <= r * r) inside.push_back(a);
      std::vector<Neighbor<Scalar>> buf(k);
      buf.resize(tree.knn(q, k, buf, r));
      expect_same_knn(buf, inside, k);
      // an infinite bound is the unbounded search
      buf.assign(k, {});
      buf.resize(tree.knn(q, k, buf, std::numeric_limits<Scalar>::infinity()));
      expect_same_knn(buf, all, k);
    }
    // nearest within a distance with a hint (near, far, not indexed, out of
    // range): the same result as without
    for (std::uint32_t hint : {all[0].index, all[all.size() / 2].index, all.back().index,
                               std::uint32_t(n), std::uint32_t(-1)}) {
      const auto hinted = tree.nearest(q, r, hint);
      const auto plain = tree.nearest(q, r);
      ASSERT_EQ(hinted.has_value(), plain.has_value()) << "hint " << hint;
      if (plain) {
        EXPECT_EQ(*hinted, *plain) << "hint " << hint;
      }
    }
    // nearest within a distance
    auto within = tree.nearest(q, r);
    if (all[0].sq_distance <= r * r) {
      ASSERT_TRUE(within.has_value());
      EXPECT_EQ(within->sq_distance, all[0].sq_distance);
    } else {
      EXPECT_FALSE(within.has_value());
    }
  }
}

TEST(KdTree, MatchesBruteForce3f) { random_check<3, float>(1500, 10, 1, false, false); }
TEST(KdTree, MatchesBruteForce2f) { random_check<2, float>(1500, 10, 2, false, false); }
TEST(KdTree, MatchesBruteForce3d) { random_check<3, double>(1200, 4, 3, false, false); }
TEST(KdTree, MatchesBruteForce2d) { random_check<2, double>(1200, 1, 4, false, false); }
TEST(KdTree, SkipsNonFinitePoints) { random_check<3, float>(1500, 10, 5, true, false); }
TEST(KdTree, ManyTiesOnAGrid) { random_check<3, float>(1200, 16, 6, false, true); }
TEST(KdTree, ManyTiesOnAGrid2D) { random_check<2, float>(1200, 3, 7, false, true); }

// Points on a plane, on a line and on a few repeated coordinates give cells
// whose boxes are flat along some axes and splits that land on many equal
// values; every search must still match brute force.
template <typename Scalar>
void degenerate_check(const std::vector<Eigen::Matrix<Scalar, 3, 1>>& pts, std::size_t leaf, unsigned seed) {
  using P = Eigen::Matrix<Scalar, 3, 1>;
  KdTree<3, Scalar> tree(pts, KdTreeOptions{leaf});
  ASSERT_EQ(tree.size(), pts.size());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-6, 6);
  std::vector<Neighbor<Scalar>> unsorted;
  for (int t = 0; t < 40; ++t) {
    const P q(static_cast<Scalar>(u(rng)), static_cast<Scalar>(u(rng)), static_cast<Scalar>(u(rng) * 0.1));
    const auto all = brute_all<3, Scalar>(pts, q);
    EXPECT_EQ(tree.nearest(q)->sq_distance, all[0].sq_distance);
    for (std::size_t k : {1u, 3u, 16u, 100u}) expect_same_knn(tree.knn(q, k), all, k);
    const Scalar r = static_cast<Scalar>(1 + t % 3);
    const auto sorted = tree.radius(q, r);
    std::size_t want = 0;
    for (const auto& a : all) want += a.sq_distance <= r * r ? 1 : 0;
    ASSERT_EQ(sorted.size(), want);
    for (std::size_t i = 0; i < want; ++i) EXPECT_EQ(sorted[i], all[i]) << "rank " << i;
    // Unsorted: the same set.
    tree.radius(q, r, unsorted, false);
    std::sort(unsorted.begin(), unsorted.end(), [](const auto& a, const auto& b) {
      return a.sq_distance < b.sq_distance || (a.sq_distance == b.sq_distance && a.index < b.index);
    });
    EXPECT_EQ(unsorted, sorted);
  }
  for (std::size_t i = 0; i < pts.size(); i += 37) EXPECT_EQ(tree.indexed_point(static_cast<std::uint32_t>(i)), pts[i]);
}

// Runs the AVX2 kernels (where the processor has them) or the baseline
// ones while alive, then restores the setting.
struct IsaSetting {
  bool previous = avx2_enabled();
  explicit IsaSetting(bool avx2) { detail::set_avx2_enabled(avx2); }
  ~IsaSetting() { detail::set_avx2_enabled(previous); }
  IsaSetting(const IsaSetting&) = delete;
  IsaSetting& operator=(const IsaSetting&) = delete;
};

// The baseline k-nearest set against brute force, on a processor where the
// AVX2 one would otherwise run.
TEST(KdTree, BaselineKernelsMatchBruteForce) {
  const IsaSetting baseline(false);
  ASSERT_FALSE(avx2_enabled());
  random_check<3, float>(1500, 10, 11, false, false);
  random_check<3, float>(1200, 16, 12, false, true);
  random_check<2, float>(1200, 3, 13, false, true);
}

// The AVX2 and baseline k-nearest sets keep the very same neighbours, tie
// choices included (both sizes of the AVX2 set, bounded and not, with and
// without ties).
TEST(KdTree, BothInstructionSetsGiveTheSameNeighbours) {
  if (!detail::cpu_has_avx2()) GTEST_SKIP() << "this processor has no AVX2: only the baseline kernels exist";
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-5, 5);
  for (bool quantized : {false, true}) {
    std::vector<Eigen::Vector3f> pts(2000);
    for (auto& p : pts)
      for (int d = 0; d < 3; ++d) p[d] = quantized ? std::round(u(rng)) : u(rng);
    const KdTree3f tree(pts, KdTreeOptions{6});
    for (int t = 0; t < 100; ++t) {
      const Eigen::Vector3f q(u(rng), u(rng), u(rng));
      for (std::size_t k = 1; k <= 17; ++k) {
        for (float bound : {std::numeric_limits<float>::infinity(), 1.5f}) {
          std::vector<Neighbor<float>> wide(k), base(k);
          {
            const IsaSetting avx2(true);
            ASSERT_TRUE(avx2_enabled());
            wide.resize(tree.knn(q, k, wide, bound));
          }
          {
            const IsaSetting baseline(false);
            base.resize(tree.knn(q, k, base, bound));
          }
          ASSERT_EQ(wide, base) << "k " << k << ", bound " << bound << ", query " << t;
        }
      }
    }
  }
}

// Points at x = 2^i: every sliding-midpoint split peels one point off, so
// the tree is about 300 levels deep, deeper than the iterative search's
// stack; the searches take the recursive form and must still be exact.
TEST(KdTree, VeryDeepTreeMatchesBruteForce) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 300; ++i) pts.emplace_back(std::ldexp(1.0, i - 150), 0.25 * (i % 3), 0);
  KdTree3d tree(pts, KdTreeOptions{1});
  for (int i = 0; i < 300; i += 7) {
    const Eigen::Vector3d q(std::ldexp(1.3, i - 150), 0.1, 0.05);
    const auto all = brute_all<3, double>(pts, q);
    EXPECT_EQ(tree.nearest(q)->sq_distance, all[0].sq_distance);
    for (std::size_t k : {1u, 5u, 40u}) expect_same_knn(tree.knn(q, k), all, k);
    const auto within = tree.radius(q, std::ldexp(1.0, i - 150));
    std::size_t want = 0;
    for (const auto& a : all) want += a.sq_distance <= std::ldexp(1.0, 2 * (i - 150)) ? 1 : 0;
    EXPECT_EQ(within.size(), want);
  }
}

TEST(KdTree, TreeOrderIsAPermutationOfTheIndexedPoints) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-5, 5);
  std::vector<Eigen::Vector3f> pts(500);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
  pts[17].x() = std::numeric_limits<float>::quiet_NaN();
  KdTree3f tree(pts, KdTreeOptions{8});
  std::vector<std::uint32_t> order(tree.tree_order().begin(), tree.tree_order().end());
  ASSERT_EQ(order.size(), 499u);
  // Consecutive points in tree order are much closer than in input order.
  double step_tree = 0, step_input = 0;
  for (std::size_t i = 1; i < order.size(); ++i) step_tree += (pts[order[i]] - pts[order[i - 1]]).norm();
  for (std::size_t i = 19; i < pts.size(); ++i) step_input += (pts[i] - pts[i - 1]).norm();
  EXPECT_LT(step_tree, 0.5 * step_input);
  std::sort(order.begin(), order.end());
  for (std::uint32_t i = 0, j = 0; i < 500; ++i) {
    if (i == 17) continue;
    EXPECT_EQ(order[j++], i);
  }
}

TEST(KdTree, PointsOnAPlaneMatchBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-5, 5);
  std::vector<Eigen::Vector3f> pts(2000);
  for (auto& p : pts) p = Eigen::Vector3f(u(rng), u(rng), 0.0f);
  for (std::size_t leaf : {1u, 10u}) degenerate_check<float>(pts, leaf, 12);
}

TEST(KdTree, PointsOnALineMatchBruteForce) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-5, 5);
  std::vector<Eigen::Vector3d> pts(1500);
  for (auto& p : pts) {
    const double s = u(rng);
    p = Eigen::Vector3d(s, 0.5 * s, 1.0);
  }
  for (std::size_t leaf : {2u, 10u}) degenerate_check<double>(pts, leaf, 14);
}

TEST(KdTree, FewDistinctCoordinatesMatchBruteForce) {
  // Three values per axis: most splits fall on runs of equal coordinates.
  std::mt19937 rng(15);
  std::uniform_int_distribution<int> v(-1, 1);
  std::vector<Eigen::Vector3f> pts(1800);
  for (auto& p : pts) p = Eigen::Vector3f(2.0f * v(rng), 2.0f * v(rng), 0.1f * v(rng));
  for (std::size_t leaf : {1u, 7u, 64u}) degenerate_check<float>(pts, leaf, 16);
}

TEST(KdTree, TwoDimensionalTreeOverA3DCloudIgnoresZ) {
  PointCloud c;
  c.push_back({0, 0, 100});
  c.push_back({1, 0, 0});
  KdTree2f tree(c);
  auto nn = tree.nearest(Eigen::Vector2f(0.1f, 0));
  ASSERT_TRUE(nn);
  EXPECT_EQ(nn->index, 0u);
  KdTree3f tree3(c);
  EXPECT_EQ(tree3.nearest(Eigen::Vector3f(0.1f, 0, 0))->index, 1u);
}

TEST(KdTree, RadiusIsInclusiveAndExactOnTheSphere) {
  std::vector<Eigen::Vector3f> pts{{1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  KdTree3f tree(pts);
  EXPECT_EQ(tree.radius(Eigen::Vector3f::Zero(), 2.0f).size(), 2u);
  EXPECT_EQ(tree.radius(Eigen::Vector3f::Zero(), std::nextafter(2.0f, 0.0f)).size(), 1u);
  EXPECT_EQ(tree.radius(Eigen::Vector3f::Zero(), 0.0f).size(), 0u);
  EXPECT_EQ(tree.nearest(Eigen::Vector3f::Zero(), 1.0f)->index, 0u);
  EXPECT_FALSE(tree.nearest(Eigen::Vector3f::Zero(), 0.99f).has_value());
  EXPECT_EQ(tree.radius(Eigen::Vector3f(1, 0, 0), 0.0f).size(), 1u);  // a point at the query
}

TEST(KdTree, EmptyTreeAndNonFiniteQueriesFindNothing) {
  KdTree3f empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_FALSE(empty.nearest(Eigen::Vector3f::Zero()));
  EXPECT_TRUE(empty.knn(Eigen::Vector3f::Zero(), 3).empty());
  EXPECT_TRUE(empty.radius(Eigen::Vector3f::Zero(), 1.0f).empty());
  std::vector<Eigen::Vector3f> nans(5, Eigen::Vector3f::Constant(std::nanf("")));
  KdTree3f all_nan(nans);
  EXPECT_EQ(all_nan.size(), 0u);
  EXPECT_EQ(all_nan.source_size(), 5u);
  EXPECT_FALSE(all_nan.nearest(Eigen::Vector3f::Zero()));
  KdTree3f one(std::vector<Eigen::Vector3f>{{1, 2, 3}});
  EXPECT_FALSE(one.nearest(Eigen::Vector3f(std::nanf(""), 0, 0)));
  EXPECT_TRUE(one.knn(Eigen::Vector3f(INFINITY, 0, 0), 1).empty());
}

TEST(KdTree, RejectsBadArguments) {
  std::vector<Eigen::Vector3f> pts{{1, 0, 0}};
  EXPECT_THROW(KdTree3f(pts, KdTreeOptions{0}), InvalidArgument);
  KdTree3f tree(pts);
  EXPECT_THROW(tree.radius(Eigen::Vector3f::Zero(), -1.0f), InvalidArgument);
  EXPECT_THROW(tree.nearest(Eigen::Vector3f::Zero(), -1.0f), InvalidArgument);
  std::vector<Neighbor<float>> small(1);
  EXPECT_THROW(tree.knn(Eigen::Vector3f::Zero(), 2, small), InvalidArgument);
  EXPECT_THROW(tree.indexed_point(1), InvalidArgument);
  EXPECT_EQ(tree.indexed_point(0), Eigen::Vector3f(1, 0, 0));
}

TEST(KdTree, DuplicatePointsAndLargeK) {
  std::vector<Eigen::Vector3f> pts(100, Eigen::Vector3f(1, 1, 1));
  KdTree3f tree(pts, KdTreeOptions{4});
  auto r = tree.knn(Eigen::Vector3f::Zero(), 200);  // more than stored: all of them
  ASSERT_EQ(r.size(), 100u);
  std::vector<bool> seen(100, false);
  for (auto& n : r) {
    EXPECT_FLOAT_EQ(n.sq_distance, 3.0f);
    seen[n.index] = true;
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), true), 100);
}

TEST(KdTree, UserCloudTypeThroughTheConcept) {
  user::MyCloud c{{{0, 0, 0}, {5, 5, 5}, {1, 1, 1}}};
  KdTree3d tree(c);
  EXPECT_EQ(tree.nearest(Eigen::Vector3d(0.9, 0.9, 0.9))->index, 2u);
  KdTree3f treef(c);
  EXPECT_EQ(treef.nearest(Eigen::Vector3f(4, 4, 4))->index, 1u);
}

TEST(KdTree, MoveKeepsTheIndex) {
  std::vector<Eigen::Vector3f> pts{{1, 0, 0}, {2, 0, 0}};
  KdTree3f a(pts);
  KdTree3f b(std::move(a));
  EXPECT_EQ(b.nearest(Eigen::Vector3f(2.1f, 0, 0))->index, 1u);
  KdTree3f c;
  c = std::move(b);
  EXPECT_EQ(c.knn(Eigen::Vector3f(0, 0, 0), 2)[1].index, 1u);
}

// A hinted search starts at the hint's leaf and searches only the smallest
// subtree whose cell holds the search ball: on a grid with duplicate points
// (ties everywhere) it must pick the very point the unhinted search picks,
// for hints near and far, in 2D and 3D.
TEST(KdTree, HintedNearestBreaksTiesAsTheUnhinted) {
  std::vector<Eigen::Vector2f> pts2;
  std::vector<Eigen::Vector3f> pts3;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j)
      for (int dup = 0; dup < 2; ++dup) {
        pts2.emplace_back(0.1f * i, 0.1f * j);
        pts3.emplace_back(0.1f * i, 0.1f * j, 0.1f * ((i + j) % 3));
      }
  const KdTree2f t2(pts2);
  const KdTree3f t3(pts3);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> cell(0, 46);
  const auto n = static_cast<std::uint32_t>(pts2.size());
  for (int t = 0; t < 400; ++t) {
    // Queries on grid points, edge midpoints and cell centres: all ties.
    const Eigen::Vector2f q2(0.05f * cell(rng), 0.05f * cell(rng));
    const Eigen::Vector3f q3(q2.x(), q2.y(), 0.05f * (cell(rng) % 5));
    const auto plain2 = t2.nearest(q2, 0.3f);
    const auto plain3 = t3.nearest(q3, 0.3f);
    for (std::uint32_t hint : {static_cast<std::uint32_t>(rng() % n), plain2 ? plain2->index : 0u,
                               plain3 ? plain3->index : 0u, n - 1}) {
      const auto h2 = t2.nearest(q2, 0.3f, hint);
      const auto h3 = t3.nearest(q3, 0.3f, hint);
      ASSERT_EQ(h2.has_value(), plain2.has_value());
      ASSERT_EQ(h3.has_value(), plain3.has_value());
      if (plain2) {
        EXPECT_EQ(*h2, *plain2) << "query " << q2.transpose() << " hint " << hint;
      }
      if (plain3) {
        EXPECT_EQ(*h3, *plain3) << "query " << q3.transpose() << " hint " << hint;
      }
    }
  }
}

}  // namespace
}  // namespace rove
