#pragma once
/// \file
/// Perspective-n-Point with RANSAC: the pose of a calibrated camera from
/// 3D points and their pixels, robust to wrong matches.
///
/// RANSAC (rove/math/ransac.h) draws minimal samples of three pairs and
/// solves each with the algebraic P3P of Ke & Roumeliotis ("An efficient
/// algebraic solution to the perspective-three-point problem", CVPR 2017;
/// OpenCV's SOLVEPNP_AP3P), up to four poses per sample. A pair is an
/// inlier when its reprojection error is within the threshold. The best
/// pose is refined on its inliers by Gauss–Newton on the reprojection error
/// over the right tangent (T·exp(ξ)), inliers recounted, refined again.
///
/// Errors are measured in the ideal (undistorted) image: a pixel is first
/// unprojected to its normalized ray (a, b) through the camera model, and
/// the residual of a point p_camera is (fx·(x/z − a), fy·(y/z − b)).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se3.h"
#include "rove/obs/pinhole_camera.h"
#include "rove/registration/termination.h"

namespace rove {

/// Options of solve_pnp_ransac.
struct PnpOptions {
  /// Inlier threshold on the reprojection error, pixels, > 0. Default 2.
  double reprojection_threshold_px = 2.0;
  /// RANSAC's probability of drawing one clean sample, in (0, 1). Default 0.99.
  double success_probability = 0.99;
  /// Most minimal samples, ≥ 1. Default 500.
  std::size_t max_iterations = 500;
  /// Seed of the sample draws; equal seeds give equal results.
  std::uint64_t seed = 42;
  /// Fewer inliers than this is TooFewCorrespondences (≥ 4). Default 10.
  std::size_t min_inliers = 10;
  /// Gauss–Newton iterations of each refinement, ≥ 1. Default 10.
  int refine_iterations = 10;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Result of solve_pnp_ransac.
struct PnpResult {
  /// Pose of the points' frame in the camera frame: p_camera = T·p_world.
  SE3d T_camera_world;
  /// Covariance of T_camera_world over the right tangent (ρ, ω):
  /// σ̂²·(JᵀJ)⁻¹ at the solution, σ̂² = Σ‖rᵢ‖² / (2n − 6) over the inliers.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  /// Indices of the inlier pairs, ascending.
  std::vector<std::size_t> inliers;
  /// RMS reprojection error over the inliers, pixels.
  double rmse_px = 0.0;
  /// Minimal samples drawn.
  std::size_t ransac_iterations = 0;
  /// Converged (at least min_inliers inliers, refined), TooFewCorrespondences
  /// (fewer pairs or inliers than min_inliers; T_camera_world holds the best
  /// pose found, if any), Degenerate (no sample gave a pose) or InvalidInput
  /// (a non-finite coordinate or a pixel the camera model cannot unproject).
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;

  /// True when termination is Converged.
  bool ok() const noexcept { return termination == RegistrationTermination::Converged; }
};

/// The camera pose from pairs (points_world[i] ↔ pixels[i]).
/// Preconditions (InvalidArgument): equal sizes, camera passes check(),
/// options valid.
PnpResult solve_pnp_ransac(std::span<const Eigen::Vector3d> points_world,
                           std::span<const Eigen::Vector2d> pixels, const PinholeCamera& camera,
                           const PnpOptions& options = {});

/// Gauss–Newton refinement of T_camera_world on the given pairs (no
/// outlier rejection), as solve_pnp_ransac's final step: `normalized` holds
/// the normalized rays (a, b) of the pixels, fx and fy scale the residuals
/// to pixels. Returns the refined pose; `covariance` (if not null) receives
/// its covariance as in PnpResult. Pairs behind the camera are skipped.
/// Preconditions (InvalidArgument): equal sizes, fx, fy nonzero, iterations ≥ 1.
SE3d refine_pnp(std::span<const Eigen::Vector3d> points_world,
                std::span<const Eigen::Vector2d> normalized, double fx, double fy,
                const SE3d& T_camera_world, int iterations,
                Eigen::Matrix<double, 6, 6>* covariance = nullptr);

}  // namespace rove
