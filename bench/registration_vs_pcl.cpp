// rove::registration against PCL 1.13, side by side on the same input points:
//  - GICP and point-to-point ICP on the small_gicp pair after a 0.25 m voxel
//    grid (max correspondence 1.0 m; GICP with 20 neighbours; ICP 64
//    iterations), timed from the down-sampled clouds: KD-trees, covariances
//    and the registration itself, as PCL's align() does them;
//  - NDT on the PCL tutorial pair (source after PCL's ApproximateVoxelGrid
//    0.2, as the reference file; epsilon 0.01, step 0.1, resolution 1.0, 35
//    iterations), timed from the raw target: grid of cells + registration.
// Counters: t_err_mm / r_err_deg against small_gicp's reference transform
// (NDT: against PCL's own result), iterations.

#include <benchmark/benchmark.h>

#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

#include "rove/maps/pcd.h"
#include "rove/maps/ply.h"
#include "rove/maps/voxel_grid.h"
#include "rove/registration/icp_3d.h"
#include "rove/registration/ndt.h"

namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;

struct Data {
  rove::PointCloud gicp_source, gicp_target;
  PclCloud::Ptr pcl_source{new PclCloud}, pcl_target{new PclCloud};
  Eigen::Matrix4d truth;
  std::vector<Eigen::Vector3f> ndt_source;
  rove::PointCloud ndt_target;
  PclCloud::Ptr pcl_ndt_source{new PclCloud}, pcl_ndt_target{new PclCloud};
  Eigen::Matrix4d pcl_ndt_T;
};

PclCloud::Ptr to_pcl(const std::vector<Eigen::Vector3f>& pts) {
  PclCloud::Ptr c(new PclCloud);
  for (const auto& p : pts) c->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  return c;
}

const Data& data() {
  static const Data d = [] {
    Data d;
    const std::string dir = ROVE_DATA_DIR "/";
    d.gicp_source = rove::voxel_downsample(rove::read_ply(dir + "small_gicp_source.ply"), 0.25f);
    d.gicp_target = rove::voxel_downsample(rove::read_ply(dir + "small_gicp_target.ply"), 0.25f);
    d.pcl_source = to_pcl(d.gicp_source.points());
    d.pcl_target = to_pcl(d.gicp_target.points());
    std::ifstream tf(dir + "small_gicp_T_target_source.txt");
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) tf >> d.truth(i, j);
    std::ifstream sf(ROVE_REG_TEST_DATA "/room_scan2_approx_voxel_0.2.f32", std::ios::binary);
    float xyz[3];
    while (sf.read(reinterpret_cast<char*>(xyz), sizeof xyz)) d.ndt_source.emplace_back(xyz[0], xyz[1], xyz[2]);
    d.ndt_target = rove::read_pcd(dir + "room_scan1.pcd");
    d.pcl_ndt_source = to_pcl(d.ndt_source);
    d.pcl_ndt_target = to_pcl(d.ndt_target.points());
    std::ifstream rf(ROVE_REG_TEST_DATA "/pcl_ndt_room_reference.txt");
    std::string line;
    while (std::getline(rf, line))
      if (line == "T_target_source")
        for (int i = 0; i < 4; ++i)
          for (int j = 0; j < 4; ++j) rf >> d.pcl_ndt_T(i, j);
    return d;
  }();
  return d;
}

void errors(benchmark::State& st, const Eigen::Matrix4d& T, const Eigen::Matrix4d& ref) {
  const Eigen::Matrix4d e = T.inverse() * ref;
  const double c = std::clamp((e.topLeftCorner<3, 3>().trace() - 1) / 2, -1.0, 1.0);
  st.counters["t_err_mm"] = 1000 * e.topRightCorner<3, 1>().norm();
  st.counters["r_err_deg"] = std::acos(c) * 180 / M_PI;
}

Eigen::Isometry3d ndt_guess() {
  return Eigen::Isometry3d(Eigen::Translation3d(1.79387, 0.720047, 0) *
                           Eigen::AngleAxisd(0.6931, Eigen::Vector3d::UnitZ()));
}

void BM_rove_gicp(benchmark::State& st) {
  const auto& d = data();
  rove::Icp3dResult r;
  for (auto _ : st) {
    rove::PrepareOptions po;
    po.covariances = true;
    po.neighbors = 20;
    po.num_threads = static_cast<int>(st.range(0));
    const auto t = rove::PreparedCloud3D::from_cloud(d.gicp_target, po);
    const auto s = rove::PreparedCloud3D::from_cloud(d.gicp_source, po);
    rove::Icp3dOptions o;
    o.method = rove::Icp3dMethod::Gicp;
    o.num_threads = po.num_threads;
    r = rove::icp_3d(t, s, Eigen::Isometry3d::Identity(), o);
    benchmark::DoNotOptimize(r);
  }
  errors(st, r.matrix, d.truth);
  st.counters["iterations"] = r.iterations;
}

void BM_pcl_gicp(benchmark::State& st) {
  const auto& d = data();
  Eigen::Matrix4f T;
  int iters = 0;
  for (auto _ : st) {
    pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> g;
    g.setMaxCorrespondenceDistance(1.0);
    g.setCorrespondenceRandomness(20);
    g.setInputSource(d.pcl_source);
    g.setInputTarget(d.pcl_target);
    PclCloud out;
    g.align(out);
    T = g.getFinalTransformation();
    iters = g.nr_iterations_;
    benchmark::DoNotOptimize(out);
  }
  errors(st, T.cast<double>(), d.truth);
  st.counters["iterations"] = iters;
}

void BM_rove_icp(benchmark::State& st) {
  const auto& d = data();
  rove::Icp3dResult r;
  for (auto _ : st) {
    const auto t = rove::PreparedCloud3D::from_cloud(d.gicp_target);
    const auto s = rove::PreparedCloud3D::from_cloud(d.gicp_source);
    rove::Icp3dOptions o;
    o.method = rove::Icp3dMethod::PointToPoint;
    o.max_iterations = 64;
    o.num_threads = static_cast<int>(st.range(0));
    r = rove::icp_3d(t, s, Eigen::Isometry3d::Identity(), o);
    benchmark::DoNotOptimize(r);
  }
  errors(st, r.matrix, d.truth);
  st.counters["iterations"] = r.iterations;
}

void BM_pcl_icp(benchmark::State& st) {
  const auto& d = data();
  Eigen::Matrix4f T;
  for (auto _ : st) {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
    icp.setMaxCorrespondenceDistance(1.0);
    icp.setMaximumIterations(64);
    icp.setInputSource(d.pcl_source);
    icp.setInputTarget(d.pcl_target);
    PclCloud out;
    icp.align(out);
    T = icp.getFinalTransformation();
    benchmark::DoNotOptimize(out);
  }
  errors(st, T.cast<double>(), d.truth);
}

void BM_rove_ndt(benchmark::State& st) {
  const auto& d = data();
  rove::Ndt3dResult r;
  for (auto _ : st) {
    const rove::NdtGrid3D grid(std::span<const Eigen::Vector3f>(d.ndt_target.points()));
    rove::NdtOptions o;
    o.transformation_epsilon = 0.01;
    o.step_size = 0.1;
    o.max_iterations = 35;
    o.num_threads = static_cast<int>(st.range(0));
    r = rove::ndt_3d(grid, d.ndt_source, ndt_guess(), o);
    benchmark::DoNotOptimize(r);
  }
  errors(st, r.matrix, d.pcl_ndt_T);
  st.counters["iterations"] = r.iterations;
}

void BM_pcl_ndt(benchmark::State& st) {
  const auto& d = data();
  Eigen::Matrix4f T;
  for (auto _ : st) {
    pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
    ndt.setTransformationEpsilon(0.01);
    ndt.setStepSize(0.1);
    ndt.setResolution(1.0f);
    ndt.setMaximumIterations(35);
    ndt.setInputSource(d.pcl_ndt_source);
    ndt.setInputTarget(d.pcl_ndt_target);
    PclCloud out;
    ndt.align(out, ndt_guess().matrix().cast<float>());
    T = ndt.getFinalTransformation();
    benchmark::DoNotOptimize(out);
  }
  errors(st, T.cast<double>(), d.pcl_ndt_T);
}

}  // namespace

BENCHMARK(BM_rove_gicp)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_pcl_gicp)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_rove_icp)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_pcl_icp)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_rove_ndt)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_pcl_ndt)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
