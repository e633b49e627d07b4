// Point-map algorithms (rove::maps) on real clouds read from PCD and PLY
// files, against the brute-force oracles of the maps tests.
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/maps/kdtree.h"
#include "rove/maps/point_cloud.h"
#include "rove/maps_oracles.h"
#include "rove/test_data.h"

namespace rove {
namespace {

using test_oracles::brute_all;
using test_oracles::expect_same_knn;

// k nearest in 3D and 2D and radius counts on a real cloud, queried near the
// points of room_scan2, against brute force.
void expect_matches_brute_force_on(const PointCloud& cloud) {
  const PointCloud room2 = read_pcd(test_data::bundled_file("pointcloud/room_scan2.pcd"));
  for (const PointCloud* c : {&cloud}) {
    KdTree3f tree(*c);
    KdTree2f tree2(*c);
    for (std::size_t t = 0; t < 12; ++t) {
      const Eigen::Vector3f q = room2[t * 9001 % room2.size()] + Eigen::Vector3f(0.05f, -0.02f, 0.01f);
      const auto all = brute_all<3, float>(c->points(), q);
      expect_same_knn(tree.knn(q, 8), all, 8);
      std::vector<Eigen::Vector2f> xy;
      for (const auto& p : c->points()) xy.push_back(p.head<2>());
      const auto all2 = brute_all<2, float>(xy, q.head<2>());
      expect_same_knn(tree2.knn(q.head<2>(), 4), all2, 4);
      std::size_t within = 0;
      for (const auto& a : all) within += a.sq_distance <= 0.2f * 0.2f ? 1 : 0;
      EXPECT_EQ(tree.radius(q, 0.2f).size(), within);
    }
  }
}

TEST(KdTree, MatchesBruteForceOnTheRealClouds) {
  expect_matches_brute_force_on(read_pcd(test_data::bundled_file("pointcloud/room_scan1.pcd")));
}

TEST(KdTreeDatasets, MatchesBruteForceOnTheSmallGicpCloud) {
  expect_matches_brute_force_on(read_ply(test_data::shared_dataset("pointcloud/small_gicp_target.ply")));
}

TEST(VoxelGrid, RoomScanAgreesWithTheOracle) {
  const PointCloud room = read_pcd(test_data::bundled_file("pointcloud/room_scan1.pcd"));
  test_oracles::expect_voxel_filter_matches_oracle(room, Eigen::Vector3f::Constant(0.1f));
}

}  // namespace
}  // namespace rove
