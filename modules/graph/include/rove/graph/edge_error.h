#pragma once
/// \file
/// The error of one relative-pose edge and its Jacobians, in the convention
/// of pose_graph.h: E = Z⁻¹·(Xi⁻¹·Xj), e = [t_E; θ_E] (2D) or
/// [t_E; q_E.xyz] with q_E.w ≥ 0 (3D).
///
/// Jacobians are with respect to right perturbations Xi·exp(δi), Xj·exp(δj)
/// (docs/conventions.md). Perturbing Xi gives E·exp(−Adj(Xj⁻¹·Xi)·δi) and
/// perturbing Xj gives E·exp(δj) (Solà et al. 2018, Eqs. 160–162), so both
/// are G(E)·(∂E tangent) with G = ∂e/∂(right tangent of E):
///   2D: G = diag(R_E, 1);
///   3D: G = diag(R_E, ½(w·I + [v]×)) for q_E = (w, v), since
///       q ⊗ (1, ω/2) has vector part v + ½(w·I + [v]×)·ω.

#include <cmath>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/math/se3.h"

namespace rove {

/// Error vector of an edge, and optionally its Jacobians with respect to
/// right perturbations of the two vertices. Xi, Xj: T_world_i, T_world_j;
/// Z: measured T_i_j.
inline Eigen::Vector3d edge_error(const SE2d& Xi, const SE2d& Xj, const SE2d& Z,
                                  Eigen::Matrix3d* J_i = nullptr,
                                  Eigen::Matrix3d* J_j = nullptr) {
  const SE2d Xij = Xi.inverse() * Xj;
  const SE2d E = Z.inverse() * Xij;
  Eigen::Vector3d e;
  e.head<2>() = E.translation();
  e(2) = E.angle();
  if (J_i || J_j) {
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    G.topLeftCorner<2, 2>() = E.rotation_matrix();
    G(2, 2) = 1.0;
    if (J_j) *J_j = G;
    if (J_i) *J_i = -G * Xij.inverse().Adj();
  }
  return e;
}

/// 3D overload.
inline Eigen::Matrix<double, 6, 1> edge_error(const SE3d& Xi, const SE3d& Xj, const SE3d& Z,
                                              Eigen::Matrix<double, 6, 6>* J_i = nullptr,
                                              Eigen::Matrix<double, 6, 6>* J_j = nullptr) {
  const SE3d Xij = Xi.inverse() * Xj;
  const SE3d E = Z.inverse() * Xij;
  Eigen::Quaterniond q = E.quaternion();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = E.translation();
  e.tail<3>() = q.vec();
  if (J_i || J_j) {
    Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Zero();
    G.topLeftCorner<3, 3>() = q.toRotationMatrix();
    Eigen::Matrix3d vx;
    vx << 0.0, -q.z(), q.y(), q.z(), 0.0, -q.x(), -q.y(), q.x(), 0.0;
    G.bottomRightCorner<3, 3>() = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + vx);
    if (J_j) *J_j = G;
    if (J_i) *J_i = -G * Xij.inverse().Adj();
  }
  return e;
}

}  // namespace rove
