#pragma once
/// \file
/// Closed-form least-squares rigid transforms from matched point pairs:
/// find T_target_source minimizing Σ wᵢ ‖T·sᵢ − tᵢ‖², in 2D (x, y, phi) and
/// in 3D (rotation + translation, no scale).
///
///  - 2D: the classic solution of Lu & Milios ("Robot pose estimation in
///    unknown environments by matching 2D range scans", 1997, eq. 12-13),
///    the one MRPT's tfest::se2_l2 uses: centroids, then
///    phi = atan2(Σ w (s̄ₓt̄ᵧ − s̄ᵧt̄ₓ), Σ w (s̄ₓt̄ₓ + s̄ᵧt̄ᵧ)) on centered points.
///  - 3D: Umeyama, "Least-squares estimation of transformation parameters
///    between two point patterns", PAMI 1991, eq. 39-41 without scale (the
///    SVD form of Horn's solution), with the reflection guard S = diag(1,1,±1).
///
/// Covariance: with every coordinate of every point perturbed by independent
/// noise of variance σ² (`point_variance`), the first-order covariance of the
/// estimate is σ²·(Σ wᵢ JᵢᵀJᵢ)⁻¹, Jᵢ the Jacobian of the residual T·sᵢ − tᵢ
/// with respect to the pose at the solution. It is reported over the group's
/// right tangent, T·exp(ξ) (SE2: ξ = (ρx, ρy, θ); SE3: ξ = (ρ, ω);
/// docs/conventions.md). Directions the pairs do not constrain get the
/// variance kUnconstrainedVariance and the termination reason Degenerate.

#include <cstddef>
#include <span>
#include <string>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/registration/termination.h"

namespace rove {

/// Variance (m² or rad²) reported along directions that the data leave
/// unconstrained, so that covariances stay finite and usable in filters.
inline constexpr double kUnconstrainedVariance = 1e6;

/// Options of fit_rigid_2d / fit_rigid_3d.
struct RigidFitOptions {
  /// σ², the variance of each point coordinate, m² (MRPT's
  /// covariance_varPoints). > 0. Default (0.02 m)².
  double point_variance = 0.02 * 0.02;
  /// A direction is unconstrained when its eigenvalue of the normalized
  /// information matrix (rotation scaled by the RMS radius of the source
  /// points) is below this fraction of the largest. In (0, 1). Default 1e-9.
  double degeneracy_ratio = 1e-9;
};

/// Result of fit_rigid_2d.
struct RigidFit2Result {
  /// The pose of the source frame in the target frame.
  SE2d T_target_source;
  /// Its covariance over the right tangent (ρx, ρy, θ).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  /// Pairs with a positive weight that were used.
  std::size_t pairs = 0;
  /// sqrt(Σ wᵢ ‖T·sᵢ − tᵢ‖² / Σ wᵢ), meters.
  double rmse = 0.0;
  /// Converged, Degenerate (a direction unconstrained, e.g. all source
  /// points equal), TooFewCorrespondences (fewer than 2 pairs) or
  /// InvalidInput (non-finite coordinates or weights).
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;
};

/// Result of fit_rigid_3d.
struct RigidFit3Result {
  /// The pose of the source frame in the target frame.
  SE3d T_target_source;
  /// Its covariance over the right tangent (ρ, ω).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  /// Pairs with a positive weight that were used.
  std::size_t pairs = 0;
  /// sqrt(Σ wᵢ ‖T·sᵢ − tᵢ‖² / Σ wᵢ), meters.
  double rmse = 0.0;
  /// Converged, Degenerate (collinear or coincident source points: a
  /// rotation is unconstrained), TooFewCorrespondences (fewer than 3 pairs)
  /// or InvalidInput (non-finite coordinates or weights).
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;
};

/// The T_target_source minimizing Σ wᵢ ‖T·sourceᵢ − targetᵢ‖² in 2D.
/// `weights` is empty (all 1) or has one weight ≥ 0 per pair.
/// Preconditions (InvalidArgument): target.size() == source.size(), weights
/// empty or of the same size and ≥ 0, options valid. Non-finite inputs are
/// outside data: they give InvalidInput, not an exception.
RigidFit2Result fit_rigid_2d(std::span<const Eigen::Vector2d> target,
                             std::span<const Eigen::Vector2d> source,
                             std::span<const double> weights = {},
                             const RigidFitOptions& options = {});

/// The T_target_source minimizing Σ wᵢ ‖T·sourceᵢ − targetᵢ‖² in 3D (same
/// contract as fit_rigid_2d).
RigidFit3Result fit_rigid_3d(std::span<const Eigen::Vector3d> target,
                             std::span<const Eigen::Vector3d> source,
                             std::span<const double> weights = {},
                             const RigidFitOptions& options = {});

}  // namespace rove
