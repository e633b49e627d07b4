#include "rove/maps/landmark_map.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/obs/beacon_ranges.h"

namespace rove {
namespace {

Eigen::Vector3d point_of(double r, double yaw, double pitch, const Pose3& T) {
  LandmarkMeasurement m;
  m.range = static_cast<float>(r);
  m.yaw = static_cast<float>(yaw);
  m.pitch = static_cast<float>(pitch);
  const Eigen::Vector3d p(r * std::cos(pitch) * std::cos(yaw), r * std::cos(pitch) * std::sin(yaw),
                          -r * std::sin(pitch));
  return T.rotation() * p + T.translation();
}

TEST(BearingRangeToPoint, CovarianceMatchesNumericJacobian) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose3 T(u(rng), u(rng), u(rng), 3 * u(rng), u(rng), u(rng));
    LandmarkMeasurement m;
    m.range = static_cast<float>(2 + 3 * (u(rng) + 1));
    m.yaw = static_cast<float>(3 * u(rng));
    m.pitch = static_cast<float>(u(rng));
    const Eigen::Matrix3d Sigma = Eigen::Vector3d(0.01, 0.002, 0.003).asDiagonal();
    const PointGaussian3 g = bearing_range_to_point(m, Sigma, T);
    EXPECT_LT((g.mean - point_of(m.range, m.yaw, m.pitch, T)).norm(), 1e-9);
    Eigen::Matrix3d J;
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      double v[3] = {m.range, m.yaw, m.pitch}, w[3] = {m.range, m.yaw, m.pitch};
      v[k] += h;
      w[k] -= h;
      J.col(k) = (point_of(v[0], v[1], v[2], T) - point_of(w[0], w[1], w[2], T)) / (2 * h);
    }
    const Eigen::Matrix3d C = J * Sigma * J.transpose();
    EXPECT_LT((g.covariance - C).norm(), 1e-7 * (1 + C.norm())) << "trial " << trial;
  }
}

BearingRange measure(const std::vector<std::pair<int, Eigen::Vector3d>>& lms, const Pose3& T,
                     std::mt19937_64& rng, bool with_ids) {
  BearingRange o;
  o.sensor_std_range = 0.05f;
  o.sensor_std_yaw = 0.01f;
  o.sensor_std_pitch = 0.01f;
  o.max_sensor_distance = 30.0f;
  std::normal_distribution<double> nr(0, 0.05), na(0, 0.01);
  for (const auto& [id, p_map] : lms) {
    const Eigen::Vector3d p = T.rotation().transpose() * (p_map - T.translation());
    LandmarkMeasurement m;
    m.landmark_id = with_ids ? id : -1;
    m.range = static_cast<float>(p.norm() + nr(rng));
    m.yaw = static_cast<float>(std::atan2(p.y(), p.x()) + na(rng));
    m.pitch = static_cast<float>(-std::atan2(p.z(), std::hypot(p.x(), p.y())) + na(rng));
    o.measurements.push_back(m);
  }
  return o;
}

void expect_mapping(bool with_ids) {
  const std::vector<std::pair<int, Eigen::Vector3d>> lms = {
      {0, {5, 1, 0.5}}, {1, {-3, 4, 1.0}}, {2, {0, -6, -0.5}}, {3, {8, 8, 2.0}}};
  std::mt19937_64 rng(11);
  // 160 measurements: a 99% gate would split about 1.6 of them off by
  // chance; these landmarks are meters apart, so a wide gate is safe.
  LandmarkMapInsertOptions io;
  io.association_gate_chi2 = 30.0;
  LandmarkMap map({}, io);
  for (int k = 0; k < 40; ++k) {
    const Pose3 T(0.1 * k, 0.05 * k, 0.0, 0.02 * k, 0.0, 0.0);
    ASSERT_TRUE(map.insert(measure(lms, T, rng, with_ids), T));
  }
  ASSERT_EQ(map.landmarks().size(), lms.size());
  for (const auto& [id, p] : lms) {
    const Landmark* best = nullptr;
    for (const auto& l : map.landmarks()) {
      if (best == nullptr || (l.position.mean - p).norm() < (best->position.mean - p).norm()) best = &l;
    }
    ASSERT_NE(best, nullptr);
    if (with_ids) {
      EXPECT_EQ(best->id, id);
    }
    EXPECT_LT((best->position.mean - p).norm(), 0.1) << "landmark " << id;
    EXPECT_EQ(best->times_seen, 40u);
  }
  // Likelihood is highest at the true pose.
  const Pose3 T(1.0, 0.5, 0.0, 0.3, 0.0, 0.0);
  const BearingRange z = measure(lms, T, rng, with_ids);
  const double at_truth = map.log_likelihood(z, T);
  EXPECT_GT(at_truth, map.log_likelihood(z, Pose3(1.2, 0.5, 0.0, 0.3, 0.0, 0.0)) + 2.0);
  EXPECT_GT(at_truth, map.log_likelihood(z, Pose3(1.0, 0.5, 0.0, 0.35, 0.0, 0.0)) + 2.0);
}

TEST(LandmarkMap, BuildsFromIdentifiedMeasurements) { expect_mapping(true); }
TEST(LandmarkMap, AssociatesMeasurementsWithoutIds) { expect_mapping(false); }

TEST(LandmarkMap, RejectsNonFiniteMeasurements) {
  LandmarkMap map;
  BearingRange o;
  LandmarkMeasurement m;
  m.range = std::nanf("");
  o.measurements.push_back(m);
  EXPECT_THROW(map.insert(o, Pose3()), InvalidArgument);
}

TEST(LandmarkMap, BeaconRangeLikelihoodAsMrpt) {
  // MRPT's ro-localization-demo declares its beacons in the creation
  // section; the range likelihood is -½((d̂-d)/σ)² per known beacon and the
  // uniform density over the sensor span for unknown ones.
  const auto ini = IniFile::parse(
      "[c]\nnBeacons=2\nbeacon_001_ID=0\nbeacon_001_X=3\nbeacon_001_Y=4\nbeacon_001_Z=0\n"
      "beacon_002_ID=1\nbeacon_002_X=-1\nbeacon_002_Y=0\nbeacon_002_Z=0\n"
      "[l]\nbeaconRangesStd=0.5\nalphaRatio=0.5\nbeaconMaxRange=20\n",
      "lm.ini");
  std::vector<IgnoredConfigKey> ignored;
  ConfigSection cs(ini, "c", &ignored), ls(ini, "l", &ignored);
  LandmarkMap map(LandmarkMapCreationOptions::from_config(cs), {}, LandmarkMapLikelihoodOptions::from_config(ls));
  cs.check_all_read();
  ls.check_all_read();
  EXPECT_EQ(ignored.size(), 2u);  // alphaRatio, beaconMaxRange: not read by MRPT 2.x
  ASSERT_EQ(map.landmarks().size(), 2u);
  BeaconRanges o;
  o.min_sensor_distance = 0;
  o.max_sensor_distance = 10;
  o.readings.push_back({0, 5.5f, Eigen::Vector3d::Zero()});
  o.readings.push_back({1, 1.0f, Eigen::Vector3d::Zero()});
  o.readings.push_back({9, 1.0f, Eigen::Vector3d::Zero()});
  EXPECT_NEAR(map.log_likelihood(o, Pose3()), -0.5 * 1.0 + 0.0 + std::log(0.1), 1e-9);
  EXPECT_FALSE(map.insert(o, Pose3()));
}

}  // namespace
}  // namespace rove
