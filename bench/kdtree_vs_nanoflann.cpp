// rove::KdTree3f against nanoflann 1.4 used directly, on room_scan1.pcd
// (112,586 points): build, kNN (k = 1 and 10) and radius (0.1 m, sorted)
// for 10,000 query points of room_scan2; and every point's k nearest
// (k = 10, 20) on the small_gicp source cloud after a 0.25 m voxel grid,
// as 3D registration prepares normals and covariances. Same leaf size (10), same float
// coordinates, same L2 metric; nanoflann indexes the cloud in place through
// the adaptor its examples use. The goal: rove within 1.1x of
// nanoflann directly (bench/RESULTS.md).

#include <cmath>
#include <cstdint>
#include <limits>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <benchmark/benchmark.h>
#include <nanoflann.hpp>

#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/maps/kdtree.h"
#include "rove/maps/point_cloud.h"
#include "rove/maps/voxel_grid.h"

namespace {

const std::string kRoom1 = std::string(ROVE_DATA_DIR) + "/room_scan1.pcd";
const std::string kRoom2 = std::string(ROVE_DATA_DIR) + "/room_scan2.pcd";

const rove::PointCloud& room1() {
  static const rove::PointCloud c = rove::read_pcd(kRoom1);
  return c;
}

/// room_scan1's finite points as a plain vector (what a user hands nanoflann).
const std::vector<Eigen::Vector3f>& room1_points() {
  static const std::vector<Eigen::Vector3f> v = [] {
    std::vector<Eigen::Vector3f> out;
    const auto& c = room1();
    out.reserve(c.size());
    for (std::size_t i = 0; i < c.size(); ++i)
      if (c[i].allFinite()) out.push_back(c[i]);
    return out;
  }();
  return v;
}

const std::vector<Eigen::Vector3f>& queries() {
  static const std::vector<Eigen::Vector3f> q = [] {
    const rove::PointCloud c2 = rove::read_pcd(kRoom2);
    std::vector<Eigen::Vector3f> out;
    for (std::size_t i = 0; i < c2.size() && out.size() < 10000; i += 11)
      if (c2[i].allFinite()) out.push_back(c2[i]);
    return out;
  }();
  return q;
}

/// The dataset adaptor of nanoflann's own examples.
struct VectorAdaptor {
  const std::vector<Eigen::Vector3f>& pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return pts[i][static_cast<int>(d)]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, VectorAdaptor>,
                                                     VectorAdaptor, 3, std::uint32_t>;

constexpr std::size_t kLeaf = 10;
constexpr float kRadius = 0.1f;

void BM_Build_Rove(benchmark::State& st) {
  const auto& c = room1();
  for (auto _ : st) {
    rove::KdTree3f t(c, rove::KdTreeOptions{kLeaf});
    benchmark::DoNotOptimize(t);
  }
}
void BM_Build_Nanoflann(benchmark::State& st) {
  VectorAdaptor a{room1_points()};
  for (auto _ : st) {
    NanoTree t(3, a, nanoflann::KDTreeSingleIndexAdaptorParams(kLeaf));
    auto* root = t.root_node;
    benchmark::DoNotOptimize(root);
  }
}

void BM_Knn_Rove(benchmark::State& st) {
  const std::size_t k = static_cast<std::size_t>(st.range(0));
  rove::KdTree3f t(room1(), rove::KdTreeOptions{kLeaf});
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
void BM_Knn_Nanoflann(benchmark::State& st) {
  const std::size_t k = static_cast<std::size_t>(st.range(0));
  VectorAdaptor a{room1_points()};
  NanoTree t(3, a, nanoflann::KDTreeSingleIndexAdaptorParams(kLeaf));
  const auto& q = queries();
  std::vector<std::uint32_t> idx(k);
  std::vector<float> d(k);
  double sum = 0;
  for (auto _ : st)
    for (const auto& p : q) {
      nanoflann::KNNResultSet<float, std::uint32_t> rs(k);
      rs.init(idx.data(), d.data());
      t.findNeighbors(rs, p.data(), nanoflann::SearchParams());
      sum += d[k - 1];
    }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * q.size()));
}

void BM_Radius_Rove(benchmark::State& st) {
  rove::KdTree3f t(room1(), rove::KdTreeOptions{kLeaf});
  const auto& q = queries();
  std::vector<rove::Neighbor<float>> out;
  std::size_t hits = 0;
  for (auto _ : st)
    for (const auto& p : q) hits += t.radius(p, kRadius, out, true);
  benchmark::DoNotOptimize(hits);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * q.size()));
}
void BM_Radius_Nanoflann(benchmark::State& st) {
  VectorAdaptor a{room1_points()};
  NanoTree t(3, a, nanoflann::KDTreeSingleIndexAdaptorParams(kLeaf));
  const auto& q = queries();
  std::vector<std::pair<std::uint32_t, float>> out;
  nanoflann::SearchParams sp;
  sp.sorted = true;
  std::size_t hits = 0;
  for (auto _ : st)
    for (const auto& p : q) hits += t.radiusSearch(p.data(), kRadius * kRadius, out, sp);
  benchmark::DoNotOptimize(hits);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * q.size()));
}

/// The small_gicp source cloud on a 0.25 m voxel grid: what GICP and
/// point-to-plane ICP prepare (every point's k nearest).
const std::vector<Eigen::Vector3f>& voxel_cloud() {
  static const std::vector<Eigen::Vector3f> v =
      rove::voxel_downsample(rove::read_ply(std::string(ROVE_DATA_DIR) + "/small_gicp_source.ply"), 0.25f)
          .points();
  return v;
}

/// Every point's k nearest as PreparedCloud3D finds them: one knn() per
/// point in tree order, each bounded by the previous one's reach plus the
/// step.
void BM_AllKnn_Rove(benchmark::State& st) {
  const std::size_t k = static_cast<std::size_t>(st.range(0));
  const auto& pts = voxel_cloud();
  rove::KdTree3f t(pts, rove::KdTreeOptions{kLeaf});
  std::vector<rove::Neighbor<float>> out(k);
  double sum = 0;
  for (auto _ : st) {
    float reach = std::numeric_limits<float>::infinity();
    Eigen::Vector3f prev = Eigen::Vector3f::Zero();
    for (std::uint32_t i : t.tree_order()) {
      const Eigen::Vector3f& q = pts[i];
      const float bound = std::isinf(reach) ? reach : (reach + (q - prev).norm()) * (1 + 1e-5f) + 1e-6f;
      std::size_t m = t.knn(q, k, out, bound);
      if (m < k) m = t.knn(q, k, out);
      reach = std::sqrt(out[m - 1].sq_distance);
      prev = q;
      sum += out[m - 1].sq_distance;
    }
  }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * pts.size()));
}

/// The same queries in nanoflann, unbounded (it takes no bound).
void BM_AllKnn_Nanoflann(benchmark::State& st) {
  const std::size_t k = static_cast<std::size_t>(st.range(0));
  VectorAdaptor a{voxel_cloud()};
  NanoTree t(3, a, nanoflann::KDTreeSingleIndexAdaptorParams(kLeaf));
  std::vector<std::uint32_t> idx(k);
  std::vector<float> d(k);
  double sum = 0;
  for (auto _ : st)
    for (const auto& p : voxel_cloud()) {
      nanoflann::KNNResultSet<float, std::uint32_t> rs(k);
      rs.init(idx.data(), d.data());
      t.findNeighbors(rs, p.data(), nanoflann::SearchParams());
      sum += d[k - 1];
    }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * voxel_cloud().size()));
}

}  // namespace

BENCHMARK(BM_AllKnn_Rove)->Arg(10)->Arg(20)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AllKnn_Nanoflann)->Arg(10)->Arg(20)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Build_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Build_Nanoflann)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Knn_Rove)->Arg(1)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Knn_Nanoflann)->Arg(1)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Radius_Rove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Radius_Nanoflann)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
