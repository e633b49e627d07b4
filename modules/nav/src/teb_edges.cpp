#include "rove/nav/teb_edges.h"

#include <cmath>
#include <numbers>

namespace rove::teb {

double wrap_angle(double theta) {
  double t = std::remainder(theta, 2 * std::numbers::pi);
  if (t <= -std::numbers::pi) t += 2 * std::numbers::pi;
  return t;
}

double penalty_below(double v, double a, double eps, double* d) {
  const double bound = a + eps;
  if (v >= bound) {
    if (d) *d = 0;
    return 0;
  }
  if (d) *d = -1;
  return bound - v;
}

double penalty_interval(double v, double a, double b, double eps, double* d) {
  if (v < a + eps) {
    if (d) *d = -1;
    return a + eps - v;
  }
  if (v <= b - eps) {
    if (d) *d = 0;
    return 0;
  }
  if (d) *d = 1;
  return v - (b - eps);
}

namespace {

using Row7 = Eigen::Matrix<double, 1, 7>;

// The signed speed from a to b over dt, v = σ(u)·|Δ|/dt, and its gradient
// in (a, b, dt); σ(u) = 100u / (1 + |100u|) with u = (cos θa, sin θa)·Δ.
double signed_speed(const PoseVec& a, const PoseVec& b, double dt, Row7* J) {
  const Eigen::Vector2d delta = b.head<2>() - a.head<2>();
  const double d = delta.norm();
  const double ca = std::cos(a.z()), sa = std::sin(a.z());
  const double u = ca * delta.x() + sa * delta.y();
  const double s = 100 * u / (1 + std::abs(100 * u));
  const double ds = 100 / ((1 + std::abs(100 * u)) * (1 + std::abs(100 * u)));
  const double v = s * d / dt;
  if (J) {
    // d(σ·|Δ|)/dΔ = σ·Δ/|Δ| + |Δ|·σ'·(cos θa, sin θa); both vanish at Δ = 0.
    Eigen::Vector2d g = d * ds * Eigen::Vector2d(ca, sa);
    if (d > 1e-12) g += s * delta / d;
    g /= dt;
    const double dtheta_a = d * ds * (-sa * delta.x() + ca * delta.y()) / dt;
    *J << -g.x(), -g.y(), dtheta_a, g.x(), g.y(), 0.0, -v / dt;
  }
  return v;
}

// The turn rate ω = wrap(θb − θa) / dt and its gradient in (a, b, dt).
double turn_rate(const PoseVec& a, const PoseVec& b, double dt, Row7* J) {
  const double w = wrap_angle(b.z() - a.z()) / dt;
  if (J) *J << 0.0, 0.0, -1.0 / dt, 0.0, 0.0, 1.0 / dt, -w / dt;
  return w;
}

// Acceleration from a known velocity to the step's (or back): e = (v1 −
// v0)/dt with v1 the step's when `step_first` is false (start edge), and
// (v_end − v_step)/dt when it is true (goal edge).
Eigen::Vector2d known_velocity_acceleration(const PoseVec& a, const PoseVec& b, double dt, double v_known,
                                            double w_known, bool step_first, const TebOptions& o,
                                            Eigen::Matrix<double, 2, 7>* J) {
  Row7 jv, jw;
  const double v = signed_speed(a, b, dt, J ? &jv : nullptr);
  const double w = turn_rate(a, b, dt, J ? &jw : nullptr);
  const double sign = step_first ? -1.0 : 1.0;
  const double acc = sign * (v - v_known) / dt, alpha = sign * (w - w_known) / dt;
  double d0 = 0, d1 = 0;
  Eigen::Vector2d e(penalty_interval(acc, -o.acc_lim_x, o.acc_lim_x, o.penalty_epsilon, &d0),
                    penalty_interval(alpha, -o.acc_lim_theta, o.acc_lim_theta, o.penalty_epsilon, &d1));
  if (J) {
    Row7 ja = sign * jv / dt, jal = sign * jw / dt;
    ja(6) -= acc / dt;
    jal(6) -= alpha / dt;
    J->row(0) = d0 * ja;
    J->row(1) = d1 * jal;
  }
  return e;
}

// The non-holonomic residual (cos θa + cos θb) Δy − (sin θa + sin θb) Δx
// and its gradient in (a, b).
double non_holonomic(const PoseVec& a, const PoseVec& b, Eigen::Matrix<double, 1, 6>* J) {
  const Eigen::Vector2d delta = b.head<2>() - a.head<2>();
  const double ca = std::cos(a.z()), sa = std::sin(a.z()), cb = std::cos(b.z()), sb = std::sin(b.z());
  const double nh = (ca + cb) * delta.y() - (sa + sb) * delta.x();
  if (J) {
    const double gx = -(sa + sb), gy = ca + cb;
    *J << -gx, -gy, -sa * delta.y() - ca * delta.x(), gx, gy, -sb * delta.y() - cb * delta.x();
  }
  return nh;
}

double sign_of(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

}  // namespace

Eigen::Vector2d velocity_error(const PoseVec& a, const PoseVec& b, double dt, const TebOptions& o,
                               Eigen::Matrix<double, 2, 7>* J) {
  Row7 jv, jw;
  const double v = signed_speed(a, b, dt, J ? &jv : nullptr);
  const double w = turn_rate(a, b, dt, J ? &jw : nullptr);
  double d0 = 0, d1 = 0;
  const Eigen::Vector2d e(
      penalty_interval(v, -o.max_vel_x_backwards, o.max_vel_x, o.penalty_epsilon, &d0),
      penalty_interval(w, -o.max_vel_theta, o.max_vel_theta, o.penalty_epsilon, &d1));
  if (J) {
    J->row(0) = d0 * jv;
    J->row(1) = d1 * jw;
  }
  return e;
}

Eigen::Vector2d acceleration_error(const PoseVec& a, const PoseVec& b, const PoseVec& c, double dt1,
                                   double dt2, const TebOptions& o, Eigen::Matrix<double, 2, 11>* J) {
  Row7 jv1, jv2, jw1, jw2;
  const double v1 = signed_speed(a, b, dt1, J ? &jv1 : nullptr);
  const double v2 = signed_speed(b, c, dt2, J ? &jv2 : nullptr);
  const double w1 = turn_rate(a, b, dt1, J ? &jw1 : nullptr);
  const double w2 = turn_rate(b, c, dt2, J ? &jw2 : nullptr);
  const double T = dt1 + dt2;
  const double acc = 2 * (v2 - v1) / T, alpha = 2 * (w2 - w1) / T;
  double d0 = 0, d1 = 0;
  const Eigen::Vector2d e(penalty_interval(acc, -o.acc_lim_x, o.acc_lim_x, o.penalty_epsilon, &d0),
                          penalty_interval(alpha, -o.acc_lim_theta, o.acc_lim_theta, o.penalty_epsilon, &d1));
  if (J) {
    // Columns: a (0-2), b (3-5), c (6-8), dt1 (9), dt2 (10).
    const auto fill = [&](const Row7& j1, const Row7& j2, double value, double dpen, int row) {
      Eigen::Matrix<double, 1, 11> r = Eigen::Matrix<double, 1, 11>::Zero();
      r.segment<3>(0) -= j1.segment<3>(0);
      r.segment<3>(3) += j2.segment<3>(0) - j1.segment<3>(3);
      r.segment<3>(6) += j2.segment<3>(3);
      r(9) = -j1(6);
      r(10) = j2(6);
      r *= 2 / T;
      r(9) -= value / T;
      r(10) -= value / T;
      J->row(row) = dpen * r;
    };
    fill(jv1, jv2, acc, d0, 0);
    fill(jw1, jw2, alpha, d1, 1);
  }
  return e;
}

Eigen::Vector2d acceleration_start_error(const PoseVec& a, const PoseVec& b, double dt, double v0,
                                         double omega0, const TebOptions& o,
                                         Eigen::Matrix<double, 2, 7>* J) {
  return known_velocity_acceleration(a, b, dt, v0, omega0, false, o, J);
}

Eigen::Vector2d acceleration_goal_error(const PoseVec& a, const PoseVec& b, double dt, double v1,
                                        double omega1, const TebOptions& o,
                                        Eigen::Matrix<double, 2, 7>* J) {
  return known_velocity_acceleration(a, b, dt, v1, omega1, true, o, J);
}

double time_optimal_error(double dt, double* J) {
  if (J) *J = 1.0;
  return dt;
}

double shortest_path_error(const PoseVec& a, const PoseVec& b, Eigen::Matrix<double, 1, 6>* J) {
  const Eigen::Vector2d delta = b.head<2>() - a.head<2>();
  const double d = delta.norm();
  if (J) {
    const Eigen::Vector2d g = d > 1e-12 ? Eigen::Vector2d(delta / d) : Eigen::Vector2d::Zero();
    *J << -g.x(), -g.y(), 0.0, g.x(), g.y(), 0.0;
  }
  return d;
}

Eigen::Vector2d diff_drive_error(const PoseVec& a, const PoseVec& b, Eigen::Matrix<double, 2, 6>* J) {
  Eigen::Matrix<double, 1, 6> jnh;
  const double nh = non_holonomic(a, b, J ? &jnh : nullptr);
  const Eigen::Vector2d delta = b.head<2>() - a.head<2>();
  const double ca = std::cos(a.z()), sa = std::sin(a.z());
  const double forward = ca * delta.x() + sa * delta.y();
  double dpen = 0;
  const Eigen::Vector2d e(std::abs(nh), penalty_below(forward, 0.0, 0.0, &dpen));
  if (J) {
    J->row(0) = sign_of(nh) * jnh;
    Eigen::Matrix<double, 1, 6> jf;
    jf << -ca, -sa, -sa * delta.x() + ca * delta.y(), ca, sa, 0.0;
    J->row(1) = dpen * jf;
  }
  return e;
}

Eigen::Vector2d car_like_error(const PoseVec& a, const PoseVec& b, const TebOptions& o,
                               Eigen::Matrix<double, 2, 6>* J) {
  Eigen::Matrix<double, 1, 6> jnh;
  const double nh = non_holonomic(a, b, J ? &jnh : nullptr);
  Eigen::Vector2d e(std::abs(nh), 0.0);
  if (J) {
    J->row(0) = sign_of(nh) * jnh;
    J->row(1).setZero();
  }
  const double turn = wrap_angle(b.z() - a.z());
  if (std::abs(turn) < 1e-9) return e;
  const Eigen::Vector2d delta = b.head<2>() - a.head<2>();
  const double d = delta.norm();
  const double radius = d / std::abs(turn);
  double dpen = 0;
  e(1) = penalty_below(radius, o.min_turning_radius, 0.0, &dpen);
  if (J && dpen != 0) {
    const Eigen::Vector2d g = d > 1e-12 ? Eigen::Vector2d(delta / (d * std::abs(turn))) : Eigen::Vector2d::Zero();
    const double dturn = -d / (turn * turn) * sign_of(turn);  // d radius / d turn
    Eigen::Matrix<double, 1, 6> jr;
    jr << -g.x(), -g.y(), -dturn, g.x(), g.y(), dturn;
    J->row(1) = dpen * jr;
  }
  return e;
}

double obstacle_error(const PoseVec& a, const Eigen::Vector2d& c, const TebOptions& o,
                      Eigen::Matrix<double, 1, 3>* J) {
  const Eigen::Vector2d away = a.head<2>() - c;
  const double d = away.norm();
  double dpen = 0;
  const double e = penalty_below(d - o.robot_radius, o.min_obstacle_dist, o.penalty_epsilon, &dpen);
  if (J) {
    const Eigen::Vector2d n = d > 1e-12 ? Eigen::Vector2d(away / d) : Eigen::Vector2d(-std::sin(a.z()), std::cos(a.z()));
    *J << dpen * n.x(), dpen * n.y(), 0.0;
  }
  return e;
}

double via_point_error(const PoseVec& a, const Eigen::Vector2d& v, Eigen::Matrix<double, 1, 3>* J) {
  const Eigen::Vector2d delta = a.head<2>() - v;
  const double d = delta.norm();
  if (J) {
    const Eigen::Vector2d g = d > 1e-12 ? Eigen::Vector2d(delta / d) : Eigen::Vector2d::Zero();
    *J << g.x(), g.y(), 0.0;
  }
  return d;
}

}  // namespace rove::teb
