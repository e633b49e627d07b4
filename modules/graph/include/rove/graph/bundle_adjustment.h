#pragma once
/// \file
/// Bundle adjustment of calibrated cameras and 3D points, with RGB-D depth
/// measurements and relative-pose measurements between cameras: Levenberg–
/// Marquardt on the cameras' poses and the points' positions, the points
/// eliminated by the Schur complement (Triggs et al., "Bundle Adjustment —
/// A Modern Synthesis", 2000, §6.1), the reduced camera system solved by a
/// sparse LDLᵀ. Robust: a Huber kernel on each observation, and rounds after
/// which the observations whose χ² exceeds the chi-square 95 % bound are
/// dropped (as ORB-SLAM2's local and global bundle adjustments do, Mur-Artal
/// and Tardós, T-RO 2017, §V).
///
/// An observation of point j by camera i is its undistorted normalized
/// image coordinates (x/z, y/z in the camera frame), the residual being the
/// difference scaled by the focal lengths so that it reads in pixels, and,
/// for a depth camera, the measured inverse depth 1/z. Inverse depth rather
/// than depth: a structured-light or stereo sensor measures disparity, whose
/// noise is about constant, so 1/z has about constant noise where z has
/// noise growing with z² (Khoshelham and Elberink, Sensors 2012, eq. 10).
///
///   rove::BundleAdjustmentProblem p;       // cameras, points, observations
///   auto r = rove::bundle_adjust(p, {});   // p's poses and points updated
///   if (!r.ok()) std::cerr << r.message;
///
/// Frames: T_world_camera maps camera coordinates (z forward) into the
/// world's. Updates are on the left of T_camera_world: T ← exp(δ)·T.

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/graph/optimizer.h"
#include "rove/math/se3.h"

namespace rove {

/// Camera `camera` sees point `point`.
struct BaObservation {
  std::size_t camera = 0;  ///< index into BundleAdjustmentProblem::T_world_camera
  std::size_t point = 0;   ///< index into BundleAdjustmentProblem::points_world
  /// Undistorted normalized image coordinates (x/z, y/z), camera frame.
  Eigen::Vector2d normalized = Eigen::Vector2d::Zero();
  /// Measured inverse depth 1/z, 1/m; NaN when the observation has no depth.
  double inverse_depth = std::numeric_limits<double>::quiet_NaN();
  /// Standard deviation of the image measurement, pixels (> 0).
  double sigma_px = 1.0;
  /// Standard deviation of the inverse depth, 1/m (> 0 when inverse_depth is given).
  double sigma_inverse_depth = 0.01;
};

/// A measured relative pose between two cameras: T_from_to = T_world_from⁻¹·T_world_to.
struct BaRelativePose {
  std::size_t from = 0;
  std::size_t to = 0;
  SE3d T_from_to;
  /// Information of the error log(T_from_to⁻¹·T_world_from⁻¹·T_world_to)
  /// over (ρ, ω), meters and radians; symmetric positive semi-definite.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();
};

/// What to adjust. bundle_adjust() updates T_world_camera and points_world.
struct BundleAdjustmentProblem {
  double fx = 1.0;  ///< focal lengths, pixels: scale the normalized residuals to pixels (> 0)
  double fy = 1.0;
  std::vector<SE3d> T_world_camera;       ///< the cameras' poses
  std::vector<bool> fixed;                ///< cameras held fixed (empty: the first one); one at least
  std::vector<Eigen::Vector3d> points_world;
  std::vector<BaObservation> observations;
  std::vector<BaRelativePose> relative_poses;
};

/// Options of bundle_adjust(); defaults in the comments.
struct BundleAdjustmentOptions {
  /// Optimization rounds; after each but the last, the observations whose χ²
  /// (whitened squared residual) exceeds the chi-square bound are dropped
  /// and kept out of the later rounds (≥ 1).
  int rounds = 2;
  int max_iterations = 20;           ///< LM iterations per round (≥ 1)
  double huber_delta_2d = 2.447695;  ///< Huber δ of an image-only observation (√5.991, χ²₂ 95 %)
  double huber_delta_3d = 2.795533;  ///< Huber δ of an observation with depth (√7.815, χ²₃ 95 %)
  double outlier_chi2_2d = 5.991;    ///< χ² bound of an image-only observation
  double outlier_chi2_3d = 7.815;    ///< χ² bound of an observation with depth
  double min_depth = 1e-3;           ///< m: a point nearer (or behind) a camera is an outlier there
  double function_tolerance = 1e-7;  ///< stop when a step lowers the cost by ≤ this × the cost
  double initial_lambda = 1e-4;      ///< LM damping, relative to the diagonal
};

/// What bundle_adjust() did.
struct BundleAdjustmentResult {
  /// Converged (the last round met function_tolerance), MaxIterations (a
  /// round ended at max_iterations; the poses are still an improvement),
  /// NoProgress (the damping could not lower the cost), InvalidInput
  /// (nothing changed; the message says why) or NumericalFailure.
  GraphTermination termination = GraphTermination::InvalidInput;
  std::string message;               ///< one line
  double initial_cost = 0.0;         ///< robust cost Σ ρ(χ²) before, all observations
  double final_cost = 0.0;           ///< robust cost after, over the inliers
  int iterations = 0;                ///< LM iterations, all rounds
  std::size_t points_adjusted = 0;   ///< points with at least one inlier observation
  std::size_t cameras_adjusted = 0;  ///< cameras not fixed that some term involves
  std::size_t outliers = 0;          ///< observations dropped
  std::vector<bool> inlier;          ///< per observation: kept to the end
  double rmse_px = 0.0;              ///< RMS image residual of the inliers at the end, pixels

  bool ok() const noexcept { return termination == GraphTermination::Converged; }
  /// The cameras and points are worth using (Converged, MaxIterations, NoProgress).
  bool improved() const noexcept {
    return termination == GraphTermination::Converged || termination == GraphTermination::MaxIterations ||
           termination == GraphTermination::NoProgress;
  }
};

/// Adjusts the problem's non-fixed cameras and its observed points in place.
/// Throws InvalidArgument for bad options. A problem that cannot be set up
/// (an index out of range, a non-finite value, σ ≤ 0, no fixed camera among
/// several, focal lengths ≤ 0) returns InvalidInput with the offending entry
/// named, the problem untouched. Cameras no term involves and points no
/// inlier observes keep their values. The reduced camera system is sparse
/// (cameras that share no point and no relative pose share no block).
BundleAdjustmentResult bundle_adjust(BundleAdjustmentProblem& problem,
                                     const BundleAdjustmentOptions& options = {});

}  // namespace rove
