// Grid path planning, rove vs MRPT 2.5.8's PlannerSimple2D, on MRPT's own
// example: the Malaga campus map (1888 × 2738 cells of 8 cm), a robot of
// radius 0.30 m from (20, −110) to (90, 40). MRPT grows the obstacles inside
// computePath; rove's NavigationGrid (clearances) is timed separately and
// with the search (`_WithClearances`), since a navigator builds it once per
// map and plans many times on it.
#include <benchmark/benchmark.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/nav/planners/PlannerSimple2D.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <cstdlib>
#include <deque>

#include "rove/io/mrpt_gridmap.h"
#include "rove/nav/grid_planner.h"

namespace {

const char* kMap = ROVE_DATA_DIR "/2006-MalagaCampus.gridmap.gz";

const mrpt::maps::COccupancyGridMap2D& mrpt_map() {
  static const mrpt::maps::COccupancyGridMap2D g = [] {
    mrpt::io::CFileGZInputStream f(kMap);
    if (!f.fileOpenCorrectly()) {
      std::fprintf(stderr, "missing %s\n", kMap);
      std::exit(1);
    }
    mrpt::maps::COccupancyGridMap2D m;
    mrpt::serialization::archiveFrom(f) >> m;
    return m;
  }();
  return g;
}

const rove::OccupancyGrid& rove_map() {
  static const rove::OccupancyGrid g = rove::load_mrpt_gridmap(kMap).grid;
  return g;
}

const rove::NavigationGrid& rove_nav_grid() {
  static const rove::NavigationGrid g = rove::NavigationGrid::from_occupancy(rove_map());
  return g;
}

void BM_Plan_Mrpt(benchmark::State& st) {
  mrpt::nav::PlannerSimple2D planner;
  planner.robotRadius = 0.30f;
  double length = 0;
  for (auto _ : st) {
    std::deque<mrpt::math::TPoint2D> path;
    bool not_found = true;
    planner.computePath(mrpt_map(), mrpt::poses::CPose2D(20, -110, 0), mrpt::poses::CPose2D(90, 40, 0),
                        path, not_found);
    if (not_found) st.SkipWithError("MRPT found no path");
    length = 0;
    double px = 20, py = -110;
    for (const auto& p : path) {
      length += std::hypot(p.x - px, p.y - py);
      px = p.x;
      py = p.y;
    }
  }
  st.counters["length_m"] = length;
}

void plan_rove(benchmark::State& st, rove::GridPlannerMethod method, bool with_clearances) {
  rove::GridPlannerOptions o;
  o.robot_radius = 0.30;
  o.method = method;
  double length = 0;
  for (auto _ : st) {
    rove::GridPlanResult r;
    if (with_clearances) {
      r = rove::plan_path(rove::NavigationGrid::from_occupancy(rove_map()), rove::SE2d(20, -110, 0),
                          rove::SE2d(90, 40, 0), o);
    } else {
      r = rove::plan_path(rove_nav_grid(), rove::SE2d(20, -110, 0), rove::SE2d(90, 40, 0), o);
    }
    if (!r.ok()) st.SkipWithError(r.message.c_str());
    length = r.path.length;
  }
  st.counters["length_m"] = length;
}

void BM_Plan_RoveValueIteration(benchmark::State& st) {
  plan_rove(st, rove::GridPlannerMethod::ValueIteration, false);
}
void BM_Plan_RoveValueIteration_WithClearances(benchmark::State& st) {
  plan_rove(st, rove::GridPlannerMethod::ValueIteration, true);
}
void BM_Plan_RoveAStar(benchmark::State& st) { plan_rove(st, rove::GridPlannerMethod::AStar, false); }
void BM_Plan_RoveAStar_WithClearances(benchmark::State& st) {
  plan_rove(st, rove::GridPlannerMethod::AStar, true);
}
void BM_Clearances_Rove(benchmark::State& st) {
  for (auto _ : st) benchmark::DoNotOptimize(rove::NavigationGrid::from_occupancy(rove_map()).clearances().data());
}

BENCHMARK(BM_Plan_Mrpt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan_RoveValueIteration)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan_RoveValueIteration_WithClearances)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan_RoveAStar)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan_RoveAStar_WithClearances)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Clearances_Rove)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
