// The reactive navigator's control cycle, rove vs MRPT 2.5.8's
// CReactiveNavigationSystem (its library), on the same inputs: MRPT's own
// navigation-ptgs/reactive2d_config.ini (three PTGs of 121 paths, 10 m,
// FullEval), one scan of rove's simulated 360-ray lidar in the Malaga campus
// map at (20, −100) facing north, a target 8 m ahead. One cycle = MRPT's
// navigationStep() (sensing the points, the TP-space transforms, the
// holonomic method and the motion scores for every PTG) vs rove's
// ReactiveNavigator::step(). Both navigators are built (PTGs and collision
// grids) before the timed loop; MRPT runs in a scratch folder where it
// caches its grids.
#include <benchmark/benchmark.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/kinematics/CVehicleVelCmd_DiffDriven.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/nav/reactive/CReactiveNavigationSystem.h>
#include <mrpt/system/datetime.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>

#include "rove/io/mrpt_gridmap.h"
#include "rove/nav/reactive_navigator.h"
#include "rove/nav/simulator.h"
#include "rove/nav/teb.h"

namespace {

const char* kMap = ROVE_DATA_DIR "/2006-MalagaCampus.gridmap.gz";
const char* kConfig = "/usr/share/mrpt/config_files/navigation-ptgs/reactive2d_config.ini";

struct Inputs {
  rove::SE2d pose{20.0, -100.0, std::numbers::pi / 2};
  Eigen::Vector2d target{20.0, -92.0};
  std::vector<Eigen::Vector2d> points_map, points_robot;
};

const Inputs& inputs() {
  static const Inputs in = [] {
    Inputs d;
    const rove::NavigationGrid grid = rove::NavigationGrid::from_occupancy(rove::load_mrpt_gridmap(kMap).grid);
    rove::Simulator sim(grid, d.pose);
    const rove::RangeScan2D scan = sim.scan();
    d.points_robot = scan.points_2d(rove::ScanFrame::Robot);
    d.points_map = rove::scan_points_in_map(scan, d.pose);
    return d;
  }();
  return in;
}

class Robot : public mrpt::nav::CRobot2NavInterface {
 public:
  bool getCurrentPoseAndSpeeds(mrpt::math::TPose2D& pose, mrpt::math::TTwist2D& velocity,
                               mrpt::system::TTimeStamp& stamp, mrpt::math::TPose2D& odometry,
                               std::string& frame) override {
    const auto& p = inputs().pose;
    pose = mrpt::math::TPose2D(p.translation().x(), p.translation().y(), p.angle());
    velocity = mrpt::math::TTwist2D(0, 0, 0);
    stamp = mrpt::system::now();
    odometry = pose;
    frame = "map";
    return true;
  }
  bool changeSpeeds(const mrpt::kinematics::CVehicleVelCmd&) override { return true; }
  bool stop(bool) override { return true; }
  mrpt::kinematics::CVehicleVelCmd::Ptr getEmergencyStopCmd() override { return stop_cmd(); }
  mrpt::kinematics::CVehicleVelCmd::Ptr getStopCmd() override { return stop_cmd(); }
  bool senseObstacles(mrpt::maps::CSimplePointsMap& obstacles, mrpt::system::TTimeStamp& stamp) override {
    obstacles.clear();
    for (const auto& p : inputs().points_robot) obstacles.insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.1f);
    stamp = mrpt::system::now();
    return true;
  }

 private:
  static mrpt::kinematics::CVehicleVelCmd::Ptr stop_cmd() {
    return std::make_shared<mrpt::kinematics::CVehicleVelCmd_DiffDriven>();
  }
};

void BM_ReactiveCycle_Mrpt(benchmark::State& st) {
  const auto scratch = std::filesystem::temp_directory_path() / "rove_bench_reactive_mrpt";
  std::filesystem::create_directories(scratch);
  const auto here = std::filesystem::current_path();
  std::filesystem::current_path(scratch);
  Robot robot;
  mrpt::nav::CReactiveNavigationSystem nav(robot, false, false);
  nav.loadConfigFile(mrpt::config::CConfigFile(kConfig));
  nav.initialize();
  mrpt::nav::CAbstractNavigator::TNavigationParams params;
  params.target.target_coords = mrpt::math::TPose2D(inputs().target.x(), inputs().target.y(), 0);
  params.target.targetAllowedDistance = 0.3f;
  nav.navigate(&params);
  nav.navigationStep();  // the first step builds what MRPT builds lazily
  for (auto _ : st) nav.navigationStep();
  if (nav.getCurrentState() != mrpt::nav::CAbstractNavigator::NAVIGATING) st.SkipWithError("MRPT stopped navigating");
  std::filesystem::current_path(here);
  st.counters["points"] = static_cast<double>(inputs().points_robot.size());
}

void BM_ReactiveCycle_Rove(benchmark::State& st) {
  rove::ReactiveNavigator nav(rove::ReactiveNavigatorOptions::from_config(rove::IniFile::load(kConfig)));
  rove::ReactiveResult r;
  for (auto _ : st) {
    r = nav.step(inputs().pose, inputs().points_map, inputs().target, 0.3);
    benchmark::DoNotOptimize(r.command);
  }
  if (!r.ok()) st.SkipWithError(r.message.c_str());
  st.counters["points"] = static_cast<double>(inputs().points_map.size());
}

BENCHMARK(BM_ReactiveCycle_Mrpt)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_ReactiveCycle_Rove)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
