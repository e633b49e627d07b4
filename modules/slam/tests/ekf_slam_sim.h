#pragma once
// A simulated world for EKF-SLAM tests: landmarks, a robot driving a loop,
// odometry and range-bearing readings drawn from exactly the filter's noise
// models with a fixed seed.

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/slam/ekf_slam.h"

namespace rove::test {

template <int Dim>
struct SlamSim {
  using Pose = typename EkfSlamTraits<Dim>::Pose;
  using Point = Eigen::Matrix<double, Dim, 1>;
  using Tangent = Eigen::Matrix<double, EkfSlamTraits<Dim>::kPoseDof, 1>;
  static constexpr int kD = EkfSlamTraits<Dim>::kPoseDof;

  std::mt19937_64 rng;
  std::vector<Point> landmarks;
  Pose truth;                // the true robot pose
  Pose T_robot_sensor;       // sensor mounting
  Tangent odo_std;           // odometry noise over the increment's right tangent
  double std_range = 0.05, std_yaw = 0.01, std_pitch = 0.01;
  double max_range = 8.0;
  bool with_ids = true;
  int step_index = 0;

  explicit SlamSim(std::uint64_t seed, int count = 30) : rng(seed) {
    std::uniform_real_distribution<double> u(-10.0, 10.0), uz(-2.0, 2.0);
    for (int i = 0; i < count; ++i) {
      Point p;
      p.template head<2>() = Eigen::Vector2d(u(rng), u(rng));
      if constexpr (Dim == 3) p[2] = uz(rng);
      landmarks.push_back(p);
    }
    odo_std.setConstant(0.01);
    odo_std.template head<Dim>().setConstant(0.02);
  }

  double normal() { return std::normal_distribution<double>(0.0, 1.0)(rng); }

  // The nominal increment of step k: a loop of radius ~5 m (3D: gentle
  // climbs and rolls).
  Pose nominal(int k) const {
    Tangent xi = Tangent::Zero();
    xi[0] = 0.3;
    if constexpr (Dim == 2) {
      xi[2] = 0.06;
    } else {
      xi[2] = 0.02 * std::sin(0.1 * k);
      xi[3] = 0.02 * std::cos(0.07 * k);
      xi[4] = 0.02 * std::sin(0.05 * k);
      xi[5] = 0.06;
    }
    return Pose::exp(xi);
  }

  // Moves the robot: the filter gets U_nom with covariance diag(odo_std²);
  // the truth moves by U_nom·exp(ε), ε drawn from that covariance.
  EkfSlamOdometry<Dim> move() {
    const Pose U = nominal(step_index++);
    Tangent eps;
    for (int i = 0; i < kD; ++i) eps[i] = odo_std[i] * normal();
    truth = truth * U * Pose::exp(eps);
    EkfSlamOdometry<Dim> odo;
    odo.increment = U;
    odo.covariance = odo_std.cwiseAbs2().asDiagonal();
    return odo;
  }

  // Readings of the landmarks within max_range, with noise.
  EkfSlamFrame<Dim> sense() {
    EkfSlamFrame<Dim> f;
    f.T_robot_sensor = T_robot_sensor;
    const Pose T_ws = truth * T_robot_sensor;
    for (std::size_t i = 0; i < landmarks.size(); ++i) {
      const Point p = T_ws.inverse() * landmarks[i];
      if (p.norm() > max_range || p.template head<2>().norm() < 0.5) continue;
      EkfSlamReading<Dim> r;
      r.id = with_ids ? static_cast<std::int64_t>(i) : -1;
      r.z[0] = p.norm() + std_range * normal();
      r.z[1] = std::atan2(p[1], p[0]) + std_yaw * normal();
      if constexpr (Dim == 3) {
        r.z[2] = -std::atan2(p[2], p.template head<2>().norm()) + std_pitch * normal();
      }
      f.readings.push_back(r);
    }
    return f;
  }

  // Filter options matching the simulated noise.
  EkfSlamOptions options() const {
    EkfSlamOptions o = EkfSlamOptions::defaults(Dim);
    o.std_sensor_range = std_range;
    o.std_sensor_yaw = std_yaw;
    o.std_sensor_pitch = std_pitch;
    return o;
  }
};

}  // namespace rove::test
