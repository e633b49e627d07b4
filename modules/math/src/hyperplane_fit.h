#pragma once
// Shared by plane_detection.cpp and line_detection.cpp: hyperplanes
// {p : n·p + d = 0} in D = 2 (lines) or D = 3 (planes) dimensions.

#include <cstddef>
#include <span>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "rove/core/check.h"

namespace rove::detail {

template <int D>
using HyperVec = Eigen::Matrix<double, D, 1>;

/// Rejects a non-finite point, naming its index in the caller's input.
template <int D>
void check_points_finite(std::span<const HyperVec<D>> points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if constexpr (D == 2) {
      ROVE_CHECK_MSG(p.allFinite(), "points[{}] = ({}, {}) is not finite", i, p.x(), p.y());
    } else {
      ROVE_CHECK_MSG(p.allFinite(), "points[{}] = ({}, {}, {}) is not finite", i, p.x(), p.y(),
                     p.z());
    }
  }
}

/// Canonical sign of (n, d): d ≤ 0, and for d = 0 the largest-magnitude
/// component of n positive.
template <int D>
void canonicalize(HyperVec<D>& n, double& d) {
  bool flip = d > 0.0;
  if (d == 0.0) {
    Eigen::Index k = 0;
    n.cwiseAbs().maxCoeff(&k);
    flip = n[k] < 0.0;
  }
  if (flip) {
    n = -n;
    d = -d;
  }
}

/// Total least squares: the hyperplane through the centroid whose normal is
/// the scatter matrix's eigenvector of smallest eigenvalue (Pearson 1901).
/// Returns false when the points do not determine one: fewer than D points,
/// all coincident, or (D = 3) all collinear, up to relative tolerances.
template <int D>
bool fit_hyperplane_pca(std::span<const HyperVec<D>> points, HyperVec<D>& n, double& d) {
  check_points_finite<D>(points);
  if (points.size() < static_cast<std::size_t>(D)) return false;
  HyperVec<D> centroid = HyperVec<D>::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  // Two passes: deviations from the centroid avoid the cancellation of
  // Σ ppᵀ − N ccᵀ when the points are far from the origin.
  Eigen::Matrix<double, D, D> scatter = Eigen::Matrix<double, D, D>::Zero();
  for (const auto& p : points) {
    const HyperVec<D> q = p - centroid;
    scatter.noalias() += q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> eig(scatter);
  if (eig.info() != Eigen::Success) return false;
  const auto& ev = eig.eigenvalues();  // ascending
  const double rounding = 1e-12 * centroid.norm();
  if (!(ev[D - 1] > static_cast<double>(points.size()) * rounding * rounding)) return false;
  if constexpr (D == 3) {
    if (!(ev[1] > 1e-10 * ev[2])) return false;  // collinear: no unique plane
  }
  n = eig.eigenvectors().col(0).normalized();
  d = -n.dot(centroid);
  canonicalize<D>(n, d);
  return true;
}

}  // namespace rove::detail
