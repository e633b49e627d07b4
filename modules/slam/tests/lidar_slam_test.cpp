// Lidar SLAM against ground truth: a robot drives two laps around the
// simulated building (180° scans of 181 rays with 1 cm noise, odometry with
// 3 % scale error, noise and a heading drift of 1° per meter). The
// front-end alone must track the truth far better than the odometry; with
// loop closure the second lap closes onto the first with correct
// constraints. Then the options' loader, the honest counters, and the run
// over files (the bundled Telecom rawlog; logs without scans, with one
// scan, with no valid range).

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/obs/selection_error.h"
#include "rove/poses/lie_conversion.h"
#include "rove/slam/lidar_slam.h"
#include "rove/slam/lidar_slam_run.h"
#include "rove/slam/trajectory_eval.h"
#include "rove/test_data.h"
#include "sim_building.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct SimLog {
  std::vector<SE2d> truth;
  std::vector<std::shared_ptr<RangeScan2D>> scans;
  std::vector<SE2d> odometry_increments;  // [0] unused
};

SimLog simulate(int laps, std::uint64_t seed) {
  SimLog log;
  const auto walls = test::building({0, 0});
  for (const Pose2& p : test::loop_path({0, 0}, laps, 0.2)) log.truth.push_back(to_se2(p));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (std::size_t k = 0; k < log.truth.size(); ++k) {
    const SE2d& T = log.truth[k];
    if (k == 0) {
      log.odometry_increments.emplace_back();
    } else {
      const SE2d d = log.truth[k - 1].inverse() * T;
      const double dist = d.translation().norm();
      log.odometry_increments.emplace_back(1.03 * d.translation().x() + 0.005 * unit(rng),
                                           1.03 * d.translation().y() + 0.005 * unit(rng),
                                           d.angle() + kDeg * (0.3 * unit(rng) + 1.0 * dist));
    }
    auto scan = std::make_shared<RangeScan2D>();
    scan->sensor_label = "LASER";
    scan->aperture = std::numbers::pi;
    scan->max_range = 81.0f;
    std::vector<float> ranges;
    for (int i = 0; i < 181; ++i) {
      const double a = T.angle() - std::numbers::pi / 2 + std::numbers::pi * i / 180.0;
      const double r = test::cast(walls, T.translation(), Eigen::Vector2d(std::cos(a), std::sin(a)));
      ranges.push_back(r < 30.0 ? static_cast<float>(r + 0.01 * unit(rng)) : 81.0f);
    }
    scan->set_ranges(std::move(ranges));
    scan->timestamp = Timestamp::from_seconds(100.0 + 0.25 * static_cast<double>(k));
    log.scans.push_back(std::move(scan));
  }
  return log;
}

LidarSlamOptions test_options(bool loop_closure) {
  LidarSlamOptions o;
  o.loop_closure.enabled = loop_closure;
  o.loop_closure.window = {2.0, 15 * kDeg};
  o.loop_closure.depth = 5;
  o.submaps.scans_per_submap = 30;
  o.backend.optimize_every_n_nodes = 30;
  o.backend.scan_window = 0;  // the final refinement has its own test
  return o;
}

// Position errors of the estimate against the truth, both relative to the
// first pose.
struct Errors {
  double rmse = 0, max = 0;
};
Errors errors(const std::vector<SE2d>& est, const std::vector<SE2d>& truth) {
  Errors e;
  for (std::size_t k = 0; k < est.size(); ++k) {
    const SE2d a = est[0].inverse() * est[k], b = truth[0].inverse() * truth[k];
    const double d = (a.translation() - b.translation()).norm();
    e.rmse += d * d;
    e.max = std::max(e.max, d);
  }
  e.rmse = std::sqrt(e.rmse / static_cast<double>(est.size()));
  return e;
}

struct SlamRun {
  std::vector<SE2d> path, local, odometry;
  LidarSlamStats stats;
  std::vector<LidarLoopClosure> loops;
  std::vector<LidarSlamNode> nodes;
  std::vector<std::size_t> submap_first_node;
};

SlamRun drive(const SimLog& log, const LidarSlamOptions& options) {
  LidarSlam slam(options);
  SlamRun run;
  SE2d odo;
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    std::optional<SE2d> inc;
    if (k > 0) {
      inc = log.odometry_increments[k];
      odo = odo * *inc;
    }
    run.odometry.push_back(odo);
    slam.add_scan(log.scans[k], log.scans[k]->timestamp, inc);
  }
  slam.finish();
  for (std::size_t k = 0; k < slam.num_scans(); ++k) {
    run.path.push_back(slam.scan_pose(k));
    run.local.push_back(slam.scan_local_pose(k));
  }
  run.stats = slam.stats();
  run.loops = slam.loop_closures();
  run.nodes = slam.nodes();
  for (const auto& s : slam.submaps()) run.submap_first_node.push_back(s.nodes.front());
  return run;
}

TEST(LidarSlamGroundTruth, FrontEndTracksFarBetterThanOdometry) {
  const SimLog log = simulate(1, 3);
  const SlamRun r = drive(log, test_options(false));
  const Errors e = errors(r.path, log.truth), o = errors(r.odometry, log.truth);
  std::printf("[simulated lap, front-end only] RMSE %.4f m (max %.4f), odometry %.3f m; %zu nodes, "
              "%zu submaps\n",
              e.rmse, e.max, o.rmse, r.stats.nodes, r.stats.submaps);
  EXPECT_LT(e.rmse, 0.02);
  EXPECT_LT(e.max, 0.05);
  EXPECT_GT(o.rmse, 50 * e.rmse);
  EXPECT_EQ(r.stats.matched, log.scans.size() - 1);
  EXPECT_GT(r.stats.icp_refined, r.stats.matched * 9 / 10);
  EXPECT_EQ(r.stats.loop_searches, 0u);
  EXPECT_GT(r.stats.nodes, 100u);
}

TEST(LidarSlamGroundTruth, LoopClosureKeepsTwoLapsConsistent) {
  const SimLog log = simulate(2, 5);
  const SlamRun with = drive(log, test_options(true));
  const SlamRun without = drive(log, test_options(false));
  const Errors e = errors(with.path, log.truth), f = errors(without.path, log.truth);
  std::printf("[simulated two laps] RMSE %.4f m (max %.4f) with loop closure (%zu of %zu searches "
              "accepted, %zu optimizations), %.4f m (max %.4f) front-end only\n",
              e.rmse, e.max, with.stats.loops_accepted, with.stats.loop_searches,
              with.stats.optimizations, f.rmse, f.max);
  EXPECT_GT(with.stats.loops_accepted, 20u);
  EXPECT_GE(with.stats.optimizations, 1u);
  EXPECT_LT(e.rmse, 0.02);
  EXPECT_LT(e.max, 0.05);
  EXPECT_LT(e.rmse, f.rmse);
  // Every accepted constraint agrees with the truth: the node's pose in the
  // frame of the submap's first node f (a submap's frame is f's position in
  // the local frame, without rotation).
  std::size_t checked = 0;
  for (const auto& lc : with.loops) {
    if (lc.outcome != LoopClosureOutcome::Accepted) continue;
    const LidarSlamNode& f = with.nodes[with.submap_first_node[static_cast<std::size_t>(lc.submap)]];
    const SE2d T_local_submap(f.T_local_robot.translation().x(), f.T_local_robot.translation().y(), 0.0);
    const SE2d est = f.T_local_robot.inverse() * T_local_submap * lc.T_submap_robot;
    const SE2d truth = log.truth[f.scan].inverse() * log.truth[with.nodes[lc.node].scan];
    EXPECT_LT((est.translation() - truth.translation()).norm(), 0.1) << "node " << lc.node;
    EXPECT_LT(std::abs((est.inverse() * truth).angle()), 1.0 * kDeg) << "node " << lc.node;
    ++checked;
  }
  EXPECT_EQ(checked, with.stats.loops_accepted);
  // A node's scan has the node's optimized pose. Between two nodes a and b
  // the correction C = T_world_robot · T_local_robot⁻¹ moves from a's to
  // b's in equal steps (the scans are equally spaced in time), rather than
  // jumping to b's at b.
  for (const auto& n : with.nodes) EXPECT_TRUE(with.path[n.scan].is_approx(n.T_world_robot, 1e-9));
  const auto correction = [&](std::size_t k) { return with.path[k] * with.local[k].inverse(); };
  std::size_t between = 0;
  for (std::size_t m = 1; m < with.nodes.size(); ++m) {
    const std::size_t a = with.nodes[m - 1].scan, b = with.nodes[m].scan;
    const double total = (correction(a).inverse() * correction(b)).log().norm();
    for (std::size_t k = a; k < b; ++k) {
      const double step = (correction(k).inverse() * correction(k + 1)).log().norm();
      EXPECT_NEAR(step, total / static_cast<double>(b - a), 1e-9 + 1e-6 * total) << "scan " << k;
    }
    between += b - a - 1;
  }
  EXPECT_GT(between, 0u);
}

// Absolute (SE(2)-aligned) and relative (consecutive scans) errors of a
// path against the truth, as `rove eval ate` and `rove eval rpe` compute them.
struct PathErrors {
  double ate_rmse = 0, ate_max = 0, rpe_translation = 0, rpe_rotation = 0;
};
PathErrors path_errors(const std::vector<SE2d>& est, const std::vector<SE2d>& truth) {
  std::vector<StampedPose3> e, t;
  for (std::size_t k = 0; k < est.size(); ++k) {
    e.push_back({static_cast<double>(k), to_se3(Pose3(to_pose2(est[k])))});
    t.push_back({static_cast<double>(k), to_se3(Pose3(to_pose2(truth[k])))});
  }
  AteOptions ao;
  ao.alignment = TrajectoryAlignment::SE2;
  const AteResult ate = absolute_trajectory_error(t, e, ao);
  const RpeResult rpe = relative_pose_error(t, e);
  return {ate.translation.rmse, ate.translation.max, rpe.translation.mean, rpe.rotation.mean};
}

TEST(LidarSlamGroundTruth, RefinementJoinsEveryScanToItsNeighbours) {
  const SimLog log = simulate(2, 5);
  LidarSlamOptions o = test_options(true);
  const SlamRun nodes_only = drive(log, o);
  o.backend.scan_window = 3;
  const SlamRun refined = drive(log, o);
  o.backend.num_threads = 2;
  const SlamRun two_threads = drive(log, o);
  const std::size_t n = log.scans.size();
  const PathErrors e = path_errors(refined.path, log.truth), f = path_errors(nodes_only.path, log.truth);
  std::printf("[simulated two laps, refinement over every scan] ATE %.4f m (max %.4f), consecutive "
              "scans %.4f m %.4f deg; nodes only: ATE %.4f m (max %.4f), consecutive scans %.4f m "
              "%.4f deg; %zu of %zu pairs aligned\n",
              e.ate_rmse, e.ate_max, e.rpe_translation, e.rpe_rotation / kDeg, f.ate_rmse, f.ate_max,
              f.rpe_translation, f.rpe_rotation / kDeg, refined.stats.window_edges,
              refined.stats.window_edges + refined.stats.window_failed);
  // Every scan has returns: each is paired with the next three.
  EXPECT_EQ(refined.stats.window_edges + refined.stats.window_failed, 3 * n - 6);
  EXPECT_GT(refined.stats.window_edges, (3 * n - 6) * 8 / 10);
  EXPECT_EQ(nodes_only.stats.window_edges + nodes_only.stats.window_failed, 0u);
  // The path stays as good as the nodes' (it is 0.006 m here), and the
  // scans between nodes fit their neighbours better: the relative error of
  // consecutive scans drops by a third.
  EXPECT_LT(e.ate_rmse, 0.01);
  EXPECT_LT(e.ate_max, 0.03);
  EXPECT_LE(e.ate_rmse, f.ate_rmse);
  EXPECT_LT(e.rpe_translation, 0.8 * f.rpe_translation);
  EXPECT_LT(e.rpe_rotation, 0.8 * f.rpe_rotation);
  // The nodes take their scans' refined poses.
  for (const auto& node : refined.nodes) {
    EXPECT_TRUE(node.T_world_robot.is_approx(refined.path[node.scan], 1e-12)) << node.scan;
  }
  // The same result on two threads, to the bit.
  ASSERT_EQ(two_threads.path.size(), refined.path.size());
  for (std::size_t k = 0; k < n; ++k) {
    EXPECT_TRUE(two_threads.path[k].is_approx(refined.path[k], 0.0)) << k;
  }
  EXPECT_EQ(two_threads.stats.window_edges, refined.stats.window_edges);
}

TEST(LidarSlam, ScansWithoutReturnsGetThePredictedPose) {
  SimLog log = simulate(1, 7);
  log.scans.resize(40);
  // Scan 20 sees nothing: every range invalid.
  auto blind = std::make_shared<RangeScan2D>(*log.scans[20]);
  blind->set_ranges(std::vector<float>(181, 0.0f));
  log.scans[20] = blind;
  LidarSlam slam(test_options(false));
  SE2d odo;
  std::vector<SE2d> odometry;
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    const auto up = slam.add_scan(log.scans[k], log.scans[k]->timestamp,
                                  k ? std::optional<SE2d>(log.odometry_increments[k]) : std::nullopt);
    EXPECT_EQ(up.has_points, k != 20) << k;
    if (k == 20) {
      EXPECT_FALSE(up.node_added);
    }
  }
  EXPECT_EQ(slam.stats().scans_without_points, 1u);
  // Its pose is scan 19's moved by the odometry.
  const SE2d expected = slam.scan_local_pose(19) * log.odometry_increments[20];
  EXPECT_TRUE(slam.scan_local_pose(20).is_approx(expected, 1e-9));
  RangeScan2D broken = *log.scans[0];
  broken.valid.pop_back();  // flags and ranges of different sizes
  EXPECT_THROW(slam.add_scan(broken, Timestamp::from_seconds(1e3)), InvalidArgument);
  slam.finish();
  EXPECT_THROW(slam.add_scan(*log.scans[0], Timestamp::from_seconds(1e3)), InvalidArgument);
}

TEST(LidarSlamOptions, LoaderIsStrictAndConvertsDegrees) {
  const IniFile ini = IniFile::parse(
      "[frontend]\nmax_range = 25\nmotion_filter_angle = 2\n[submaps]\nscans_per_submap = 50\n"
      "[loop_closure]\nangular_search_window = 20\nmin_score = 0.6\n[backend]\nrotation_sigma = 0.2\n",
      "lidar.ini");
  const LidarSlamOptions o = load_lidar_slam_options(ini);
  EXPECT_DOUBLE_EQ(o.frontend.scan.max_range, 25.0);
  EXPECT_NEAR(o.frontend.motion_filter_angle, 2 * kDeg, 1e-15);
  EXPECT_EQ(o.submaps.scans_per_submap, 50);
  EXPECT_NEAR(o.loop_closure.window.angular, 20 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(o.loop_closure.min_score, 0.6);
  EXPECT_NEAR(o.backend.rotation_sigma, 0.2 * kDeg, 1e-15);
  const auto fails = [](const char* text, const char* key) {
    try {
      (void)load_lidar_slam_options(IniFile::parse(text, "bad.ini"));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  fails("[frontend]\nmax_rnage = 25\n", "max_rnage");
  fails("[loop_closure]\nmin_score = 0.95\n", "min_score");
  fails("[submaps]\nscans_per_submap = 2.5\n", "scans_per_submap");
  fails("[frontend]\nmin_range = 5\nmax_range = 4\n", "max_range");
  fails("[submaps]\nhit_probability = 0.5\n", "hit_probability");
  fails("[backend]\nscan_window = 21\n", "scan_window");
  fails("[backend]\nnum_threads = -1\n", "num_threads");
  const LidarSlamOptions w =
      load_lidar_slam_options(IniFile::parse("[backend]\nscan_window = 4\nscan_window_rotation_sigma = 0.2\n"
                                             "num_threads = 0\n", "w.ini"));
  EXPECT_EQ(w.backend.scan_window, 4);
  EXPECT_NEAR(w.backend.scan_window_rotation_sigma, 0.2 * kDeg, 1e-15);
  EXPECT_EQ(w.backend.num_threads, 0);
}

// --- Runs over files -------------------------------------------------------

std::string temp_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "rove_lidar_slam_test";
  std::filesystem::create_directories(dir);
  const std::string p = (dir / name).string();
  std::ofstream(p) << text;
  return p;
}

std::string flaser(double t, double x, const std::vector<double>& ranges) {
  std::string s = fmt::format("FLASER {}", ranges.size());
  for (const double r : ranges) s += fmt::format(" {}", r);
  return s + fmt::format(" {} 0 0 {} 0 0 {} host {}\n", x, x, t, t);
}

template <typename F>
std::string selection_error(F&& f) {
  try {
    f();
  } catch (const SelectionError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(LidarSlamRun, RefusesLogsWithoutEnoughScans) {
  LidarSlam slam(test_options(false));
  const std::string odom = temp_file("odom_only.clf", "ODOM 0 0 0 0 0 0 1.0 host 1.0\nODOM 0.5 0 0 0 0 0 2.0 host 2.0\n");
  // A CARMEN log of ODOM lines gives no entry in layout #1: the reader says so.
  EXPECT_THROW(run_lidar_slam(slam, odom), ParseError);
  std::vector<double> wall(180, 3.0);
  const std::string one = temp_file("one_scan.clf", flaser(1.0, 0.0, wall));
  LidarSlam s1(test_options(false));
  EXPECT_NE(selection_error([&] { run_lidar_slam(s1, one); }).find("a single 2D scan"), std::string::npos);
  const std::string blind = temp_file(
      "blind.clf", flaser(1.0, 0.0, std::vector<double>(180, 81.9)) +
                       flaser(1.2, 0.1, std::vector<double>(180, 0.0)) +
                       flaser(1.4, 0.2, std::vector<double>(180, 81.9)));
  LidarSlam s2(test_options(false));
  const std::string msg = selection_error([&] { run_lidar_slam(s2, blind); });
  EXPECT_NE(msg.find("none of the 3 scans"), std::string::npos) << msg;
  EXPECT_NE(msg.find("valid return"), std::string::npos) << msg;
}

TEST(LidarSlamRun, TelecomRawlogWithItsOdometry) {
  LidarSlam slam(LidarSlamOptions{});
  LidarSlamRunOptions ro;
  ro.max_scans = 120;
  const LidarSlamRunResult r = run_lidar_slam(
      slam, test_data::bundled_file("mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"), ro);
  EXPECT_EQ(slam.num_scans(), 120u);
  EXPECT_EQ(r.odometry.size(), 120u);
  EXPECT_EQ(r.format, RawlogFormat::Mrpt);
  EXPECT_EQ(r.other_scans, 0u);
  EXPECT_EQ(slam.stats().matched, 119u);
  EXPECT_GT(slam.stats().match_score_sum / 119.0, 0.35);
  const OccupancyGrid grid = build_lidar_slam_map(slam);
  EXPECT_GT(grid.size_x(), 100u);
  // The scans' poses follow the odometry's shape: the path length agrees
  // within 10 %.
  double est = 0, odo = 0;
  for (std::size_t i = 1; i < slam.num_scans(); ++i) {
    est += (slam.scan_pose(i).translation() - slam.scan_pose(i - 1).translation()).norm();
    odo += (r.odometry[i].translation() - r.odometry[i - 1].translation()).norm();
  }
  EXPECT_NEAR(est, odo, 0.1 * odo);
}

}  // namespace
}  // namespace rove
