#pragma once
/// \file
/// 2D ICP: the pose T_target_source of a planar point set (a laser scan in
/// the robot frame, scan.points_2d()) in the frame of an IcpTarget2D (a point
/// map or the occupied cells of a grid), from an initial guess.
///
/// Semantics follow MRPT's CICP (icpClassic, icpLevenbergMarquardt) and its
/// [ICP] configuration section, so an ICP-SLAM config runs unchanged. The
/// arithmetic is rove's double precision unless Icp2dOptions::arithmetic is
/// Arithmetic::Mrpt, which reproduces MRPT 2.5.8's runs to the bit
/// (docs/conventions.md, "MRPT and PCL compatibility"):
///  - each iteration pairs every `corresponding_points_decimation`-th source
///    point (starting at a rotating offset) with its nearest target point if
///    their distance is below thresholdDist + thresholdAng·‖p − pivot‖, p the
///    source point in the target frame and pivot the current pose's position
///    (the sensor), so far points get proportionally wider gates;
///  - onlyUniqueRobust keeps, for each target point, only its closest pair;
///  - when an update moves the pose by no more than minAbsStep_trans (x and y)
///    and minAbsStep_rot, the gates shrink by ALFA and the decimation offset
///    advances (so every source point is used over the run); the run ends
///    when thresholdDist falls below smallestThresholdDist (Converged);
///  - after maxIterations the gates shrink by ALFA each further iteration
///    until they are below smallestThresholdDist (MRPT's tail), and the
///    result says MaxIterations.
///
/// Pose updates: Classic + point-to-point uses the closed form of
/// fit_rigid_2d (MRPT's se2_l2); Classic + point-to-line takes one
/// Gauss–Newton step of the linearized point-to-line cost (Censi, "An ICP
/// variant using a point-to-line metric", ICRA 2008, eq. 3); the
/// Levenberg–Marquardt algorithm minimizes ½Σρ(‖rᵢ‖²) over the current pairs
/// with damped Gauss–Newton steps and a robust kernel ρ (IRLS weights ρ').
///
/// Result: the pose as a Gaussian whose covariance is σ²·H⁻¹ from the final
/// Gauss–Newton Hessian H of the chosen metric (σ² = covariance_varPoints),
/// goodness (share of source points with a pair, MRPT's
/// correspondencesRatio), fitness (mean squared pair distance), iterations
/// and the termination reason. After convergence the geometry is checked:
/// the point-to-line information of the final pairs (normals of the target
/// at the matched points, rotation about the pairs' centroid scaled by their
/// RMS radius) must have λmin/λmax ≥ degeneracy_threshold, otherwise the
/// result is Degenerate (a corridor constrains nothing along its axis).

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/core/arithmetic.h"
#include "rove/core/config_section.h"
#include "rove/math/robust_kernel.h"
#include "rove/math/se2.h"
#include "rove/poses/pdf_sog.h"
#include "rove/registration/icp_target_2d.h"
#include "rove/registration/ransac_rigid.h"
#include "rove/registration/termination.h"

namespace rove {

/// Which ICP loop runs (MRPT's ICP_algorithm).
enum class IcpAlgorithm {
  /// icpClassic: closed form (or one GN step) per pairing.
  Classic,
  /// icpLevenbergMarquardt, MRPT's method: point-to-point only; per
  /// pairing, the gradient of the kernelized squared distances by finite
  /// differences of step Axy_aprox_derivatives (the x part from nearest-map-
  /// point distances), then damped steps on the fixed gradient with λ ÷ 10
  /// on a lower sum of squared distances and λ × 10 otherwise, until the
  /// step is below minAbsStep (at most 99 steps). The pairing gate widens
  /// with the distance from the target frame's origin (MRPT's pivot for this
  /// method), not from the current pose. With Arithmetic::Mrpt the gradient,
  /// its products and the 3×3 inverse are MRPT's float computations in
  /// MRPT's order of evaluation.
  LevenbergMarquardt,
  /// (icpRobustLevenbergMarquardt; rove) Levenberg–Marquardt on ½Σρ(r²) of
  /// the pairs with an analytic Jacobian, Nielsen's damping update and the
  /// kernel of use_kernel/kernel_rho or robust_kernel; point-to-point or
  /// point-to-line; gate widening from the current pose as icpClassic.
  RobustLevenbergMarquardt,
};

/// The error metric of a pair.
enum class Icp2dMetric {
  PointToPoint,  ///< ‖T·s − t‖² (MRPT)
  PointToLine,   ///< (nᵀ(T·s − t))², n the target normal (needs target normals)
};

/// How the covariance is computed (MRPT's ICP_covariance_method).
enum class IcpCovarianceMethod {
  LinearMse,          ///< icpCovLinealMSE: σ²·(Σ JᵀJ)⁻¹ of the unweighted pairs
  FiniteDifferences,  ///< icpCovFiniteDifferences: σ²·(Σ ρ'·JᵀJ)⁻¹ with the
                      ///< kernel weights of the final pairs (the Hessian an LM
                      ///< stage ends with; rove differentiates analytically)
};

/// Options of icp_2d (MRPT's [ICP] section; key names in parentheses).
struct Icp2dOptions {
  /// (ICP_algorithm: icpClassic | icpLevenbergMarquardt |
  /// icpRobustLevenbergMarquardt, or 0 | 1 | 2). Default Classic.
  IcpAlgorithm algorithm = IcpAlgorithm::Classic;
  /// (metric: point_to_point | point_to_line; rove). Default PointToPoint.
  Icp2dMetric metric = Icp2dMetric::PointToPoint;
  /// (arithmetic: double | mrpt; rove) Double: rove's double precision
  /// (centered closed-form fit, gates and distances in double). Mrpt:
  /// MRPT 2.5.8's arithmetic to the bit, so that a run reproduces MRPT's
  /// step by step: the option values MRPT reads with read_float rounded to
  /// float; both gates kept and shrunk in float; the source points moved in
  /// float, (x₀ + cos·x) − sin·y, and searched in the target's float tree
  /// (the target must be built with Arithmetic::Mrpt); icpClassic's fit is
  /// MRPT's tfest::se2_l2 in single precision (raw, uncentered sums in pair
  /// order, whose rounding grows with the distance from the origin);
  /// MRPT's LM in its float order; the goodness in float. Default Double.
  Arithmetic arithmetic = Arithmetic::Double;
  /// (ICP_covariance_method: icpCovLinealMSE | icpCovFiniteDifferences).
  /// Default FiniteDifferences (MRPT's default).
  IcpCovarianceMethod covariance_method = IcpCovarianceMethod::FiniteDifferences;
  /// (maxIterations) ≥ 1. Default 40.
  unsigned max_iterations = 40;
  /// (minAbsStep_trans) meters, ≥ 0. Default 1e-6.
  double min_abs_step_trans = 1e-6;
  /// (minAbsStep_rot) radians, ≥ 0. Default 1e-6.
  double min_abs_step_rot = 1e-6;
  /// (thresholdDist) initial pairing gate, meters, > 0. Default 0.75.
  double threshold_dist = 0.75;
  /// (thresholdAng_DEG in the file, degrees) gate widening per meter of
  /// distance from the pivot, radians here (m/m). ≥ 0. Default 0.15°.
  double threshold_ang = 0.15 * 3.14159265358979323846 / 180.0;
  /// (ALFA) gate shrink factor after convergence, in [0, 1). Default 0.5.
  double alfa = 0.5;
  /// (smallestThresholdDist) meters, > 0. Default 0.1.
  double smallest_threshold_dist = 0.1;
  /// (onlyClosestCorrespondences) true: the nearest target point only;
  /// false: every target point inside the gate. Default true.
  bool only_closest_correspondences = true;
  /// (onlyUniqueRobust) each target point keeps only its closest pair.
  /// Default false.
  bool only_unique_robust = false;
  /// (corresponding_points_decimation) use 1 source point in this many, ≥ 1.
  /// Default 5.
  unsigned corresponding_points_decimation = 5;
  /// (covariance_varPoints) σ² of a point coordinate, m², > 0. Default 0.02².
  double covariance_var_points = 0.02 * 0.02;
  /// (skip_cov_calculation) report a zero covariance. Default false.
  bool skip_cov_calculation = false;
  /// (use_kernel, kernel_rho) LM only. MRPT's method: the squared distances
  /// are kernelized as K(x²) = x²/(x²+ρ²) in its gradient when true. Robust
  /// LM: the Cauchy kernel of scale kernel_rho (meters) when true (the same
  /// family), plain least squares when false. Default true, 0.07.
  bool use_kernel = true;
  double kernel_rho = 0.07;
  /// (robust_kernel; rove) overrides use_kernel/kernel_rho when set, e.g.
  /// "huber:0.05" (parameter in meters).
  std::optional<RobustKernel> robust_kernel;
  /// (LM_initial_lambda) LM only, > 0. Default 1e-4. MRPT's method: the
  /// initial λ of each pairing (diagonal × (1 + λ)); robust LM: the initial
  /// damping relative to the largest diagonal entry of the Hessian.
  double lm_initial_lambda = 1e-4;
  /// (Axy_aprox_derivatives) MRPT's LM only: the finite-difference step of
  /// its gradient, meters, > 0. Default 0.05.
  double axy_aprox_derivatives = 0.05;
  /// (LM_inner_iterations; rove) robust LM only: damped steps per pairing,
  /// ≥ 1. Default 5.
  unsigned lm_inner_iterations = 5;
  /// (doRANSAC) after convergence, run ransac_rigid_2d on the final pairs
  /// and return its sum of Gaussians in Icp2dResult::sog. Default false.
  bool do_ransac = false;
  /// (ransac_minSetSize, ransac_maxSetSize, ransac_nSimulations,
  /// ransac_mahalanobisDistanceThreshold, normalizationStd,
  /// ransac_fuseByCorrsMatch, ransac_fuseMaxDiffXY, ransac_fuseMaxDiffPhi_DEG)
  RansacRigid2dOptions ransac;
  /// (degeneracy_threshold; rove) smallest accepted λmin/λmax of the
  /// normalized point-to-line information of the final pairs; 0 disables
  /// the check. In [0, 1). Default 0.01.
  double degeneracy_threshold = 0.01;
  /// (normal_neighbors; rove) neighbours for the target normals the
  /// degeneracy check fits at matched points when the target has none, ≥ 3.
  /// Default 5.
  unsigned normal_neighbors = 5;
  /// (num_threads; rove) threads for pairing and accumulation; results are
  /// identical for any value. 1 to kMaxThreads (rove/core/parallel.h), 0
  /// for all hardware threads. Default 1.
  int num_threads = 1;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;

  /// An [ICP] section of an MRPT-style INI file over the defaults. MRPT's
  /// keys that rove accepts without using them (skip_quality_calculation)
  /// are read and ignored. Strict: a key of the section that is not an ICP
  /// option, a malformed value, or options that check() rejects are a
  /// ConfigError naming the file, section and key.
  static Icp2dOptions from_config(const ConfigSection& section);
};


/// Result of icp_2d.
struct Icp2dResult {
  /// Pose of the source frame in the target frame.
  SE2d T_target_source;
  /// Its covariance over the right tangent (ρx, ρy, θ) (zero when
  /// skip_cov_calculation or the run did not converge).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  /// Sum of Gaussians from the RANSAC step (empty unless do_ransac).
  Pose2SOG sog;
  /// Share of source points with a pair at the last pairing, in [0, 1]:
  /// MRPT's goodness (correspondencesRatio), decimation × paired / N.
  double goodness = 0.0;
  /// Mean squared distance of the last pairs, m² (point-to-point).
  double fitness = 0.0;
  /// Pairs of the last pairing.
  std::size_t correspondences = 0;
  /// Iterations run (pairings), MRPT's nIterations.
  unsigned iterations = 0;
  /// The pairing gate thresholdDist when the run ended, meters.
  double final_threshold_dist = 0.0;
  /// λmin/λmax of the normalized point-to-line information of the last
  /// pairs (1: isotropic constraints, 0: a free direction); NaN if not
  /// computed (check disabled or too few pairs).
  double conditioning = 0.0;
  /// Why the run stopped.
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;
  /// True only when termination is Converged (succeeded()).
  bool ok() const noexcept { return succeeded(termination); }
};

/// Registers `source` (meters, source frame; non-finite points are skipped)
/// against `target` starting from `initial_T_target_source`.
/// Preconditions (InvalidArgument): options.check() passes; the target was
/// built with the same arithmetic; point-to-line needs target.has_normals().
/// Empty inputs give InvalidInput.
Icp2dResult icp_2d(const IcpTarget2D& target, std::span<const Eigen::Vector2d> source,
                   const SE2d& initial_T_target_source, const Icp2dOptions& options = {});

}  // namespace rove
