#include "rove/maps/beacon_map.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {
namespace {

/// A robot driving a circle of radius 3 m around the origin, ranging to
/// `beacons` with Gaussian noise of `sigma`.
struct RangeSim {
  std::vector<std::pair<int, Eigen::Vector3d>> beacons;
  double sigma = 0.02;
  std::mt19937_64 rng{42};

  Pose3 pose(int k) const {
    const double a = 0.1 * k;
    return Pose3(3.0 * std::cos(a), 3.0 * std::sin(a), 0.0, a + kPi / 2, 0.0, 0.0);
  }
  BeaconRanges observe(const Pose3& T) {
    BeaconRanges o;
    o.min_sensor_distance = 0.1f;
    o.max_sensor_distance = 20.0f;
    std::normal_distribution<double> n(0.0, sigma);
    for (const auto& [id, p] : beacons) {
      BeaconRange r;
      r.beacon_id = id;
      r.position_on_robot = Eigen::Vector3d(0.1, 0.0, 0.0);
      const Eigen::Vector3d s = T.rotation() * r.position_on_robot + T.translation();
      r.range = static_cast<float>((p - s).norm() + n(rng));
      o.readings.push_back(r);
    }
    return o;
  }
};

TEST(BeaconRing, MatchesMrptGeometry) {
  BeaconMapInsertOptions io;
  io.sog_max_dist_between_gaussians = 1.0;
  io.sog_separation_constant = 3.0;
  BeaconMapLikelihoodOptions lo;
  lo.range_std = 0.05;
  const Eigen::Vector3d sensor(1.0, -2.0, 0.5);
  const auto modes = beacon_ring_modes(3.0, sensor, io, lo);
  // B = max(floor(2π·3 / 1) + 1, 30) = 30 modes, one elevation (2D).
  ASSERT_EQ(modes.size(), 30u);
  const double step = 2 * kPi / 30;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const auto& g = modes[i].gaussian;
    const Eigen::Vector3d d = g.mean - sensor;
    EXPECT_NEAR(d.norm(), 3.0, 1e-12);
    EXPECT_NEAR(std::atan2(d.y(), d.x()), wrap_to_pi(static_cast<double>(i) * step), 1e-12);
    // Radial variance rangeStd², tangential (step·R/3)², z zero in 2D.
    const Eigen::Vector3d u = d.normalized();
    EXPECT_NEAR(u.dot(g.covariance * u), 0.05 * 0.05, 1e-12);
    const Eigen::Vector3d t(-u.y(), u.x(), 0.0);
    EXPECT_NEAR(t.dot(g.covariance * t), std::pow(step * 3.0 / 3.0, 2), 1e-12);
    EXPECT_EQ(g.covariance.row(2).norm(), 0.0);
    EXPECT_EQ(modes[i].log_weight, 0.0);
  }
  // Larger ring: spacing bounded by SOG_maxDistBetweenGaussians, even count.
  const auto big = beacon_ring_modes(10.0, sensor, io, lo);
  EXPECT_EQ(big.size(), 64u);  // floor(62.83) + 1 = 63 → 64
  // 3D: elevations from -90 to 90 degrees.
  io.min_elevation_deg = -90;
  io.max_elevation_deg = 90;
  const auto sphere = beacon_ring_modes(3.0, sensor, io, lo);
  EXPECT_GT(sphere.size(), 30u * 10);
  for (const auto& m : sphere) EXPECT_NEAR((m.gaussian.mean - sensor).norm(), 3.0, 1e-9);
  EXPECT_THROW(beacon_ring_modes(0.0, sensor, io, lo), InvalidArgument);
  EXPECT_THROW(beacon_ring_modes(std::nan(""), sensor, io, lo), InvalidArgument);
}

void expect_converges(bool monte_carlo) {
  RangeSim sim;
  sim.beacons = {{1, {0.5, 0.8, 0.0}}, {7, {-4.0, 2.0, 0.0}}, {9, {2.0, -5.0, 0.0}}};
  BeaconMapInsertOptions io;
  io.insert_as_monte_carlo = monte_carlo;
  io.mc_samples_per_meter = 400;
  io.mc_max_std_to_gauss = 0.07;
  io.mc_threshold_negligible = 30;
  io.sog_threshold_negligible = 40;
  io.sog_max_dist_between_gaussians = 0.6;
  io.sog_separation_constant = 2;
  BeaconMapLikelihoodOptions lo;
  lo.range_std = 0.05;
  BeaconMap map(io, lo);
  EXPECT_TRUE(map.empty());
  for (int k = 0; k < 60; ++k) {
    const Pose3 T = sim.pose(k);
    ASSERT_TRUE(map.insert(sim.observe(T), T));
  }
  ASSERT_EQ(map.beacons().size(), 3u);
  for (const auto& [id, truth] : sim.beacons) {
    const Beacon* b = map.find(id);
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->kind, BeaconPdfKind::Gaussian) << "beacon " << id;
    const PointGaussian3 g = b->moments();
    EXPECT_LT((g.mean - truth).norm(), 0.05) << "beacon " << id << " at " << g.mean.transpose();
    EXPECT_NEAR(g.mean.z(), 0.0, 1e-9);  // 2D map stays in the plane
  }
  // The likelihood peaks near the true pose.
  const Pose3 T = sim.pose(61);
  const BeaconRanges z = sim.observe(T);
  const double at_truth = map.log_likelihood(z, T);
  const double off = map.log_likelihood(z, Pose3(T.x() + 0.3, T.y(), 0, 0, 0, 0) + Pose3(0, 0, 0, T.yaw(), 0, 0));
  EXPECT_GT(at_truth, off + 5.0);
}

TEST(BeaconMap, SumOfGaussiansConvergesToTruth) { expect_converges(false); }
TEST(BeaconMap, MonteCarloConvergesToTruth) { expect_converges(true); }

TEST(BeaconMap, LikelihoodOfUnknownBeaconIsUniform) {
  BeaconMap map;
  BeaconRanges o;
  o.min_sensor_distance = 1.0f;
  o.max_sensor_distance = 11.0f;
  o.readings.push_back({5, 3.0f, Eigen::Vector3d::Zero()});
  o.readings.push_back({6, 4.0f, Eigen::Vector3d::Zero()});
  EXPECT_NEAR(map.log_likelihood(o, Pose3()), 2 * std::log(0.1), 1e-12);
  EXPECT_TRUE(map.can_compute_likelihood(o));
  RangeScan2D scan;
  EXPECT_FALSE(map.can_compute_likelihood(scan));
  EXPECT_FALSE(map.insert(scan, Pose3()));
  EXPECT_EQ(map.log_likelihood(scan, Pose3()), 0.0);
}

TEST(BeaconMap, GaussianLikelihoodIsTheInnovationDensity) {
  BeaconMap map({}, BeaconMapLikelihoodOptions{0.1});
  Beacon b;
  b.id = 3;
  b.kind = BeaconPdfKind::Gaussian;
  b.gaussian.mean = Eigen::Vector3d(4, 0, 0);
  b.gaussian.covariance = Eigen::Vector3d(0.04, 0.09, 0).asDiagonal();
  map.add(b);
  BeaconRanges o;
  o.readings.push_back({3, 3.5f, Eigen::Vector3d::Zero()});
  // H = (1, 0, 0): var_z = 0.04 + 0.01; residual 3.5 - 4 = -0.5.
  EXPECT_NEAR(map.log_likelihood(o, Pose3()), -0.5 * 0.25 / 0.05, 1e-6);
  // An EKF update moves the mean towards the range and shrinks the variance.
  ASSERT_TRUE(map.insert(o, Pose3()));
  const auto& g = map.find(3)->gaussian;
  EXPECT_NEAR(g.mean.x(), 4.0 + 0.04 / 0.05 * (-0.5), 1e-6);
  EXPECT_NEAR(g.covariance(0, 0), 0.04 - 0.04 * 0.04 / 0.05, 1e-9);
  EXPECT_NEAR(g.covariance(1, 1), 0.09, 1e-12);
}

TEST(BeaconMap, IgnoresNonPositiveRanges) {
  BeaconMap map;
  BeaconRanges o;
  o.readings.push_back({1, 0.0f, Eigen::Vector3d::Zero()});
  o.readings.push_back({2, -1.0f, Eigen::Vector3d::Zero()});
  o.readings.push_back({3, std::nanf(""), Eigen::Vector3d::Zero()});
  EXPECT_TRUE(map.insert(o, Pose3()));
  EXPECT_TRUE(map.empty());
}

TEST(BeaconMapOptions, LoadFromMrptSection) {
  const auto ini = IniFile::parse(
      "[m_insertOpts]\ninsertAsMonteCarlo=0\nmaxElevation_deg=0\nminElevation_deg=0\n"
      "MC_numSamplesPerMeter=1000\nMC_maxStdToGauss=0.07\nMC_thresholdNegligible=30\n"
      "SOG_thresholdNegligible=40\nSOG_maxDistBetweenGaussians=0.60\nSOG_separationConstant=2\n"
      "[m_likelihoodOpts]\nrangeStd=0.02\n",
      "test.ini");
  ConfigSection is(ini, "m_insertOpts"), ls(ini, "m_likelihoodOpts");
  const auto io = BeaconMapInsertOptions::from_config(is);
  const auto lo = BeaconMapLikelihoodOptions::from_config(ls);
  is.check_all_read();
  ls.check_all_read();
  EXPECT_FALSE(io.insert_as_monte_carlo);
  EXPECT_EQ(io.mc_samples_per_meter, 1000u);
  EXPECT_DOUBLE_EQ(io.mc_max_std_to_gauss, 0.07);
  EXPECT_DOUBLE_EQ(io.sog_max_dist_between_gaussians, 0.6);
  EXPECT_DOUBLE_EQ(lo.range_std, 0.02);

  const auto bad = IniFile::parse("[s]\nminElevation_deg=10\nmaxElevation_deg=5\n", "bad.ini");
  try {
    (void)BeaconMapInsertOptions::from_config(ConfigSection(bad, "s"));
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "minElevation_deg");
    EXPECT_EQ(e.file(), "bad.ini");
  }
  const auto typo = IniFile::parse("[s]\nrangeStdd=0.1\n", "typo.ini");
  ConfigSection ts(typo, "s");
  (void)BeaconMapLikelihoodOptions::from_config(ts);
  try {
    ts.check_all_read();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "rangeStdd");
    EXPECT_EQ(e.section(), "s");
  }
}

}  // namespace
}  // namespace rove
