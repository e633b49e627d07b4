// One TEB control cycle (optimize + command) at the size the issue names:
// a band of ~50 poses (6 m ahead at 0.4 m/s and dt_ref 0.3 s) and 100
// obstacle points (two walls 1.2 m to each side, a post near the line).
// Warm: the band kept from the previous cycle, as in closed loop; cold:
// built anew from the plan each time.
#include <benchmark/benchmark.h>

#include <vector>

#include "rove/nav/teb.h"

namespace {

struct Scene {
  std::vector<rove::SE2d> plan;
  std::vector<rove::TebObstacle> obstacles;
  rove::TebOptions options;
};

Scene scene() {
  Scene s;
  for (int i = 0; i <= 60; ++i) s.plan.emplace_back(0.1 * i, 0.0, 0.0);
  for (int i = 0; i < 49; ++i) {
    s.obstacles.push_back({{Eigen::Vector2d(0.125 * i, 1.2)}});
    s.obstacles.push_back({{Eigen::Vector2d(0.125 * i, -1.2)}});
  }
  s.obstacles.push_back({{Eigen::Vector2d(3.0, 0.45)}});
  s.obstacles.push_back({{Eigen::Vector2d(3.1, 0.45)}});
  s.options.max_global_plan_lookahead_dist = 6.0;
  s.options.max_vel_x = 0.4;
  s.options.robot_radius = 0.3;
  return s;
}

void BM_TebCycle(benchmark::State& st) {
  const Scene s = scene();
  rove::TebPlanner teb(s.options);
  const bool warm = st.range(0) != 0;
  int poses = 0;
  for (auto _ : st) {
    if (!warm) teb.reset();
    const rove::TebResult r = teb.plan(rove::SE2d(0, 0, 0), rove::Twist2{0.3, 0, 0}, s.plan, s.obstacles);
    if (!r.ok()) st.SkipWithError(r.message.c_str());
    poses = r.poses;
  }
  st.counters["band_poses"] = poses;
  st.counters["obstacles"] = static_cast<double>(s.obstacles.size());
}

BENCHMARK(BM_TebCycle)->Arg(1)->Arg(0)->ArgNames({"warm"})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
