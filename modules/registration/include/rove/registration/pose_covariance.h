#pragma once
/// \file
/// A building block shared by the registration solvers: turning an
/// information matrix into a pose covariance.

#include <Eigen/Core>

namespace rove {

/// Covariance from an information (Gauss–Newton Hessian) matrix H, scaled by
/// `scale`: scale·H⁻¹ computed on the eigen-decomposition, where eigenvalues
/// below `relative_floor`·λ_max are treated as zero information and get the
/// variance kUnconstrainedVariance along their eigenvector. Returns the
/// number of such directions in `unconstrained` when it is not null.
/// Precondition: H symmetric and finite, scale > 0, relative_floor in (0, 1).
template <int N>
Eigen::Matrix<double, N, N> covariance_from_information(const Eigen::Matrix<double, N, N>& H,
                                                        double scale, double relative_floor,
                                                        int* unconstrained = nullptr);

}  // namespace rove
