// The cost of one EKF-SLAM step against the number of landmarks N in the
// map: the map is built from one frame that sees all N landmarks (3D points
// at 5–50 m in every direction, known IDs), then each timed step is a
// prediction without odometry and an update with the readings of 10 mapped
// landmarks (by ID, one batch update: MRPT's kfEKFNaive). rove's EkfSlam3D
// and MRPT 2.5.8's CRangeBearingKFSLAM on the same readings. rove also
// reports the prediction alone, which touches only the robot's rows and
// columns (O(N)); the update's covariance downdate is O(N²).
#include <benchmark/benchmark.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/slam/CRangeBearingKFSLAM.h>

#include <cmath>
#include <random>
#include <vector>

#include "rove/slam/ekf_slam.h"

namespace {

constexpr int kSeen = 10;

struct Reading {
  int id;
  double range, yaw, pitch;
};

std::vector<Reading> landmarks(int n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> r(5.0, 50.0), yaw(-3.1, 3.1), pitch(-1.2, 1.2);
  std::vector<Reading> v;
  for (int i = 0; i < n; ++i) v.push_back({i, r(rng), yaw(rng), pitch(rng)});
  return v;
}

rove::EkfSlamFrame<3> rove_frame(const std::vector<Reading>& rs, int count) {
  rove::EkfSlamFrame<3> f;
  for (int i = 0; i < count; ++i) {
    f.readings.push_back({rs[static_cast<std::size_t>(i)].id,
                          {rs[static_cast<std::size_t>(i)].range, rs[static_cast<std::size_t>(i)].yaw,
                           rs[static_cast<std::size_t>(i)].pitch}});
  }
  return f;
}

void BM_RoveStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto rs = landmarks(n);
  rove::EkfSlam3D slam(rove::EkfSlamOptions::defaults(3));
  slam.step(std::nullopt, rove_frame(rs, n));
  const auto f = rove_frame(rs, kSeen);
  for (auto _ : state) benchmark::DoNotOptimize(slam.step(std::nullopt, f));
  state.SetComplexityN(n);
}

void BM_RovePredict(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  rove::EkfSlam3D slam(rove::EkfSlamOptions::defaults(3));
  slam.step(std::nullopt, rove_frame(landmarks(n), n));
  for (auto _ : state) {
    slam.predict(std::nullopt);
    benchmark::ClobberMemory();
  }
  state.SetComplexityN(n);
}

mrpt::obs::CSensoryFrame::Ptr mrpt_frame(const std::vector<Reading>& rs, int count) {
  auto obs = mrpt::obs::CObservationBearingRange::Create();
  obs->minSensorDistance = 0;
  obs->maxSensorDistance = 100;
  obs->fieldOfView_yaw = 2 * M_PI;
  obs->fieldOfView_pitch = M_PI;
  for (int i = 0; i < count; ++i) {
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    const Reading& r = rs[static_cast<std::size_t>(i)];
    m.landmarkID = r.id;
    m.range = static_cast<float>(r.range);
    m.yaw = static_cast<float>(r.yaw);
    m.pitch = static_cast<float>(r.pitch);
    obs->sensedData.push_back(m);
  }
  auto sf = mrpt::obs::CSensoryFrame::Create();
  sf->insert(obs);
  return sf;
}

void BM_MrptStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto rs = landmarks(n);
  mrpt::slam::CRangeBearingKFSLAM slam;
  mrpt::config::CConfigFileMemory ini;
  ini.write("RangeBearingKFSLAM_KalmanFilter", "method", "kfEKFNaive");
  slam.loadOptions(ini);
  auto action = mrpt::obs::CActionCollection::Create();
  auto all = mrpt_frame(rs, n);
  slam.processActionObservation(action, all);
  auto some = mrpt_frame(rs, kSeen);
  for (auto _ : state) slam.processActionObservation(action, some);
  state.SetComplexityN(n);
}

}  // namespace

BENCHMARK(BM_RoveStep)->RangeMultiplier(2)->Range(25, 1600)->Complexity(benchmark::oNSquared)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RovePredict)->RangeMultiplier(2)->Range(25, 1600)->Complexity(benchmark::oN)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MrptStep)->RangeMultiplier(2)->Range(25, 800)->Complexity(benchmark::oNSquared)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
