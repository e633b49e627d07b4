#include "rove/nav/simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <variant>

#include "nav_test_worlds.h"
#include "rove/core/error.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"

namespace rove {
namespace {

namespace fs = std::filesystem;

SimulatorOptions quiet() {
  SimulatorOptions o;
  o.lidar.range_sigma = 0;
  o.odometry_sigma_xy = o.odometry_sigma_phi = o.odometry_sigma_phi_per_m = 0;
  return o;
}

TEST(Simulator, AcceleratesWithinTheLimitsAndIntegratesTheTwist) {
  const NavigationGrid g = nav_test::empty_room(200, 200, 0.05);
  SimulatorOptions o = quiet();
  o.limits.max_acc_v = 1.0;
  o.limits.max_v = 0.8;
  Simulator sim(g, SE2d(2, 2, 0), o);
  double x = 2;
  for (int k = 1; k <= 12; ++k) {
    const SimulatorStep s = sim.step({5.0, 3.0, 0.0});  // beyond the limits; vy ignored
    const double v = std::min(0.1 * k, 0.8);
    EXPECT_NEAR(s.velocity.vx, v, 1e-12);
    EXPECT_EQ(s.velocity.vy, 0.0);
    x += v * 0.1;
    EXPECT_NEAR(s.T_map_robot.translation().x(), x, 1e-9);
    EXPECT_NEAR(s.T_map_robot.translation().y(), 2.0, 1e-12);
    EXPECT_FALSE(s.collided);
  }
  // An arc: constant v and ω from rest are reached, then the pose follows
  // the circle of radius v/ω.
  Simulator arc(g, SE2d(5, 5, 0), o);
  for (int k = 0; k < 10; ++k) arc.step({0.5, 0, 0.5});
  const SE2d at = arc.pose();
  for (int k = 0; k < 20; ++k) arc.step({0.5, 0, 0.5});
  const SE2d expected = at * SE2d::exp(SE2d::Tangent(0.5 * 2.0, 0, 0.5 * 2.0));
  EXPECT_TRUE(arc.pose().is_approx(expected, 1e-9));
  EXPECT_NEAR(arc.time(), 3.0, 1e-12);
  // Odometry without noise is the ground truth.
  EXPECT_NEAR(arc.odometry().x(), (SE2d(5, 5, 0).inverse() * arc.pose()).translation().x(), 1e-9);
  EXPECT_NEAR(arc.odometry().phi(), arc.pose().angle(), 1e-9);
}

TEST(Simulator, HolonomicRobotMovesSideways) {
  const NavigationGrid g = nav_test::empty_room(200, 200, 0.05);
  SimulatorOptions o = quiet();
  o.kinematics = RobotKinematics::Holonomic;
  o.limits.max_acc_v = 100;
  Simulator sim(g, SE2d(5, 5, std::numbers::pi / 2), o);
  for (int k = 0; k < 10; ++k) sim.step({0.0, 0.6, 0.0});
  // Left of a robot facing +y is −x.
  EXPECT_NEAR(sim.pose().translation().x(), 5 - 0.6, 1e-9);
  EXPECT_NEAR(sim.pose().translation().y(), 5, 1e-9);
  // The planar speed is limited as a whole.
  sim.step({3.0, 4.0, 0.0});
  EXPECT_NEAR(std::hypot(sim.velocity().vx, sim.velocity().vy), 1.0, 1e-12);
}

TEST(Simulator, StopsAtAWallWithoutTouchingIt) {
  const NavigationGrid g = nav_test::wall_with_gap(100, 60, 0.05, 70, 0, 0);  // a wall at x = 3.5 m
  SimulatorOptions o = quiet();
  o.limits.max_acc_v = 10;
  Simulator sim(g, SE2d(1.0, 1.5, 0), o);
  bool hit = false;
  for (int k = 0; k < 60 && !hit; ++k) {
    hit = sim.step({1.0, 0, 0}).collided;
    EXPECT_GE(g.distance_to_obstacle(sim.pose().translation(), 1.0), o.robot_radius);
  }
  EXPECT_TRUE(hit);
  EXPECT_EQ(sim.collisions(), 1);
  EXPECT_NEAR(sim.pose().translation().x(), 3.5 - 0.3, 0.021);
  EXPECT_LT(sim.clearance(), 0.021);
  EXPECT_EQ(sim.velocity().vx, 0.0);
}

TEST(Simulator, LidarRangesAreTheDistancesToTheWalls) {
  // A 6 m × 4 m room (the outside of the grid gives no echo, so the walls
  // are obstacle cells at its border).
  const std::uint32_t w = 120, h = 80;
  std::vector<std::uint8_t> mask(std::size_t{w} * h, 0);
  for (std::uint32_t x = 0; x < w; ++x) mask[x] = mask[x + (h - 1) * std::size_t{w}] = 1;
  for (std::uint32_t y = 0; y < h; ++y) mask[y * std::size_t{w}] = mask[w - 1 + y * std::size_t{w}] = 1;
  const NavigationGrid g = NavigationGrid::from_mask(w, h, 0.0, 0.0, 0.05, mask);
  SimulatorOptions o = quiet();
  o.lidar.T_robot_sensor = SE2d(0.1, 0.0, 0.0);
  Simulator sim(g, SE2d(2.0, 1.5, 0.3), o);
  const RangeScan2D scan = sim.scan();
  ASSERT_EQ(scan.size(), 360u);
  const SE2d s = sim.pose() * o.lidar.T_robot_sensor;
  // The free space is [0.05, 5.95] × [0.05, 3.95].
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double a = s.angle() + scan.ray_angle(i);
    const Eigen::Vector2d d(std::cos(a), std::sin(a)), p = s.translation();
    double t = 1e9;
    if (d.x() > 1e-12) t = std::min(t, (5.95 - p.x()) / d.x());
    if (d.x() < -1e-12) t = std::min(t, (0.05 - p.x()) / d.x());
    if (d.y() > 1e-12) t = std::min(t, (3.95 - p.y()) / d.y());
    if (d.y() < -1e-12) t = std::min(t, (0.05 - p.y()) / d.y());
    ASSERT_TRUE(scan.valid[i]) << i;
    EXPECT_NEAR(scan.ranges[i], t, 1e-5) << i;
  }
  // With noise the ranges scatter around the truth.
  SimulatorOptions noisy = o;
  noisy.lidar.range_sigma = 0.05;
  Simulator sim2(g, SE2d(2.0, 1.5, 0.3), noisy);
  const RangeScan2D n = sim2.scan();
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const double e = n.ranges[i] - scan.ranges[i];
    sum += e;
    sum2 += e * e;
  }
  EXPECT_NEAR(sum / n.size(), 0.0, 0.015);
  EXPECT_NEAR(std::sqrt(sum2 / n.size()), 0.05, 0.01);
}

TEST(Simulator, NoEchoBeyondTheRangeOrTheMap) {
  const NavigationGrid g = nav_test::empty_room(400, 400, 0.05);
  SimulatorOptions o = quiet();
  o.lidar.max_range = 5;
  Simulator sim(g, SE2d(10, 10, 0), o);
  const RangeScan2D scan = sim.scan();
  for (std::size_t i = 0; i < scan.size(); ++i) EXPECT_FALSE(scan.valid[i]);
  EXPECT_TRUE(std::isinf(g.cast_ray(Eigen::Vector2d(10, 10), 0.0, 5.0)));
}

TEST(Simulator, BadOptionsAndStartsAreRefused) {
  const NavigationGrid g = nav_test::wall_with_gap(100, 60, 0.05, 70, 0, 0);
  const auto make = [&](auto change) {
    SimulatorOptions o;
    change(o);
    return Simulator(g, SE2d(1.0, 1.5, 0), o);
  };
  EXPECT_THROW(make([](auto& o) { o.limits.max_v = 0; }), InvalidArgument);
  EXPECT_THROW(make([](auto& o) { o.limits.max_omega = -1; }), InvalidArgument);
  EXPECT_THROW(make([](auto& o) { o.limits.max_acc_v = 0; }), InvalidArgument);
  EXPECT_THROW(make([](auto& o) { o.limits.max_acc_omega = std::nan(""); }), InvalidArgument);
  EXPECT_THROW(make([](auto& o) { o.dt = 0; }), InvalidArgument);
  EXPECT_THROW(make([](auto& o) { o.robot_radius = -0.1; }), InvalidArgument);
  EXPECT_THROW(make([](auto& o) { o.lidar.rays = 1; }), InvalidArgument);
  EXPECT_THROW(make([](auto& o) { o.lidar.range_sigma = -1; }), InvalidArgument);
  try {
    make([](auto& o) { o.limits.max_acc_v = 0; });
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(e.message().find("max_acc_v"), std::string::npos) << e.message();
  }
  EXPECT_THROW(Simulator(g, SE2d(3.4, 1.5, 0), SimulatorOptions{}), InvalidArgument);  // overlaps the wall
  Simulator sim(g, SE2d(1.0, 1.5, 0));
  EXPECT_THROW(sim.step({std::nan(""), 0, 0}), InvalidArgument);
}

TEST(Simulator, WritesARawlogTheReaderLoads) {
  const NavigationGrid g = nav_test::empty_room(200, 200, 0.05);
  const fs::path dir = fs::temp_directory_path() / "rove_nav_simulator_rawlog";
  fs::create_directories(dir);
  const std::string path = (dir / "run.rawlog").string();
  Simulator sim(g, SE2d(2, 2, 0));
  std::vector<Pose2> increments;
  {
    RoveRawlogWriter log(path);
    for (int k = 0; k < 5; ++k) {
      const SimulatorStep s = sim.step({0.5, 0, 0.2});
      increments.push_back(s.odometry_increment);
      write_simulation_step(log, s, sim.scan(), Timestamp::from_seconds(1000.0));
    }
    log.close();
  }
  const RoveRawlog r = load_rove_rawlog(path);
  ASSERT_EQ(r.entries.size(), 10u);
  for (int k = 0; k < 5; ++k) {
    const auto& a = std::get<std::shared_ptr<const ActionCollection>>(r.entries[2 * k]);
    const auto& f = std::get<std::shared_ptr<const SensoryFrame>>(r.entries[2 * k + 1]);
    const auto* m = dynamic_cast<const RobotMovement2D*>(a->actions.at(0).get());
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->odometry_increment.x(), increments[k].x());
    EXPECT_EQ(m->odometry_increment.phi(), increments[k].phi());
    const auto scans = f->find_all<RangeScan2D>();
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0]->size(), 360u);
    EXPECT_NEAR(scans[0]->timestamp.to_seconds(), 1000.0 + 0.1 * (k + 1), 1e-6);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rove
