// rove::maps against PCL 1.13 on the same clouds, in one run:
//  - voxel grid (room_scan1, leaf 0.1): rove::voxel_grid_filter vs pcl::VoxelGrid
//  - KD-tree build (room_scan1): rove::KdTree3f vs pcl::KdTreeFLANN
//  - kNN (k = 1, 10; 10,000 queries from room_scan2): same trees
//  - PCD load (room_scan1, binary_compressed): rove::read_pcd vs pcl::io::loadPCDFile
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include "rove/io/pcd.h"
#include "rove/maps/kdtree.h"
#include "rove/maps/voxel_grid.h"

namespace {

const std::string kRoom1 = std::string(ROVE_DATA_DIR) + "/room_scan1.pcd";
const std::string kRoom2 = std::string(ROVE_DATA_DIR) + "/room_scan2.pcd";

const rove::PointCloud& rove_room1() {
  static const rove::PointCloud c = rove::read_pcd(kRoom1);
  return c;
}
pcl::PointCloud<pcl::PointXYZ>::Ptr pcl_room1() {
  static pcl::PointCloud<pcl::PointXYZ>::Ptr c = [] {
    pcl::PointCloud<pcl::PointXYZ>::Ptr p(new pcl::PointCloud<pcl::PointXYZ>);
    if (pcl::io::loadPCDFile(kRoom1, *p) != 0) {
      std::fprintf(stderr, "cannot load %s\n", kRoom1.c_str());
      std::exit(1);
    }
    return p;
  }();
  return c;
}
const std::vector<Eigen::Vector3f>& queries() {
  static const std::vector<Eigen::Vector3f> q = [] {
    const rove::PointCloud c2 = rove::read_pcd(kRoom2);
    std::vector<Eigen::Vector3f> out;
    for (std::size_t i = 0; i < c2.size() && out.size() < 10000; i += 11) out.push_back(c2[i]);
    return out;
  }();
  return q;
}

void BM_VoxelGrid_Rove(benchmark::State& st) {
  const auto& c = rove_room1();
  std::size_t n = 0;
  for (auto _ : st) {
    auto r = rove::voxel_downsample(c, 0.1f);
    n = r.size();
    benchmark::DoNotOptimize(r);
  }
  st.counters["points_out"] = static_cast<double>(n);
}
void BM_VoxelGrid_Pcl(benchmark::State& st) {
  auto c = pcl_room1();
  std::size_t n = 0;
  for (auto _ : st) {
    pcl::VoxelGrid<pcl::PointXYZ> vg;
    vg.setInputCloud(c);
    vg.setLeafSize(0.1f, 0.1f, 0.1f);
    pcl::PointCloud<pcl::PointXYZ> out;
    vg.filter(out);
    n = out.size();
    benchmark::DoNotOptimize(out);
  }
  st.counters["points_out"] = static_cast<double>(n);
}

void BM_KdBuild_Rove(benchmark::State& st) {
  const auto& c = rove_room1();
  for (auto _ : st) {
    rove::KdTree3f t(c);
    benchmark::DoNotOptimize(t);
  }
}
void BM_KdBuild_Pcl(benchmark::State& st) {
  auto c = pcl_room1();
  for (auto _ : st) {
    pcl::KdTreeFLANN<pcl::PointXYZ> t;
    t.setInputCloud(c);
    benchmark::DoNotOptimize(t);
  }
}

void BM_Knn_Rove(benchmark::State& st) {
  const std::size_t k = static_cast<std::size_t>(st.range(0));
  rove::KdTree3f t(rove_room1());
  const auto& q = queries();
  std::vector<rove::Neighbor<float>> out(k);
  double sum = 0;
  for (auto _ : st)
    for (const auto& p : q) {
      t.knn(p, k, out);
      sum += out[k - 1].sq_distance;
    }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * q.size()));
}
void BM_Knn_Pcl(benchmark::State& st) {
  const int k = static_cast<int>(st.range(0));
  pcl::KdTreeFLANN<pcl::PointXYZ> t;
  t.setInputCloud(pcl_room1());
  const auto& q = queries();
  std::vector<int> idx(static_cast<std::size_t>(k));
  std::vector<float> d(static_cast<std::size_t>(k));
  double sum = 0;
  for (auto _ : st)
    for (const auto& p : q) {
      pcl::PointXYZ s(p.x(), p.y(), p.z());
      t.nearestKSearch(s, k, idx, d);
      sum += d[static_cast<std::size_t>(k - 1)];
    }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * q.size()));
}

void BM_PcdLoad_Rove(benchmark::State& st) {
  for (auto _ : st) {
    auto c = rove::read_pcd(kRoom1);
    benchmark::DoNotOptimize(c);
  }
}
void BM_PcdLoad_Pcl(benchmark::State& st) {
  for (auto _ : st) {
    pcl::PointCloud<pcl::PointXYZ> c;
    pcl::io::loadPCDFile(kRoom1, c);
    benchmark::DoNotOptimize(c);
  }
}

}  // namespace

BENCHMARK(BM_VoxelGrid_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VoxelGrid_Pcl)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KdBuild_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KdBuild_Pcl)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Knn_Rove)->Arg(1)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Knn_Pcl)->Arg(1)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PcdLoad_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PcdLoad_Pcl)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
