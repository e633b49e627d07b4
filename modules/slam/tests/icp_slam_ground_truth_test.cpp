// ICP-SLAM against ground truth: a robot drives a loop through a simulated
// building (walls as segments, scans ray-cast with range noise, odometry
// with drift), with MRPT's demo configuration. The path ICP-SLAM estimates
// is compared with the true one, in rove's default arithmetic and in
// MRPT's (Arithmetic::Mrpt): the default must be at least as accurate.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "icp_slam_test_util.h"
#include "sim_building.h"
#include "rove/core/ini.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/slam/icp_slam.h"

namespace rove {
namespace {

using test::building;
using test::cast;

/// The true loop (x, y, heading) every 0.2 m, counter-clockwise around the
/// block, starting and ending at (1.5, 1.5) + origin.
std::vector<Pose2> true_path(const Eigen::Vector2d& origin) {
  return test::loop_path(origin, 1, 0.2, false);
}

struct LoopRun {
  std::vector<Pose2> path;
  double rmse = 0, end_error = 0;
};

/// Drives the loop through ICP-SLAM with the demo config in `arithmetic`.
/// The world and the noise are the same for every call with the same seed.
LoopRun drive(const Eigen::Vector2d& origin, Arithmetic arithmetic, std::uint64_t seed) {
  const std::vector<test::Segment> walls = building(origin);
  const std::vector<Pose2> truth = true_path(origin);
  IcpSlamConfig cfg = load_icp_slam_config(IniFile::load(test::data_path("icp-slam_demo_classic.ini")));
  cfg.options.icp.arithmetic = arithmetic;
  IcpSlam slam(cfg.options, std::move(cfg.map));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  // Odometry: each step's motion with 2 % scale error, 1 cm and 0.3° noise
  // and a heading drift of 0.5° per meter.
  Pose2 odo(origin.x() + 1.5, origin.y() + 1.5, 0.0);
  LoopRun run;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const Timestamp time = Timestamp::from_seconds(1000.0 + 0.1 * static_cast<double>(k));
    if (k > 0) {
      const Pose2 d = truth[k] - truth[k - 1];
      const double dist = d.norm();
      odo = odo + Pose2(1.02 * d.x() + 0.01 * unit(rng), 1.02 * d.y() + 0.01 * unit(rng),
                        d.phi() + std::numbers::pi / 180 * (0.3 * unit(rng) + 0.5 * dist));
    }
    auto o = std::make_shared<OdometryObservation>();
    o->odometry = odo;
    o->timestamp = time;
    slam.process(o);
    auto scan = std::make_shared<RangeScan2D>();
    scan->sensor_label = "LASER";
    scan->timestamp = time;
    scan->aperture = std::numbers::pi;
    scan->max_range = 30.0f;
    std::vector<float> ranges;
    for (std::size_t i = 0; i < 361; ++i) {
      const double a = truth[k].phi() - std::numbers::pi / 2 + std::numbers::pi * static_cast<double>(i) / 360.0;
      const double r = cast(walls, truth[k].translation(), Eigen::Vector2d(std::cos(a), std::sin(a)));
      ranges.push_back(r < 30.0 ? static_cast<float>(r + 0.01 * unit(rng)) : 0.0f);
    }
    scan->set_ranges(std::move(ranges));
    run.path.push_back(slam.process(scan).pose);
  }
  // The estimate lives in the frame of the first pose (the origin of the
  // map is where the first scan was inserted): compare relative to it.
  std::vector<Pose2> rel_est, rel_true;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    rel_est.push_back(run.path[k] - run.path[0]);
    rel_true.push_back(truth[k] - truth[0]);
  }
  run.rmse = test::position_rmse(rel_est, rel_true);
  run.end_error = rel_est.back().distance_to(rel_true.back());
  return run;
}

// Near the origin both arithmetics see the same data to float precision: the
// default is as accurate as MRPT's (their paths differ by rounding only).
TEST(IcpSlamGroundTruth, DefaultArithmeticIsAsAccurateAsMrpts) {
  const Eigen::Vector2d origin(0, 0);
  const LoopRun d = drive(origin, Arithmetic::Double, 7);
  const LoopRun m = drive(origin, Arithmetic::Mrpt, 7);
  std::printf("[synthetic loop at the origin] position RMSE vs truth: %.4f m (double), %.4f m "
              "(mrpt); end error %.4f m / %.4f m over %zu steps\n",
              d.rmse, m.rmse, d.end_error, m.end_error, d.path.size());
  EXPECT_LT(d.rmse, 0.05);
  EXPECT_LT(d.end_error, 0.1);
  EXPECT_LE(d.rmse, m.rmse + 0.005);
}

// 25 km from the map's origin (where a georeferenced map puts its points),
// MRPT's single-precision fit sums raw coordinates and loses the path; the
// default arithmetic does not.
TEST(IcpSlamGroundTruth, DefaultArithmeticStaysAccurateFarFromTheOrigin) {
  const Eigen::Vector2d origin(20000.0, -15000.0);
  const LoopRun d = drive(origin, Arithmetic::Double, 7);
  const LoopRun m = drive(origin, Arithmetic::Mrpt, 7);
  std::printf("[synthetic loop 25 km from the origin] position RMSE vs truth: %.4f m (double), "
              "%.4f m (mrpt); end error %.4f m / %.4f m\n",
              d.rmse, m.rmse, d.end_error, m.end_error);
  EXPECT_LT(d.rmse, 0.05);
  EXPECT_LT(d.end_error, 0.1);
  EXPECT_LT(d.rmse, m.rmse);
}

}  // namespace
}  // namespace rove
