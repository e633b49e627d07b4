// Sequential RANSAC plane detection on the scene of the unit test: 3 planes
// (points on ±2 m patches, Gaussian noise σ = 5 mm) plus uniform outliers in
// the box [−3, 3]³ (one outlier per three plane points), scaled by the
// benchmark argument (points per plane). When built with
// ROVE_BENCH_WITH_MRPT, MRPT's ransac_detect_3D_planes runs on the same cloud
// with the same threshold and minimum support, for a ratio in the same run.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "rove/math/plane_detection.h"

#ifdef ROVE_BENCH_WITH_MRPT
#include <mrpt/math/CVectorDynamic.h>
#include <mrpt/math/TPlane.h>
#include <mrpt/math/ransac_applications.h>
#endif

namespace {

std::vector<Eigen::Vector3d> three_plane_cloud(int points_per_plane, std::uint64_t seed) {
  const Eigen::Vector3d normals[3] = {Eigen::Vector3d(0, 0, 1),
                                      Eigen::Vector3d(1, 0.2, 0).normalized(),
                                      Eigen::Vector3d(0.1, 1, 0.3).normalized()};
  const double offsets[3] = {1.0, -1.5, 2.0};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::uniform_real_distribution<double> patch(-2.0, 2.0);
  std::uniform_real_distribution<double> box(-3.0, 3.0);
  std::vector<Eigen::Vector3d> cloud;
  for (const auto& [n, d] : {std::pair{normals[0], offsets[0]}, std::pair{normals[1], offsets[1]},
                             std::pair{normals[2], offsets[2]}}) {
    const Eigen::Vector3d u = n.unitOrthogonal();
    const Eigen::Vector3d v = n.cross(u);
    for (int i = 0; i < points_per_plane; ++i) {
      cloud.push_back(-d * n + patch(rng) * u + patch(rng) * v +
                      Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    }
  }
  for (int i = 0; i < points_per_plane; ++i) cloud.emplace_back(box(rng), box(rng), box(rng));
  std::shuffle(cloud.begin(), cloud.end(), rng);
  return cloud;
}

void BM_DetectThreePlanes(benchmark::State& state) {
  const int per_plane = static_cast<int>(state.range(0));
  const std::vector<Eigen::Vector3d> cloud = three_plane_cloud(per_plane, 2024);
  rove::PlaneDetectionOptions options;
  options.ransac.distance_threshold = 0.015;
  options.min_inliers = static_cast<std::size_t>(per_plane / 3);
  std::size_t planes = 0;
  for (auto _ : state) {
    const rove::PlaneDetectionResult result = rove::detect_planes(cloud, options);
    planes = result.detections.size();
    benchmark::DoNotOptimize(result.detections.data());
  }
  state.counters["planes"] = static_cast<double>(planes);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(cloud.size()));
}
BENCHMARK(BM_DetectThreePlanes)->Arg(300)->Arg(3000)->Arg(30000)->Unit(benchmark::kMillisecond);

#ifdef ROVE_BENCH_WITH_MRPT
void BM_DetectThreePlanesMrpt(benchmark::State& state) {
  const int per_plane = static_cast<int>(state.range(0));
  const std::vector<Eigen::Vector3d> cloud = three_plane_cloud(per_plane, 2024);
  mrpt::math::CVectorDynamic<double> xs(cloud.size()), ys(cloud.size()), zs(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    xs[i] = cloud[i].x();
    ys[i] = cloud[i].y();
    zs[i] = cloud[i].z();
  }
  std::size_t planes = 0;
  for (auto _ : state) {
    std::vector<std::pair<std::size_t, mrpt::math::TPlane>> detected;
    mrpt::math::ransac_detect_3D_planes(xs, ys, zs, detected, 0.015,
                                        static_cast<std::size_t>(per_plane / 3));
    planes = detected.size();
    benchmark::DoNotOptimize(detected.data());
  }
  state.counters["planes"] = static_cast<double>(planes);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(cloud.size()));
}
BENCHMARK(BM_DetectThreePlanesMrpt)->Arg(300)->Arg(3000)->Unit(benchmark::kMillisecond);
#endif

void BM_SinglePlaneRansac(benchmark::State& state) {
  const std::vector<Eigen::Vector3d> cloud =
      three_plane_cloud(static_cast<int>(state.range(0)), 7);
  rove::RansacOptions options;
  options.distance_threshold = 0.015;
  for (auto _ : state) {
    auto result = rove::ransac(rove::PlaneRansacProblem{}, cloud, options);
    benchmark::DoNotOptimize(result.inliers.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(cloud.size()));
}
BENCHMARK(BM_SinglePlaneRansac)->Arg(300)->Arg(3000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
