// Monte-Carlo localization on a synthetic room whose truth is known exactly
// (mcl_test_world.h): tracking, global localization, recovery from a
// kidnapping, independence from the thread count, and bad input.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "mcl_test_world.h"
#include "rove/core/error.h"
#include "rove/maps/landmark_map.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/slam/mcl.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double position_error(const SE2d& a, const SE2d& b) {
  return (a.translation() - b.translation()).norm();
}
double heading_error(const SE2d& a, const SE2d& b) { return std::abs((a.inverse() * b).angle()); }

MclOptions tracking_options(int threads = 1) {
  MclOptions o;
  o.pf.adaptive_sample_size = false;
  o.init.mode = ParticleInitMode::AroundPose;
  o.init.count = 2000;
  o.init.pose = test::room_path().front();
  o.init.std_xy = 0.3;
  o.init.std_yaw = 10 * kDeg;
  o.num_threads = threads;
  o.seed = 7;
  return o;
}

// Runs `mcl` along `path` (from path[0], the first step observes path[1]).
// Returns the worst position error over the steps from `settle` on.
double run_along(MonteCarloLocalization& mcl, const std::vector<SE2d>& path, std::size_t settle,
                 std::uint64_t noise_seed = 1) {
  Rng rng(noise_seed);
  double worst = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const RobotMovement2D m = test::movement(path[k - 1], path[k]);
    const MclStepResult r = mcl.step(&m, test::frame_of(test::simulate_scan(path[k], rng)));
    if (k >= settle) worst = std::max(worst, position_error(r.estimate.mean, path[k]));
  }
  return worst;
}

TEST(MclEstimate, CircularMeanAndCovarianceAcrossPi) {
  // Two equally weighted particles at ±179° and 1 m apart in x: the mean
  // heading is 180°, not 0°, and the heading spread is 1°.
  ParticleSet<SE2d> p = ParticleSet<SE2d>::uniform(
      {SE2d(0.0, 0.0, 179 * kDeg), SE2d(1.0, 0.0, -179 * kDeg)});
  const MclEstimate e = estimate_of(p);
  EXPECT_NEAR(std::abs(e.mean.angle()), std::numbers::pi, 1e-12);
  EXPECT_NEAR(e.mean.translation().x(), 0.5, 1e-12);
  EXPECT_NEAR(e.heading_std, 1 * kDeg, 1e-9);
  EXPECT_NEAR(e.position_std, 0.5, 1e-12);
  // World covariance: var x = 0.25; in the tangent at heading 180° the x
  // axis is reversed but the variance is the same.
  const Eigen::Matrix3d W = e.world_covariance();
  EXPECT_NEAR(W(0, 0), 0.25, 1e-12);
  EXPECT_NEAR(e.covariance(0, 0), 0.25, 1e-12);
  EXPECT_NEAR(W(0, 2), -e.covariance(0, 2), 1e-12);
}

TEST(MclEstimate, WeightsCount) {
  ParticleSet<SE2d> p;
  p.states = {SE2d(0.0, 0.0, 0.0), SE2d(4.0, 0.0, 0.0)};
  p.log_weights = {std::log(0.75), std::log(0.25)};
  EXPECT_NEAR(estimate_of(p).mean.translation().x(), 1.0, 1e-12);
  p.log_weights = {0.0, -std::numeric_limits<double>::infinity()};
  EXPECT_NEAR(estimate_of(p).mean.translation().x(), 0.0, 1e-12);
  EXPECT_NEAR(estimate_of(p).position_std, 0.0, 1e-12);
}

TEST(MonteCarloLocalization, TracksTheRobot) {
  const MultiMetricMap map = test::room_map();
  MonteCarloLocalization mcl(map, tracking_options());
  mcl.initialize();
  const auto path = test::room_path();
  EXPECT_LT(run_along(mcl, path, 5), 0.10);
  const MclEstimate e = mcl.estimate();
  EXPECT_LT(heading_error(e.mean, path.back()), 3 * kDeg);
  EXPECT_LT(e.position_std, 0.1);
}

// NaN ranges flagged valid are skipped: with every other ray NaN the robot
// is still tracked; with every ray NaN the scan explains nothing, the step
// only moves the particles, and nothing throws.
TEST(MonteCarloLocalization, NanRangesAreSkipped) {
  const MultiMetricMap map = test::room_map();
  MonteCarloLocalization mcl(map, tracking_options());
  mcl.initialize();
  const auto path = test::room_path();
  Rng rng(3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t k = 1; k < path.size(); ++k) {
    auto scan = test::simulate_scan(path[k], rng);
    const bool all = k % 10 == 0;
    for (std::size_t i = 0; i < scan->ranges.size(); ++i) {
      if (all || i % 2 == 0) scan->ranges[i] = nan;  // valid[i] stays true
    }
    const RobotMovement2D m = test::movement(path[k - 1], path[k]);
    const MclStepResult r = mcl.step(&m, test::frame_of(scan));
    EXPECT_NE(r.filter.termination, ParticleFilterTermination::Degenerate) << k;
    if (k >= 5) {
      EXPECT_LT(position_error(r.estimate.mean, path[k]), 0.15) << k;
    }
  }
}

TEST(MonteCarloLocalization, ResultDependsOnTheSeedNotOnTheThreads) {
  const MultiMetricMap map = test::room_map();
  const auto path = test::room_path();
  const auto run = [&](int threads, std::uint64_t seed, bool kld) {
    MclOptions o = tracking_options(threads);
    o.seed = seed;
    o.pf.adaptive_sample_size = kld;
    o.kld.min_sample_size = 500;
    o.kld.max_sample_size = 5000;
    o.init.count = 3000;
    MonteCarloLocalization mcl(map, o);
    mcl.initialize();
    std::vector<SE2d> sub(path.begin(), path.begin() + 12);
    run_along(mcl, sub, 1);
    return mcl.particles();
  };
  for (const bool kld : {false, true}) {
    const ParticleSet<SE2d> a = run(1, 3, kld), b = run(3, 3, kld), c = run(1, 4, kld);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a.states[i].translation(), b.states[i].translation()) << i;
      ASSERT_EQ(a.states[i].angle(), b.states[i].angle()) << i;
      ASSERT_EQ(a.log_weights[i], b.log_weights[i]) << i;
    }
    // Another seed, other particles.
    bool differ = a.size() != c.size();
    for (std::size_t i = 0; !differ && i < a.size(); ++i) {
      differ = a.states[i].translation() != c.states[i].translation();
    }
    EXPECT_TRUE(differ) << "kld " << kld;
  }
}

TEST(MonteCarloLocalization, GlobalLocalizationFromFreeSpace) {
  const MultiMetricMap map = test::room_map();
  const auto path = test::room_path();
  int converged = 0;
  const int seeds = 5;
  for (int seed = 0; seed < seeds; ++seed) {
    MclOptions o;
    o.init.mode = ParticleInitMode::FreeSpace;
    o.init.count = 20000;
    o.pf.adaptive_sample_size = true;
    o.kld.max_sample_size = 20000;
    o.kld.min_sample_size = 300;
    o.seed = static_cast<std::uint64_t>(seed);
    MonteCarloLocalization mcl(map, o);
    mcl.initialize();
    run_along(mcl, path, path.size(), static_cast<std::uint64_t>(seed) + 10);
    const MclEstimate e = mcl.estimate();
    if (position_error(e.mean, path.back()) < 0.15 && heading_error(e.mean, path.back()) < 3 * kDeg) {
      ++converged;
    }
  }
  EXPECT_EQ(converged, seeds);
}

// The robot is carried from the east leg of the path to the west leg (the
// odometry says it moved 0.25 m): with augmented MCL the filter finds it
// again; without, it stays where the odometry says.
TEST(MonteCarloLocalization, RecoversFromAKidnapping) {
  const MultiMetricMap map = test::room_map();
  const auto path = test::room_path();
  std::vector<SE2d> before(path.begin(), path.begin() + 15);  // east leg, x ≤ 4.5
  const std::size_t west = path.size() - 20;                  // west leg, y = 6.8
  std::vector<SE2d> after(path.begin() + static_cast<std::ptrdiff_t>(west), path.end());
  const auto run = [&](bool recovery, std::size_t& recovered_at) {
    MclOptions o = tracking_options();
    o.pf.adaptive_sample_size = true;
    o.kld.min_sample_size = 500;
    o.kld.max_sample_size = 20000;
    if (recovery) {
      o.recovery.alpha_slow = 0.02;
      o.recovery.alpha_fast = 0.3;
    }
    MonteCarloLocalization mcl(map, o);
    mcl.initialize();
    EXPECT_LT(run_along(mcl, before, 5), 0.1);
    Rng rng(99);
    recovered_at = 0;
    for (std::size_t k = 0; k < after.size(); ++k) {
      // The odometry reports the last step of the east leg again.
      const RobotMovement2D m = test::movement(before[before.size() - 2], before.back());
      const MclStepResult r = mcl.step(&m, test::frame_of(test::simulate_scan(after[k], rng)));
      const bool ok = position_error(r.estimate.mean, after[k]) < 0.25;
      if (ok && recovered_at == 0) recovered_at = k + 1;
      if (!ok) recovered_at = 0;
    }
    return position_error(mcl.estimate().mean, after.back());
  };
  std::size_t with = 0, without = 0;
  EXPECT_LT(run(true, with), 0.1);
  EXPECT_GT(with, 0u);
  EXPECT_LE(with, 10u) << "back within 0.25 m (and staying) only after " << with << " steps";
  EXPECT_GT(run(false, without), 1.0);
}

TEST(MonteCarloLocalization, RejectsBadOptions) {
  const MultiMetricMap map = test::room_map();
  MclOptions o = tracking_options();
  o.init.count = 0;
  EXPECT_THROW(MonteCarloLocalization(map, o), InvalidArgument);
  o = tracking_options();
  o.init.mode = ParticleInitMode::FreeSpaceInBox;
  o.init.min_x = 50;
  o.init.max_x = 60;  // no cell there
  EXPECT_THROW(MonteCarloLocalization(map, o), InvalidArgument);
  o = tracking_options();
  o.recovery.alpha_slow = 0.2;
  o.recovery.alpha_fast = 0.1;
  EXPECT_THROW(MonteCarloLocalization(map, o), InvalidArgument);
  o = tracking_options();
  o.init.mode = ParticleInitMode::FreeSpace;
  EXPECT_THROW(MonteCarloLocalization(MultiMetricMap(), o), InvalidArgument);  // no grid
}

// Range-only localization against known beacons; a NaN range is skipped,
// and a step whose every range is impossible is flagged, not a crash.
TEST(MonteCarloLocalization, BeaconRangesWithBadReadings) {
  LandmarkMapCreationOptions creation;
  const std::vector<Eigen::Vector3d> beacons{{0, 0, 0}, {10, 0, 0}, {0, 8, 0}, {10, 8, 0}};
  for (std::size_t i = 0; i < beacons.size(); ++i) {
    Landmark l;
    l.id = static_cast<std::int32_t>(i);
    l.position.mean = beacons[i];
    creation.initial.push_back(l);
  }
  LandmarkMapLikelihoodOptions lik;
  lik.beacon_ranges_std = 0.1;
  MultiMetricMap map;
  map.add(std::make_unique<LandmarkMap>(creation, LandmarkMapInsertOptions{}, lik));
  MclOptions o;
  o.init.mode = ParticleInitMode::UniformInBox;
  o.init.count = 5000;
  o.init.min_x = 0;
  o.init.max_x = 10;
  o.init.min_y = 0;
  o.init.max_y = 8;
  o.pf.adaptive_sample_size = false;
  MonteCarloLocalization mcl(map, o);
  mcl.initialize();
  const SE2d truth(4.0, 3.0, 0.5);
  const auto ranges = [&](float bad) {
    auto obs = std::make_shared<BeaconRanges>();
    obs->max_sensor_distance = 50.0f;
    for (std::size_t i = 0; i < beacons.size(); ++i) {
      BeaconRange r;
      r.beacon_id = static_cast<std::int32_t>(i);
      r.range = static_cast<float>((beacons[i].head<2>() - truth.translation()).norm());
      if (i == 1) r.range = bad;
      obs->readings.push_back(r);
    }
    return obs;
  };
  MclStepResult r;
  for (int k = 0; k < 8; ++k) {
    r = mcl.step(nullptr, test::frame_of(ranges(std::numeric_limits<float>::quiet_NaN())));
  }
  EXPECT_EQ(r.filter.termination, ParticleFilterTermination::Updated);
  EXPECT_LT(position_error(r.estimate.mean, truth), 0.1);
  ASSERT_TRUE(r.range_residual.has_value());
  EXPECT_LT(*r.range_residual, 3.0);
  // An infinite range explains no particle: the step is flagged Degenerate
  // and the particles keep their weights.
  r = mcl.step(nullptr, test::frame_of(ranges(std::numeric_limits<float>::infinity())));
  EXPECT_EQ(r.filter.termination, ParticleFilterTermination::Degenerate);
  EXPECT_LT(position_error(r.estimate.mean, truth), 0.1);
}

}  // namespace
}  // namespace rove
