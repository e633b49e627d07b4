#pragma once
// Brute-force oracles for the point-map tests: k-nearest neighbours and
// voxel-grid averages computed the straightforward way. Shared by the tests
// of rove::maps and of the modules above it that run them on clouds read
// from files (rove::io).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "rove/maps/kdtree.h"
#include "rove/maps/point_cloud.h"
#include "rove/maps/voxel_grid.h"

namespace rove::test_oracles {

// Every finite point of `pts` with its squared distance to `q`, nearest
// first (ties by index).
template <int Dim, typename Scalar>
std::vector<Neighbor<Scalar>> brute_all(const std::vector<Eigen::Matrix<Scalar, Dim, 1>>& pts,
                                        const Eigen::Matrix<Scalar, Dim, 1>& q) {
  std::vector<Neighbor<Scalar>> all;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) continue;
    Scalar d = 0;
    for (int k = 0; k < Dim; ++k) d += (q[k] - pts[i][k]) * (q[k] - pts[i][k]);
    all.push_back({static_cast<std::uint32_t>(i), d});
  }
  std::sort(all.begin(), all.end(), [](auto& a, auto& b) {
    return a.sq_distance < b.sq_distance || (a.sq_distance == b.sq_distance && a.index < b.index);
  });
  return all;
}

// The k-th distances must agree exactly; the indices must agree where the
// distance is not tied.
template <typename Scalar>
void expect_same_knn(const std::vector<Neighbor<Scalar>>& got, const std::vector<Neighbor<Scalar>>& want,
                     std::size_t k) {
  const std::size_t n = std::min(k, want.size());
  ASSERT_EQ(got.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(got[i].sq_distance, want[i].sq_distance) << "rank " << i;
    const bool tied = (i > 0 && want[i - 1].sq_distance == want[i].sq_distance) ||
                      (i + 1 < want.size() && want[i + 1].sq_distance == want[i].sq_distance);
    if (!tied) {
      EXPECT_EQ(got[i].index, want[i].index) << "rank " << i;
    }
  }
}

// Oracle: group by PCL's float voxel index with a std::map, ordered z, y, x.
inline std::vector<Eigen::Vector3d> brute_voxels(const PointCloud& c, const Eigen::Vector3f& leaf) {
  std::map<std::array<std::int64_t, 3>, std::pair<Eigen::Vector3d, int>> cells;
  const Eigen::Array3f inv = leaf.array().inverse();
  for (const auto& p : c.points()) {
    if (!p.allFinite()) continue;
    std::array<std::int64_t, 3> k;
    for (int a = 0; a < 3; ++a) k[static_cast<std::size_t>(2 - a)] = static_cast<std::int64_t>(std::floor(p[a] * inv[a]));
    auto& e = cells[k];
    if (e.second == 0) e.first.setZero();
    e.first += p.cast<double>();
    ++e.second;
  }
  std::vector<Eigen::Vector3d> out;
  for (auto& [k, v] : cells) out.push_back(v.first / v.second);
  return out;
}

// voxel_grid_filter against brute_voxels.
inline void expect_voxel_filter_matches_oracle(const PointCloud& c, const Eigen::Vector3f& leaf) {
  VoxelGridOptions o;
  o.leaf_size = leaf;
  const auto r = voxel_grid_filter(c, o);
  const auto want = brute_voxels(c, leaf);
  ASSERT_EQ(r.cloud.size(), want.size());
  EXPECT_EQ(r.occupied_voxels, want.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    ASSERT_NEAR((r.cloud[i].cast<double>() - want[i]).norm(), 0.0, 1e-5 * (1 + want[i].norm())) << i;
}

}  // namespace rove::test_oracles
