// Google Benchmark timings of rove::SE3d exp, log, compose and point action.
// Each benchmark cycles through 1024 fixed random inputs so that nothing is
// constant-folded. When built with ROVE_BENCH_WITH_MRPT defined (and linked
// against mrpt-poses), the same operations of MRPT 2.5 (Lie::SE<3>::exp/log on
// CPose3D, CPose3D composition, CPose3D::composePoint) run in the same binary,
// so their ratio can be read from one report. Note that MRPT's SE<3>::exp/log
// are pseudo-exponentials (the translation is passed through unchanged), i.e.
// less work than the true SE(3) exp/log timed here.

#include <cstddef>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "rove/math/se3.h"

#ifdef ROVE_BENCH_WITH_MRPT
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/Lie/SE.h>
#endif

namespace {

constexpr std::size_t kInputs = 1024;  // power of two: index with a mask

struct Inputs {
  std::vector<rove::SE3d::Tangent> tangents;
  std::vector<rove::SE3d> poses;
  std::vector<rove::Vector3<double>> points;
};

const Inputs& inputs() {
  static const Inputs in = [] {
    Inputs r;
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> trans(-5.0, 5.0);
    std::uniform_real_distribution<double> rot(-1.8, 1.8);
    for (std::size_t i = 0; i < kInputs; ++i) {
      rove::SE3d::Tangent xi;
      xi << trans(rng), trans(rng), trans(rng), rot(rng), rot(rng), rot(rng);
      r.tangents.push_back(xi);
      r.poses.push_back(rove::SE3d::exp(xi));
      r.points.emplace_back(trans(rng), trans(rng), trans(rng));
    }
    return r;
  }();
  return in;
}

void BM_rove_SE3_exp(benchmark::State& state) {
  const auto& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(rove::SE3d::exp(in.tangents[i++ & (kInputs - 1)]));
  }
}
BENCHMARK(BM_rove_SE3_exp);

void BM_rove_SE3_log(benchmark::State& state) {
  const auto& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(in.poses[i++ & (kInputs - 1)].log());
  }
}
BENCHMARK(BM_rove_SE3_log);

void BM_rove_SE3_compose(benchmark::State& state) {
  const auto& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++;
    benchmark::DoNotOptimize(in.poses[k & (kInputs - 1)] * in.poses[(k + 1) & (kInputs - 1)]);
  }
}
BENCHMARK(BM_rove_SE3_compose);

void BM_rove_SE3_act(benchmark::State& state) {
  const auto& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++;
    benchmark::DoNotOptimize(in.poses[k & (kInputs - 1)] * in.points[(k + 7) & (kInputs - 1)]);
  }
}
BENCHMARK(BM_rove_SE3_act);

#ifdef ROVE_BENCH_WITH_MRPT
struct MrptInputs {
  std::vector<mrpt::poses::Lie::SE<3>::tangent_vector> tangents;
  std::vector<mrpt::poses::CPose3D> poses;
  std::vector<mrpt::math::TPoint3D> points;
};

const MrptInputs& mrpt_inputs() {
  static const MrptInputs in = [] {
    MrptInputs r;
    const auto& src = inputs();
    for (std::size_t i = 0; i < kInputs; ++i) {
      mrpt::poses::Lie::SE<3>::tangent_vector v;
      for (int k = 0; k < 6; ++k) v[k] = src.tangents[i](k);
      r.tangents.push_back(v);
      r.poses.push_back(mrpt::poses::Lie::SE<3>::exp(v));
      const auto& p = src.points[i];
      r.points.emplace_back(p.x(), p.y(), p.z());
    }
    return r;
  }();
  return in;
}

void BM_mrpt_SE3_exp(benchmark::State& state) {
  const auto& in = mrpt_inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(mrpt::poses::Lie::SE<3>::exp(in.tangents[i++ & (kInputs - 1)]));
  }
}
BENCHMARK(BM_mrpt_SE3_exp);

void BM_mrpt_SE3_log(benchmark::State& state) {
  const auto& in = mrpt_inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(mrpt::poses::Lie::SE<3>::log(in.poses[i++ & (kInputs - 1)]));
  }
}
BENCHMARK(BM_mrpt_SE3_log);

void BM_mrpt_SE3_compose(benchmark::State& state) {
  const auto& in = mrpt_inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++;
    benchmark::DoNotOptimize(in.poses[k & (kInputs - 1)] + in.poses[(k + 1) & (kInputs - 1)]);
  }
}
BENCHMARK(BM_mrpt_SE3_compose);

void BM_mrpt_SE3_act(benchmark::State& state) {
  const auto& in = mrpt_inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++;
    benchmark::DoNotOptimize(
        in.poses[k & (kInputs - 1)].composePoint(in.points[(k + 7) & (kInputs - 1)]));
  }
}
BENCHMARK(BM_mrpt_SE3_act);
#endif

}  // namespace

BENCHMARK_MAIN();
