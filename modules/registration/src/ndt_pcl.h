#pragma once
// PCL's NDT parametrizations (NdtCompat::Pcl; ndt_pcl.cpp): Euler angles
// in 3D, (x, y, phi) in 2D, as models of the solver in ndt_solver.h.

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "ndt_solver.h"

namespace rove::detail {

/// 3D: parameters (x, y, z, roll, pitch, yaw), R = Rx(roll)·Ry(pitch)·Rz(yaw)
/// as PCL's NDT. Precomputes R, its first and second derivatives with
/// respect to the three angles (Magnusson eq. 6.17-6.21 in matrix form).
struct PclEuler3 : NdtModelBase<3, 6, 3, Eigen::Matrix<double, 6, 1>> {
  Mat Rx, Ry;  // the first two factors (for the rates of the angles)
  explicit PclEuler3(const Params& p) {
    const double ca = std::cos(p(3)), sa = std::sin(p(3));
    const double cb = std::cos(p(4)), sb = std::sin(p(4));
    const double cc = std::cos(p(5)), sc = std::sin(p(5));
    Mat X[3], Y[3], Z[3];  // value, first, second derivative
    X[0] << 1, 0, 0, 0, ca, -sa, 0, sa, ca;
    X[1] << 0, 0, 0, 0, -sa, -ca, 0, ca, -sa;
    X[2] << 0, 0, 0, 0, -ca, sa, 0, -sa, -ca;
    Y[0] << cb, 0, sb, 0, 1, 0, -sb, 0, cb;
    Y[1] << -sb, 0, cb, 0, 0, 0, -cb, 0, -sb;
    Y[2] << -cb, 0, -sb, 0, 0, 0, sb, 0, -cb;
    Z[0] << cc, -sc, 0, sc, cc, 0, 0, 0, 1;
    Z[1] << -sc, -cc, 0, cc, -sc, 0, 0, 0, 0;
    Z[2] << -cc, sc, 0, -sc, -cc, 0, 0, 0, 0;
    Rx = X[0];
    Ry = Y[0];
    R = X[0] * Y[0] * Z[0];
    t = p.head<3>();
    dR[0] = X[1] * Y[0] * Z[0];
    dR[1] = X[0] * Y[1] * Z[0];
    dR[2] = X[0] * Y[0] * Z[1];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int oi[3] = {i == 0 ? 1 : 0, i == 1 ? 1 : 0, i == 2 ? 1 : 0};
        const int oj[3] = {j == 0 ? 1 : 0, j == 1 ? 1 : 0, j == 2 ? 1 : 0};
        d2R[i][j] = X[oi[0] + oj[0]] * Y[oi[1] + oj[1]] * Z[oi[2] + oj[2]];
      }
  }
  Vec basis(const Vec& x) const { return x; }
  static Params retract(const Params& p, const Params& d) { return p + d; }
  static bool finite(const Params& p) { return p.allFinite(); }
  static double step_translation_sq(const Params& d) { return d.head<3>().squaredNorm(); }
  static double step_cos_angle(const Params& d) { return 0.5 * (PclEuler3(d).R.trace() - 1); }
  static Params from_group(const SE3d& T) {
    const Mat m = T.rotation_matrix();
    Params p;
    p.head<3>() = T.translation();
    // R = Rx(a)·Ry(b)·Rz(c): R(0,2) = sin b, R(1,2) = −sin a cos b,
    // R(2,2) = cos a cos b, R(0,1) = −cos b sin c, R(0,0) = cos b cos c.
    p(4) = std::asin(std::clamp(m(0, 2), -1.0, 1.0));
    p(3) = std::atan2(-m(1, 2), m(2, 2));
    p(5) = std::atan2(-m(0, 1), m(0, 0));
    return p;
  }
  static SE3d to_group(const Params& p) {
    const PclEuler3 m(p);
    return SE3d(Eigen::Quaterniond(m.R).normalized(), m.t);
  }
  /// d(ρ, ω) / d(t, roll, pitch, yaw): ρ = Rᵀ·δt; the angles' rates are
  /// ω_world = [e_x, Rx·e_y, Rx·Ry·e_z]·(roll, pitch, yaw)˙, ω = Rᵀ·ω_world.
  static Eigen::Matrix<double, P, P> right_from_params(const Params& p) {
    const PclEuler3 m(p);
    Mat E;
    E.col(0) = Vec::UnitX();
    E.col(1) = m.Rx * Vec::UnitY();
    E.col(2) = m.Rx * m.Ry * Vec::UnitZ();
    Eigen::Matrix<double, P, P> J = Eigen::Matrix<double, P, P>::Zero();
    J.topLeftCorner<3, 3>() = m.R.transpose();
    J.bottomRightCorner<3, 3>() = m.R.transpose() * E;
    return J;
  }
};

/// 2D: parameters (x, y, phi) with the translation in the target frame.
struct PclPlanar : NdtModelBase<2, 3, 1, Eigen::Vector3d> {
  explicit PclPlanar(const Params& p) {
    const double c = std::cos(p(2)), s = std::sin(p(2));
    R << c, -s, s, c;
    dR[0] << -s, -c, c, -s;
    d2R[0][0] = -R;
    t = p.head<2>();
  }
  Vec basis(const Vec& x) const { return x; }
  static Params retract(const Params& p, const Params& d) { return p + d; }
  static bool finite(const Params& p) { return p.allFinite(); }
  static double step_translation_sq(const Params& d) { return d.head<2>().squaredNorm(); }
  static double step_cos_angle(const Params& d) { return std::cos(d(2)); }
  static Params from_group(const SE2d& T) {
    return Params(T.translation().x(), T.translation().y(), T.rotation().angle());
  }
  static SE2d to_group(const Params& p) { return SE2d(p(0), p(1), p(2)); }
  /// d(ρx, ρy, θ) / d(x, y, phi) = diag(Rᵀ, 1).
  static Eigen::Matrix3d right_from_params(const Params& p) {
    Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
    J.topLeftCorner<2, 2>() = PclPlanar(p).R.transpose();
    return J;
  }
};

}  // namespace rove::detail
