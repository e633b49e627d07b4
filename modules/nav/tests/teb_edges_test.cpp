// Every TEB edge's analytic Jacobian against central differences, at
// random configurations where its bounds are active.
#include "rove/nav/teb_edges.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>

namespace rove {
namespace {

using teb::PoseVec;

TebOptions tight() {
  TebOptions o;
  o.max_vel_x = 0.3;
  o.max_vel_x_backwards = 0.1;
  o.max_vel_theta = 0.2;
  o.acc_lim_x = 0.2;
  o.acc_lim_theta = 0.2;
  o.min_turning_radius = 2.0;
  o.min_obstacle_dist = 0.5;
  o.robot_radius = 0.3;
  return o;
}

// Central differences of f over its stacked variables x.
template <int M>
Eigen::MatrixXd numeric(const std::function<Eigen::Matrix<double, M, 1>(const Eigen::VectorXd&)>& f,
                        const Eigen::VectorXd& x) {
  Eigen::MatrixXd J(M, x.size());
  const double h = 1e-6;
  for (int k = 0; k < x.size(); ++k) {
    Eigen::VectorXd a = x, b = x;
    a(k) += h;
    b(k) -= h;
    J.col(k) = (f(a) - f(b)) / (2 * h);
  }
  return J;
}

void expect_close(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& num, const char* edge, int trial) {
  ASSERT_TRUE(analytic.allFinite()) << edge;
  for (int r = 0; r < analytic.rows(); ++r) {
    for (int c = 0; c < analytic.cols(); ++c) {
      EXPECT_NEAR(analytic(r, c), num(r, c), 1e-5 * (1 + std::abs(num(r, c))))
          << edge << " trial " << trial << " (" << r << ", " << c << ")";
    }
  }
}

struct Sampler {
  std::mt19937_64 rng{42};
  std::uniform_real_distribution<double> pos{-1.0, 1.0}, ang{-3.0, 3.0}, dt{0.1, 0.6};
  PoseVec pose() { return {pos(rng), pos(rng), ang(rng)}; }
  // A pose a short step from p, forward or backward, turned a little.
  PoseVec near(const PoseVec& p) {
    const double d = 0.05 + 0.3 * std::abs(pos(rng));
    const double a = p.z() + 2.5 * pos(rng);
    return {p.x() + d * std::cos(a), p.y() + d * std::sin(a), p.z() + 0.6 * pos(rng)};
  }
};

PoseVec at(const Eigen::VectorXd& x, int k) { return x.segment<3>(k); }

TEST(TebEdges, VelocityAndAccelerationJacobians) {
  Sampler s;
  const TebOptions o = tight();
  int active_v = 0, active_w = 0, active_acc = 0;
  for (int t = 0; t < 300; ++t) {
    const PoseVec a = s.pose(), b = s.near(a), c = s.near(b);
    const double dt1 = s.dt(s.rng), dt2 = s.dt(s.rng);
    Eigen::VectorXd x7(7), x11(11);
    x7 << a, b, dt1;
    x11 << a, b, c, dt1, dt2;
    Eigen::Matrix<double, 2, 7> J7;
    const Eigen::Vector2d ev = teb::velocity_error(a, b, dt1, o, &J7);
    active_v += ev(0) > 0;
    active_w += ev(1) > 0;
    active_acc += teb::acceleration_error(a, b, c, dt1, dt2, o)(0) > 0;
    expect_close(J7, numeric<2>([&](const Eigen::VectorXd& x) { return teb::velocity_error(at(x, 0), at(x, 3), x(6), o); }, x7),
                 "velocity", t);
    Eigen::Matrix<double, 2, 11> J11;
    teb::acceleration_error(a, b, c, dt1, dt2, o, &J11);
    expect_close(J11,
                 numeric<2>([&](const Eigen::VectorXd& x) {
                   return teb::acceleration_error(at(x, 0), at(x, 3), at(x, 6), x(9), x(10), o);
                 }, x11),
                 "acceleration", t);
    teb::acceleration_start_error(a, b, dt1, 0.2, -0.1, o, &J7);
    expect_close(J7, numeric<2>([&](const Eigen::VectorXd& x) {
                   return teb::acceleration_start_error(at(x, 0), at(x, 3), x(6), 0.2, -0.1, o);
                 }, x7),
                 "acceleration_start", t);
    teb::acceleration_goal_error(a, b, dt1, 0.0, 0.0, o, &J7);
    expect_close(J7, numeric<2>([&](const Eigen::VectorXd& x) {
                   return teb::acceleration_goal_error(at(x, 0), at(x, 3), x(6), 0.0, 0.0, o);
                 }, x7),
                 "acceleration_goal", t);
  }
  // The bounds were active in most trials (the Jacobians are not all zero).
  EXPECT_GT(active_v, 100);
  EXPECT_GT(active_w, 100);
  EXPECT_GT(active_acc, 100);
}

TEST(TebEdges, KinematicsPathObstacleAndViaJacobians) {
  Sampler s;
  const TebOptions o = tight();
  int active_radius = 0, active_obstacle = 0, active_backward = 0;
  for (int t = 0; t < 300; ++t) {
    const PoseVec a = s.pose(), b = s.near(a);
    active_radius += teb::car_like_error(a, b, o)(1) > 0;
    active_backward += teb::diff_drive_error(a, b)(1) > 0;
    Eigen::VectorXd x6(6), x3(3);
    x6 << a, b;
    x3 << a;
    Eigen::Matrix<double, 2, 6> J6;
    teb::diff_drive_error(a, b, &J6);
    expect_close(J6, numeric<2>([&](const Eigen::VectorXd& x) { return teb::diff_drive_error(at(x, 0), at(x, 3)); }, x6),
                 "diff_drive", t);
    teb::car_like_error(a, b, o, &J6);
    expect_close(J6, numeric<2>([&](const Eigen::VectorXd& x) { return teb::car_like_error(at(x, 0), at(x, 3), o); }, x6),
                 "car_like", t);
    Eigen::Matrix<double, 1, 6> J16;
    teb::shortest_path_error(a, b, &J16);
    expect_close(J16, numeric<1>([&](const Eigen::VectorXd& x) {
                   return Eigen::Matrix<double, 1, 1>(teb::shortest_path_error(at(x, 0), at(x, 3)));
                 }, x6),
                 "shortest_path", t);
    const Eigen::Vector2d obstacle = a.head<2>() + Eigen::Vector2d(s.pos(s.rng), s.pos(s.rng));
    Eigen::Matrix<double, 1, 3> J3;
    active_obstacle += teb::obstacle_error(a, obstacle, o, &J3) > 0;
    expect_close(J3, numeric<1>([&](const Eigen::VectorXd& x) {
                   return Eigen::Matrix<double, 1, 1>(teb::obstacle_error(at(x, 0), obstacle, o));
                 }, x3),
                 "obstacle", t);
    teb::via_point_error(a, obstacle, &J3);
    expect_close(J3, numeric<1>([&](const Eigen::VectorXd& x) {
                   return Eigen::Matrix<double, 1, 1>(teb::via_point_error(at(x, 0), obstacle));
                 }, x3),
                 "via_point", t);
    double jt = 0;
    EXPECT_EQ(teb::time_optimal_error(0.25, &jt), 0.25);
    EXPECT_EQ(jt, 1.0);
  }
  EXPECT_GT(active_radius, 50);
  EXPECT_GT(active_obstacle, 50);
  EXPECT_GT(active_backward, 20);
}

TEST(TebEdges, DegenerateConfigurationsGiveFiniteValues) {
  const TebOptions o = tight();
  const PoseVec a(1.0, 2.0, 0.5);
  Eigen::Matrix<double, 2, 7> J7;
  Eigen::Matrix<double, 2, 11> J11;
  Eigen::Matrix<double, 2, 6> J6;
  Eigen::Matrix<double, 1, 3> J3;
  // A zero-length step, a zero-length band, an obstacle on the pose.
  EXPECT_TRUE(teb::velocity_error(a, a, 0.3, o, &J7).allFinite());
  EXPECT_TRUE(J7.allFinite());
  EXPECT_TRUE(teb::acceleration_error(a, a, a, 0.3, 0.3, o, &J11).allFinite());
  EXPECT_TRUE(J11.allFinite());
  EXPECT_TRUE(teb::diff_drive_error(a, a, &J6).allFinite());
  EXPECT_TRUE(teb::car_like_error(a, a, o, &J6).allFinite());
  EXPECT_TRUE(J6.allFinite());
  const double e = teb::obstacle_error(a, a.head<2>(), o, &J3);
  EXPECT_DOUBLE_EQ(e, o.robot_radius * 0 + o.min_obstacle_dist + o.penalty_epsilon + o.robot_radius);
  EXPECT_TRUE(J3.allFinite());
  EXPECT_NEAR(J3.head<2>().norm(), 1.0, 1e-12);  // pushed sideways
  EXPECT_DOUBLE_EQ(teb::via_point_error(a, a.head<2>(), &J3), 0.0);
  EXPECT_TRUE(J3.allFinite());
}

TEST(TebEdges, Penalties) {
  double d = 0;
  EXPECT_EQ(teb::penalty_below(1.0, 0.5, 0.1, &d), 0.0);
  EXPECT_EQ(d, 0.0);
  EXPECT_NEAR(teb::penalty_below(0.2, 0.5, 0.1, &d), 0.4, 1e-15);
  EXPECT_EQ(d, -1.0);
  EXPECT_NEAR(teb::penalty_interval(1.0, -0.5, 0.8, 0.1, &d), 0.3, 1e-15);
  EXPECT_EQ(d, 1.0);
  EXPECT_NEAR(teb::penalty_interval(-1.0, -0.5, 0.8, 0.1, &d), 0.6, 1e-15);
  EXPECT_EQ(d, -1.0);
  EXPECT_EQ(teb::penalty_interval(0.0, -0.5, 0.8, 0.1, &d), 0.0);
  EXPECT_NEAR(teb::wrap_angle(3 * std::numbers::pi), std::numbers::pi, 1e-12);
  EXPECT_NEAR(teb::wrap_angle(-std::numbers::pi), std::numbers::pi, 1e-12);
}

}  // namespace
}  // namespace rove
