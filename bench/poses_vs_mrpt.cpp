// rove vs MRPT 2.5.8 on 3D pose operations, same inputs, same run.
//
// Each operation is registered twice, "<op>/rove" and "<op>/mrpt";
// bench/run_poses_vs_mrpt.sh pairs them into a table of ns/op and ratios.
// Inputs: 1024 pairs of poses (and points) from the generator of the MRPT
// agreement test (modules/poses/tests/reference_cases.h), cycled through so
// that both libraries see identical values and a working set that fits in L1.

#include <benchmark/benchmark.h>

#include <mrpt/math/CVectorFixed.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/Lie/SE.h>

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "reference_cases.h"
#include "rove/math/se3.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose3.h"

namespace {

namespace ref = rove::reference;
using mrpt::poses::CPoint3D;
using mrpt::poses::CPose3D;
using MrptSE3 = mrpt::poses::Lie::SE<3>;

constexpr std::size_t kCount = 1024;  // power of two: index wraps with a mask

struct Inputs {
  std::vector<rove::Pose3> rove_a, rove_b;
  std::vector<rove::Point3> rove_p;
  std::vector<rove::SE3d> rove_se3;
  std::vector<rove::SE3d::Tangent> rove_xi;

  std::vector<CPose3D> mrpt_a, mrpt_b;
  std::vector<CPoint3D> mrpt_p;
  std::vector<MrptSE3::tangent_vector> mrpt_xi;
};

const Inputs& inputs() {
  static const Inputs in = [] {
    Inputs r;
    ref::SplitMix64 rng = ref::section_rng("bench_poses_vs_mrpt");
    for (std::size_t i = 0; i < kCount; ++i) {
      const ref::Pose3In a = ref::pose3(rng);
      const ref::Pose3In b = ref::pose3(rng);
      const ref::Point3In p = ref::point3(rng);
      r.rove_a.emplace_back(a[0], a[1], a[2], a[3], a[4], a[5]);
      r.rove_b.emplace_back(b[0], b[1], b[2], b[3], b[4], b[5]);
      r.rove_p.emplace_back(p[0], p[1], p[2]);
      r.mrpt_a.emplace_back(a[0], a[1], a[2], a[3], a[4], a[5]);
      r.mrpt_b.emplace_back(b[0], b[1], b[2], b[3], b[4], b[5]);
      r.mrpt_p.emplace_back(p[0], p[1], p[2]);
      // SE3 of pose a; the tangent vectors are its logarithm, so exp() sees
      // rotations of every angle in [0, π).
      const rove::SE3d T(r.rove_a.back().rotation(), r.rove_a.back().translation());
      r.rove_se3.push_back(T);
      const rove::SE3d::Tangent xi = T.log();
      r.rove_xi.push_back(xi);
      MrptSE3::tangent_vector mxi;
      for (int k = 0; k < 6; ++k) mxi[k] = xi[k];
      r.mrpt_xi.push_back(mxi);
    }
    return r;
  }();
  return in;
}

template <class Op>
void run(benchmark::State& state, Op&& op) {
  std::size_t i = 0;
  for (auto _ : state) {
    op(i);
    i = (i + 1) & (kCount - 1);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

// ---- Pose3 ⊕ Pose3 -----------------------------------------------------------
void pose3_compose_rove(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    rove::Pose3 r = in.rove_a[i] + in.rove_b[i];
    benchmark::DoNotOptimize(r);
  });
}
void pose3_compose_mrpt(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    CPose3D r = in.mrpt_a[i] + in.mrpt_b[i];
    benchmark::DoNotOptimize(r);
  });
}
// MRPT's in-place form, which avoids constructing the result.
void pose3_compose_into_rove(benchmark::State& st) {
  const Inputs& in = inputs();
  rove::Pose3 r;
  run(st, [&](std::size_t i) {
    r = in.rove_a[i] + in.rove_b[i];
    benchmark::DoNotOptimize(r);
  });
}
void pose3_compose_into_mrpt(benchmark::State& st) {
  const Inputs& in = inputs();
  CPose3D r;
  run(st, [&](std::size_t i) {
    r.composeFrom(in.mrpt_a[i], in.mrpt_b[i]);
    benchmark::DoNotOptimize(r);
  });
}

// ---- Pose3 ⊕ Point3 ----------------------------------------------------------
void pose3_plus_point3_rove(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    rove::Point3 r = in.rove_a[i] + in.rove_p[i];
    benchmark::DoNotOptimize(r);
  });
}
void pose3_plus_point3_mrpt(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    CPoint3D r = in.mrpt_a[i] + in.mrpt_p[i];
    benchmark::DoNotOptimize(r);
  });
}

// ---- Pose3 ⊖ Pose3 -----------------------------------------------------------
void pose3_inverse_compose_rove(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    rove::Pose3 r = in.rove_a[i] - in.rove_b[i];
    benchmark::DoNotOptimize(r);
  });
}
void pose3_inverse_compose_mrpt(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    CPose3D r = in.mrpt_a[i] - in.mrpt_b[i];
    benchmark::DoNotOptimize(r);
  });
}

// ---- SE(3) exp / log ---------------------------------------------------------
// MRPT's Lie::SE<3>::exp/log are a pseudo-exponential and pseudo-logarithm
// (only the rotation goes through exp/log, the translation is copied; see
// mrpt/poses/Lie/SE.h), so they do less work than rove's true SE(3) maps.
void se3_exp_rove(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    rove::SE3d r = rove::SE3d::exp(in.rove_xi[i]);
    benchmark::DoNotOptimize(r);
  });
}
void se3_exp_mrpt(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    CPose3D r = MrptSE3::exp(in.mrpt_xi[i]);
    benchmark::DoNotOptimize(r);
  });
}
void se3_log_rove(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    rove::SE3d::Tangent r = in.rove_se3[i].log();
    benchmark::DoNotOptimize(r);
  });
}
void se3_log_mrpt(benchmark::State& st) {
  const Inputs& in = inputs();
  run(st, [&](std::size_t i) {
    MrptSE3::tangent_vector r = MrptSE3::log(in.mrpt_a[i]);
    benchmark::DoNotOptimize(r);
  });
}

}  // namespace

int main(int argc, char** argv) {
  inputs();  // build the inputs before any timing
  benchmark::RegisterBenchmark("pose3_compose/rove", pose3_compose_rove);
  benchmark::RegisterBenchmark("pose3_compose/mrpt", pose3_compose_mrpt);
  benchmark::RegisterBenchmark("pose3_compose_into/rove", pose3_compose_into_rove);
  benchmark::RegisterBenchmark("pose3_compose_into/mrpt", pose3_compose_into_mrpt);
  benchmark::RegisterBenchmark("pose3_plus_point3/rove", pose3_plus_point3_rove);
  benchmark::RegisterBenchmark("pose3_plus_point3/mrpt", pose3_plus_point3_mrpt);
  benchmark::RegisterBenchmark("pose3_inverse_compose/rove", pose3_inverse_compose_rove);
  benchmark::RegisterBenchmark("pose3_inverse_compose/mrpt", pose3_inverse_compose_mrpt);
  benchmark::RegisterBenchmark("se3_exp/rove", se3_exp_rove);
  benchmark::RegisterBenchmark("se3_exp/mrpt", se3_exp_mrpt);
  benchmark::RegisterBenchmark("se3_log/rove", se3_log_rove);
  benchmark::RegisterBenchmark("se3_log/mrpt", se3_log_mrpt);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
