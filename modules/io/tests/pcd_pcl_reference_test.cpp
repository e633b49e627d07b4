// Agreement with PCL 1.13 on the bundled clouds and small_gicp's (shared): the reference file was
// written by tools/pcl_reference (PCL's loadPCDFile/loadPLYFile, VoxelGrid,
// KdTreeFLANN); see that tool for the format.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/maps/kdtree.h"
#include "rove/maps/voxel_grid.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kReference = std::string(ROVE_SOURCE_DIR) + "/modules/io/tests/data/pcl_points_reference.txt";

// Checks the reference file's records of the PLY cloud (small_gicp's, in the
// shared datasets) or of the others (bundled in data/pointcloud).
void expect_agreement_with_pcl(bool shared_clouds, int expected_checks) {
  std::ifstream in(kReference);
  ASSERT_TRUE(in) << "missing " << kReference;
  std::map<std::string, PointCloud> clouds;
  std::map<std::string, PointCloud> voxels;
  std::map<std::string, KdTree3f> trees;
  auto cloud_of = [&](const std::string& name) -> const PointCloud& {
    auto it = clouds.find(name);
    if (it == clouds.end())
      it = clouds.emplace(name, name.ends_with(".ply") ? read_ply(test_data::shared_dataset("pointcloud/" + name))
                                                       : read_pcd(test_data::bundled_file("pointcloud/" + name)))
               .first;
    return it->second;
  };
  std::string line;
  int checks = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string kind, name;
    ls >> kind >> name;
    if (name.ends_with(".ply") != shared_clouds) continue;
    const PointCloud& c = cloud_of(name);
    if (kind == "cloud") {
      std::size_t n;
      ls >> n;
      EXPECT_EQ(c.size(), n) << name;
    } else if (kind == "point") {
      std::size_t i;
      float x, y, z;
      ls >> i >> x >> y >> z;
      ASSERT_LT(i, c.size());
      EXPECT_EQ(c[i], Eigen::Vector3f(x, y, z)) << name << " point " << i;  // bit-exact
    } else if (kind == "voxel" || kind == "centroid") {
      float leaf;
      ls >> leaf;
      const std::string key = name + std::to_string(leaf);
      if (!voxels.count(key)) voxels.emplace(key, voxel_downsample(c, leaf));
      const PointCloud& v = voxels.at(key);
      if (kind == "voxel") {
        std::size_t n;
        ls >> n;
        EXPECT_EQ(v.size(), n) << name;
      } else {
        std::size_t r;
        float x, y, z;
        ls >> r >> x >> y >> z;
        ASSERT_LT(r, v.size());
        // PCL sums in float, rove in double: equal to a few float ulps.
        EXPECT_NEAR((v[r] - Eigen::Vector3f(x, y, z)).norm(), 0.0f, 2e-6f * (1 + Eigen::Vector3f(x, y, z).norm()))
            << name << " centroid " << r;
      }
    } else if (kind == "knn") {
      float qx, qy, qz;
      std::size_t k;
      ls >> qx >> qy >> qz >> k;
      std::vector<std::uint32_t> want;
      std::vector<float> want_d;
      for (std::size_t j = 0; j < k; ++j) {
        std::uint32_t idx;
        float d;
        ls >> idx >> d;
        want.push_back(idx);
        want_d.push_back(d);
      }
      auto t = trees.find(name);
      if (t == trees.end()) t = trees.emplace(name, KdTree3f(c)).first;
      const KdTree3f& tree = t->second;
      const auto got = tree.knn(Eigen::Vector3f(qx, qy, qz), k);
      ASSERT_EQ(got.size(), k);
      // Same distances rank by rank; the same points except those tied
      // with the k-th distance (either library may pick any of them).
      std::vector<std::uint32_t> got_idx, want_idx;
      for (std::size_t j = 0; j < k; ++j) {
        EXPECT_NEAR(got[j].sq_distance, want_d[j], 1e-6f * want_d[j] + 1e-12f) << name << " rank " << j;
        if (want_d[j] < want_d[k - 1]) {
          got_idx.push_back(got[j].index);
          want_idx.push_back(want[j]);
        }
      }
      std::sort(got_idx.begin(), got_idx.end());
      std::sort(want_idx.begin(), want_idx.end());
      EXPECT_EQ(got_idx, want_idx) << name;
    } else {
      FAIL() << "unknown record: " << line;
    }
    ++checks;
  }
  EXPECT_EQ(checks, expected_checks);
}

TEST(PclReference, LoadFilterAndSearchAgreeWithPcl) { expect_agreement_with_pcl(false, 3 * 12); }

TEST(PclReferenceDatasets, SmallGicpCloudAgreesWithPcl) { expect_agreement_with_pcl(true, 12); }

}  // namespace
}  // namespace rove
