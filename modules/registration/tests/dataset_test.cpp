// Registration on real data: the small_gicp outdoor LiDAR pair against its
// published transform, and the PCL NDT tutorial pair against PCL 1.13's
// result (tests/data/pcl_ndt_room_reference.txt, written by
// tools/pcl_registration_reference). The datasets live in
// ../shared/datasets/pointcloud; a missing file fails the test.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "rove/maps/pcd.h"
#include "rove/maps/ply.h"
#include "rove/maps/voxel_grid.h"
#include "rove/registration/icp_3d.h"
#include "rove/registration/ndt.h"
#include "synthetic_3d.h"

namespace rove {
namespace {

const std::string kData = std::string(ROVE_SOURCE_DIR) + "/../shared/datasets/pointcloud/";
const std::string kRef = std::string(ROVE_SOURCE_DIR) + "/modules/registration/tests/data/";

void require_file(const std::string& path) {
  ASSERT_TRUE(std::filesystem::exists(path))
      << "dataset file missing: " << path << " (see docs/registration.md)";
}

Eigen::Matrix4d read_matrix(std::istream& in) {
  Eigen::Matrix4d T;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) in >> T(i, j);
  return T;
}

TEST(Dataset, SmallGicpPairGicpAndPointToPlane) {
  for (const char* f : {"small_gicp_source.ply", "small_gicp_target.ply",
                        "small_gicp_T_target_source.txt"})
    require_file(kData + f);
  std::ifstream tf(kData + "small_gicp_T_target_source.txt");
  const Eigen::Matrix4d truth = read_matrix(tf);
  const PointCloud source = voxel_downsample(read_ply(kData + "small_gicp_source.ply"), 0.25f);
  const PointCloud target = voxel_downsample(read_ply(kData + "small_gicp_target.ply"), 0.25f);
  ASSERT_GT(source.size(), 3000u);
  PrepareOptions po;
  po.normals = true;
  po.covariances = true;
  po.neighbors = 20;
  po.num_threads = 2;
  const auto t = PreparedCloud3D::from_cloud(target, po);
  const auto s = PreparedCloud3D::from_cloud(source, po);
  for (auto method : {Icp3dMethod::Gicp, Icp3dMethod::PointToPlane}) {
    Icp3dOptions o;
    o.method = method;
    o.max_correspondence_distance = 1.0;
    o.num_threads = 2;
    const auto r = icp_3d(t, s, Eigen::Isometry3d::Identity(), o);
    SCOPED_TRACE(static_cast<int>(method));
    ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
    const auto [et, er] = test::pose_error(r.matrix, truth);
    // Measured: GICP 1.3 cm / 0.68°, point-to-plane 2.7 cm / 0.68°; the goal
    // (2 cm, 0.2°) is not met yet: the residual error is a roll of ~0.6° that
    // both costs prefer at this sampling (see docs/registration.md).
    EXPECT_LT(et, method == Icp3dMethod::Gicp ? 0.02 : 0.03) << "translation error, m";
    EXPECT_LT(er, 1.0 * M_PI / 180) << "rotation error, rad";
    EXPECT_GT(r.goodness, 0.8);
  }
}

TEST(Dataset, PclNdtTutorialPairMatchesPcl) {
  require_file(kData + "room_scan1.pcd");
  require_file(kRef + "pcl_ndt_room_reference.txt");
  require_file(kRef + "room_scan2_approx_voxel_0.2.f32");
  // PCL's reference: iterations and the 4×4 transform.
  std::ifstream rf(kRef + "pcl_ndt_room_reference.txt");
  std::string line, key;
  int pcl_iterations = -1;
  Eigen::Matrix4d pcl_T = Eigen::Matrix4d::Zero();
  while (std::getline(rf, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    ls >> key;
    if (key == "iterations") ls >> pcl_iterations;
    if (key == "T_target_source") pcl_T = read_matrix(rf);
  }
  ASSERT_GT(pcl_iterations, 0);
  // The source exactly as PCL registered it (after its ApproximateVoxelGrid).
  std::ifstream sf(kRef + "room_scan2_approx_voxel_0.2.f32", std::ios::binary);
  std::vector<Eigen::Vector3f> source;
  float xyz[3];
  while (sf.read(reinterpret_cast<char*>(xyz), sizeof xyz)) source.emplace_back(xyz[0], xyz[1], xyz[2]);
  ASSERT_EQ(source.size(), 12433u);
  const PointCloud target = read_pcd(kData + "room_scan1.pcd");
  const NdtGrid3D grid(std::span<const Eigen::Vector3f>(target.points()));
  NdtOptions o;
  o.transformation_epsilon = 0.01;
  o.step_size = 0.1;
  o.max_iterations = 35;
  o.num_threads = 2;
  const Eigen::Isometry3d guess(Eigen::Translation3d(1.79387, 0.720047, 0) *
                                Eigen::AngleAxisd(0.6931, Eigen::Vector3d::UnitZ()));
  const auto r = ndt_3d(grid, source, guess, o);
  EXPECT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  EXPECT_EQ(r.iterations, pcl_iterations);
  const auto [et, er] = test::pose_error(r.matrix, pcl_T);
  EXPECT_LT(et, 0.005) << "translation difference to PCL, m\n" << r.matrix << "\nPCL\n" << pcl_T;
  EXPECT_LT(er, 0.05 * M_PI / 180) << "rotation difference to PCL, rad";
}

}  // namespace
}  // namespace rove
