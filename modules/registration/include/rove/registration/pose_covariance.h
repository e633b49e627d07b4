#pragma once
/// \file
/// Building blocks shared by the registration solvers: turning an
/// information matrix into a pose covariance, and the Jacobian that maps a
/// small rotation to yaw/pitch/roll rates.

#include <Eigen/Core>

#include "rove/poses/lie_conversion.h"  // ypr_rate_to_omega
#include "rove/poses/pose3.h"

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

/// The Jacobian d(x, y, z, yaw, pitch, roll) / d(δt, δω) at `pose` for the
/// left perturbation T ← (exp([δω]ₓ)·R, t + δt). Near gimbal lock
/// (|cos pitch| < 1e-9) the yaw/roll rows use the pseudo-inverse of E, so the
/// result stays finite.
Eigen::Matrix<double, 6, 6> ypr_jacobian_wrt_left_tangent(const Pose3& pose);

}  // namespace rove
