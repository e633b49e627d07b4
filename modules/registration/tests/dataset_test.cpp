// Registration on real data: the small_gicp outdoor LiDAR pair against its
// published transform, and the PCL NDT tutorial pair against PCL 1.13's
// result (tests/data/pcl_ndt_room_reference.txt, written by
// tools/pcl_registration_reference). A missing file fails the test.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/maps/voxel_grid.h"
#include "rove/registration/icp_3d.h"
#include "rove/registration/icp_3d_multi_resolution.h"
#include "rove/registration/ndt.h"
#include "rove/test_data.h"
#include "synthetic_3d.h"

namespace rove {
namespace {

// small_gicp's pair is in the shared datasets; the PCL tutorial pair is
// bundled in data/pointcloud.
const std::string kData = test_data::shared_datasets_dir() + "/pointcloud/";
const std::string kBundled = test_data::bundled_file("pointcloud/");
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

TEST(SmallGicpDatasets, GicpAndPointToPlane) {
  for (const char* f : {"small_gicp_source.ply", "small_gicp_target.ply",
                        "small_gicp_T_target_source.txt"})
    require_file(kData + f);
  std::ifstream tf(kData + "small_gicp_T_target_source.txt");
  const Eigen::Matrix4d truth = read_matrix(tf);
  const PointCloud source = read_ply(kData + "small_gicp_source.ply");
  const PointCloud target = read_ply(kData + "small_gicp_target.ply");
  ASSERT_GT(source.size(), 60000u);
  // Issue 5: from identity, within 2 cm and 0.2° of the published transform,
  // coarse to fine (voxel 0.25 m then 0.1 m, gate 3 × voxel, k = 10).
  // Measured: GICP 5.6 mm / 0.13°, point-to-plane 6.8 mm / 0.15°.
  for (auto method : {Icp3dMethod::Gicp, Icp3dMethod::PointToPlane}) {
    Icp3dMultiResolutionOptions o;
    o.icp.method = method;
    o.icp.num_threads = 2;
    const auto r = icp_3d_multi_resolution(target.points(), source.points(),
                                           SE3d(), o);
    SCOPED_TRACE(static_cast<int>(method));
    ASSERT_EQ(r.levels.size(), 2u);
    ASSERT_EQ(r.result.termination, RegistrationTermination::Converged) << r.result.message;
    const auto [et, er] = test::pose_error(r.result.T_target_source.matrix(), truth);
    EXPECT_LT(et, 0.02) << "translation error, m";
    EXPECT_LT(er, 0.2 * M_PI / 180) << "rotation error, rad";
    EXPECT_GT(r.result.goodness, 0.8);
  }
}

TEST(SmallGicpDatasets, SingleLevelWithTenNeighbours) {
  // One level at voxel 0.25 m: k = 10 neighbours and tight step tolerances
  // beat PCL's error at k = 20 (GICP 9.5 mm / 0.62°, point-to-plane
  // 27 mm / 0.68°, bench/RESULTS.md). Measured: GICP 7.1 mm / 0.33°,
  // point-to-plane 17 mm / 0.21°.
  for (const char* f : {"small_gicp_source.ply", "small_gicp_target.ply",
                        "small_gicp_T_target_source.txt"})
    require_file(kData + f);
  std::ifstream tf(kData + "small_gicp_T_target_source.txt");
  const Eigen::Matrix4d truth = read_matrix(tf);
  const PointCloud source = read_ply(kData + "small_gicp_source.ply");
  const PointCloud target = read_ply(kData + "small_gicp_target.ply");
  for (auto method : {Icp3dMethod::Gicp, Icp3dMethod::PointToPlane}) {
    Icp3dMultiResolutionOptions o;
    o.voxel_sizes = {0.25};
    o.distance_factor = 4;
    o.icp.method = method;
    const auto r = icp_3d_multi_resolution(target.points(), source.points(),
                                           SE3d(), o);
    SCOPED_TRACE(static_cast<int>(method));
    ASSERT_EQ(r.result.termination, RegistrationTermination::Converged) << r.result.message;
    const auto [et, er] = test::pose_error(r.result.T_target_source.matrix(), truth);
    EXPECT_LT(et, method == Icp3dMethod::Gicp ? 0.0095 : 0.027) << "translation error, m";
    EXPECT_LT(er, (method == Icp3dMethod::Gicp ? 0.5 : 0.3) * M_PI / 180) << "rotation error, rad";
  }
}

// Pairing walks the target's neighbourhoods (from its normals or
// covariances) and searches the tree only where the walk cannot certify the
// nearest point. The pairs must be exactly the tree's: point-to-point ICP,
// which ignores normals, gives the same run against a target with
// neighbourhoods as against a bare one, from several starts.
TEST(SmallGicpDatasets, PairingByNeighbourhoodsEqualsTreeSearch) {
  for (const char* f : {"small_gicp_source.ply", "small_gicp_target.ply"}) require_file(kData + f);
  const auto source = voxel_downsample(read_ply(kData + "small_gicp_source.ply"), 0.25f).points();
  const auto target = voxel_downsample(read_ply(kData + "small_gicp_target.ply"), 0.25f).points();
  PrepareOptions with;
  with.normals = true;
  with.neighbors = 10;
  const PreparedCloud3D bare_target(target);
  const PreparedCloud3D walk_target(target, with);
  ASSERT_FALSE(bare_target.has_neighborhoods());
  ASSERT_TRUE(walk_target.has_neighborhoods());
  const PreparedCloud3D src(source);
  for (const auto& start : {Eigen::Isometry3d::Identity(), test::make_pose(0.5, -0.3, 0.1, 0.02, 0.01, 0.1),
                            test::make_pose(-1.0, 0.4, 0, 0, 0, -0.2)}) {
    Icp3dOptions o;
    o.method = Icp3dMethod::PointToPoint;
    o.max_iterations = 30;
    const auto a = icp_3d(bare_target, src, SE3d(start.matrix()), o);
    const auto b = icp_3d(walk_target, src, SE3d(start.matrix()), o);
    EXPECT_EQ(a.T_target_source.matrix(), b.T_target_source.matrix());
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.correspondences, b.correspondences);
    EXPECT_EQ(a.information, b.information);
  }
}

/// The PCL tutorial pair: room_scan1 as the target, room_scan2 exactly as
/// PCL registered it (after its ApproximateVoxelGrid), and PCL's guess.
struct RoomPair {
  NdtGrid3D grid;
  std::vector<Eigen::Vector3f> source;
  Eigen::Isometry3d guess = Eigen::Isometry3d(Eigen::Translation3d(1.79387, 0.720047, 0) *
                                              Eigen::AngleAxisd(0.6931, Eigen::Vector3d::UnitZ()));
};

RoomPair room_pair() {
  RoomPair p;
  std::ifstream sf(kRef + "room_scan2_approx_voxel_0.2.f32", std::ios::binary);
  float xyz[3];
  while (sf.read(reinterpret_cast<char*>(xyz), sizeof xyz)) p.source.emplace_back(xyz[0], xyz[1], xyz[2]);
  const PointCloud target = read_pcd(kBundled + "room_scan1.pcd");
  p.grid = NdtGrid3D(std::span<const Eigen::Vector3f>(target.points()));
  return p;
}

// NdtCompat::Pcl against PCL 1.13's own run on the tutorial pair.
TEST(NdtPclCompat, TutorialPairMatchesPcl) {
  require_file(kBundled + "room_scan1.pcd");
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
  const RoomPair pair = room_pair();
  ASSERT_EQ(pair.source.size(), 12433u);
  NdtOptions o;
  o.compat = NdtCompat::Pcl;  // PCL's parametrization and rule, for parity
  o.transformation_epsilon = 0.01;
  o.step_size = 0.1;
  o.max_iterations = 35;
  o.num_threads = 2;
  const auto r = ndt_3d(pair.grid, pair.source, SE3d(pair.guess.matrix()), o);
  EXPECT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  EXPECT_EQ(r.iterations, pcl_iterations);
  const auto [et, er] = test::pose_error(r.T_target_source.matrix(), pcl_T);
  EXPECT_LT(et, 0.005) << "translation difference to PCL, m\n" << r.T_target_source.matrix() << "\nPCL\n" << pcl_T;
  EXPECT_LT(er, 0.05 * M_PI / 180) << "rotation difference to PCL, rad";
}

// Issue 18 item 2: PCL's rule "converges" after its first step of at most
// 0.1. The default runs on until the Newton step is within its tolerances
// (or says why not), and reaches a higher score than PCL's stop.
TEST(NdtRoomPair, DefaultRunsPastPclsFirstStep) {
  require_file(kBundled + "room_scan1.pcd");
  require_file(kRef + "room_scan2_approx_voxel_0.2.f32");
  const RoomPair pair = room_pair();
  NdtOptions p;
  p.compat = NdtCompat::Pcl;
  p.transformation_epsilon = 0.01;
  p.num_threads = 2;
  const auto r = ndt_3d(pair.grid, pair.source, SE3d(pair.guess.matrix()), p);
  NdtOptions d;
  d.num_threads = 2;
  const auto h = ndt_3d(pair.grid, pair.source, SE3d(pair.guess.matrix()), d);
  EXPECT_GT(h.iterations, 1) << h.message;
  if (h.ok()) {
    EXPECT_LE(h.iterations, d.max_iterations);
    EXPECT_NE(h.message.find("Newton step"), std::string::npos) << h.message;
  } else {
    EXPECT_TRUE(h.termination == RegistrationTermination::MaxIterations ||
                h.termination == RegistrationTermination::Stalled)
        << h.message;
  }
  EXPECT_GT(h.transformation_probability, r.transformation_probability) << h.message;
  const auto [et, er] = test::pose_error(h.T_target_source.matrix(), r.T_target_source.matrix());
  std::printf("tutorial pair, default: %d iterations, %.3f m / %.2f° from PCL's one-step answer\n",
              h.iterations, et, er * 180 / M_PI);
}

}  // namespace
}  // namespace rove
