#pragma once
/// \file
/// 3D–3D alternative to PnP where both frames have depth: RANSAC
/// (rove/math/ransac.h) over the registration module's closed-form rigid
/// fit (fit_rigid_3d, Umeyama 1991) on minimal samples of three pairs, an
/// inlier being a pair with ‖T·sourceᵢ − targetᵢ‖ within the threshold,
/// refit on the inliers.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se3.h"
#include "rove/registration/rigid_transform.h"
#include "rove/registration/termination.h"

namespace rove {

/// Options of fit_rigid_3d_ransac.
struct RigidRansac3dOptions {
  /// Inlier distance, meters, > 0. Default 0.03.
  double inlier_distance = 0.03;
  /// RANSAC's probability of drawing one clean sample, in (0, 1). Default 0.99.
  double success_probability = 0.99;
  /// Most minimal samples, ≥ 1. Default 500.
  std::size_t max_iterations = 500;
  /// Seed of the sample draws.
  std::uint64_t seed = 42;
  /// Fewer inliers than this is TooFewCorrespondences (≥ 3). Default 10.
  std::size_t min_inliers = 10;
  /// Options of the rigid fit (its point variance sets the covariance).
  RigidFitOptions fit;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Result of fit_rigid_3d_ransac.
struct RigidRansac3dResult {
  /// Pose of the source frame in the target frame: target ≈ T·source.
  SE3d T_target_source;
  /// Its covariance over the right tangent (fit_rigid_3d's, on the inliers).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  /// Indices of the inlier pairs, ascending.
  std::vector<std::size_t> inliers;
  /// RMS distance of the inliers after the fit, meters.
  double rmse = 0.0;
  /// Minimal samples drawn.
  std::size_t ransac_iterations = 0;
  /// Converged, TooFewCorrespondences (fewer pairs or inliers than
  /// min_inliers), Degenerate (no sample gave a fit, or the inliers do not
  /// constrain the pose) or InvalidInput (non-finite coordinates).
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;

  /// True when termination is Converged.
  bool ok() const noexcept { return termination == RegistrationTermination::Converged; }
};

/// Robust T_target_source from pairs (targetᵢ ↔ sourceᵢ), meters.
/// Preconditions (InvalidArgument): equal sizes, options valid.
RigidRansac3dResult fit_rigid_3d_ransac(std::span<const Eigen::Vector3d> target,
                                        std::span<const Eigen::Vector3d> source,
                                        const RigidRansac3dOptions& options = {});

}  // namespace rove
