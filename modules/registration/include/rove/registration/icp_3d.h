#pragma once
/// \file
/// 3D ICP family: point-to-point, point-to-plane and Generalized-ICP between
/// two PreparedCloud3D, from an initial T_target_source.
///
/// Each iteration pairs every source point with its nearest target point
/// within max_correspondence_distance, linearizes the cost around the
/// current pose with a right perturbation T·exp(δ), δ = (ρ, ω) ∈ se(3), and
/// takes a Levenberg–Marquardt step on the fixed pairs: the damping, scaled
/// to the Hessian and updated by Nielsen's rule, is raised until the cost of
/// those pairs decreases. Costs, with
/// qᵢ = T·sᵢ − tᵢ:
///  - point-to-point: Σ ρ(‖qᵢ‖²) (Besl & McKay 1992);
///  - point-to-plane: Σ ρ((nᵢᵀqᵢ)²), nᵢ the target normal (Chen & Medioni
///    1992);
///  - GICP: Σ ρ(qᵢᵀ (C_tᵢ + R C_sᵢ Rᵀ)⁻¹ qᵢ) (Segal et al. 2009, eq. 2),
///    the combined covariance re-evaluated at each linearization.
/// The run converges when a step changes the rotation by less than
/// rotation_epsilon and the translation by less than translation_epsilon
/// (small_gicp's criterion). When no damped step lowers the cost, the run
/// converges only if the undamped step is itself within those tolerances or
/// the decrease it predicts is below 1e-4 of the cost (after Ceres' function
/// tolerance: stationary within the model's error); otherwise it ends Stalled at the last estimate that lowered the cost
/// (GICP's Hessian holds the combined covariances fixed, so its step can
/// miss the cost that re-evaluates them).
///
/// The covariance of the result is H⁻¹ (GICP: the information is already in
/// m⁻²) or σ²·H⁻¹ (point-to-point, point-to-plane; σ² = point_variance) from
/// the final Gauss–Newton Hessian, expressed over (x, y, z, yaw, pitch,
/// roll). After convergence the point-to-plane information of the final pairs
/// (about their centroid, rotation scaled by their RMS radius) must have
/// λmin/λmax ≥ degeneracy_threshold; a single plane or a straight tunnel
/// gives Degenerate instead of Converged.

#include <cstddef>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/math/robust_kernel.h"
#include "rove/math/se3.h"
#include "rove/registration/prepared_cloud.h"
#include "rove/registration/termination.h"

namespace rove {

/// The cost of icp_3d.
enum class Icp3dMethod {
  PointToPoint,  ///< needs nothing beyond the points
  PointToPlane,  ///< needs target normals
  Gicp,          ///< needs target and source covariances
};

/// Options of icp_3d.
struct Icp3dOptions {
  /// Cost. Default Gicp.
  Icp3dMethod method = Icp3dMethod::Gicp;
  /// Pairing gate, meters, > 0. Default 1.0.
  double max_correspondence_distance = 1.0;
  /// Iteration cap (linearizations), ≥ 1. Default 64.
  int max_iterations = 64;
  /// Convergence: rotation change of a step, radians, ≥ 0. Default 0.1°.
  double rotation_epsilon = 0.1 * 3.14159265358979323846 / 180.0;
  /// Convergence: translation change of a step, meters, ≥ 0. Default 1e-3.
  double translation_epsilon = 1e-3;
  /// Robust kernel on the (whitened) residual. Default none.
  RobustKernel kernel;
  /// Initial LM damping relative to the largest diagonal entry of the first
  /// Hessian (μ₀ = τ·max diag H, Madsen et al. 2004), ≥ 0. Default 1e-6.
  double lm_initial_lambda = 1e-6;
  /// Damped steps tried per linearization before the run ends Stalled (or
  /// Converged, see above), ≥ 1. Default 30 (Nielsen's doubling reaches
  /// 2^465 × the first damping, a gradient step of negligible length).
  int lm_max_tries = 30;
  /// σ² of a point coordinate for the covariance of point-to-point and
  /// point-to-plane results, m², > 0. Default 0.01².
  double point_variance = 0.01 * 0.01;
  /// Fewest pairs to take a step (below: TooFewCorrespondences), ≥ 6.
  /// Default 6.
  std::size_t min_correspondences = 6;
  /// Smallest accepted λmin/λmax of the normalized point-to-plane
  /// information; 0 disables the check. In [0, 1). Default 1e-3.
  double degeneracy_threshold = 1e-3;
  /// Neighbours to fit a target normal at a matched point when the target
  /// has neither normals nor covariances (degeneracy check), ≥ 3. Default 10.
  std::size_t normal_neighbors = 10;
  /// Threads; the result is identical for any value. 1 to kMaxThreads
  /// (rove/core/parallel.h), 0 for all hardware threads. Default 1.
  int num_threads = 1;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Result of icp_3d.
struct Icp3dResult {
  /// Pose of the source frame in the target frame (p_target =
  /// T_target_source·p_source).
  SE3d T_target_source;
  /// Its covariance over the right tangent (ρ, ω): σ²-scaled inverse of
  /// `information` (zero when the run produced none).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  /// Gauss–Newton Hessian at the result in the right tangent (ρ, ω).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  /// Share of source points paired at the last linearization, [0, 1].
  double goodness = 0.0;
  /// Mean squared Euclidean distance of the last pairs, m².
  double fitness = 0.0;
  /// Cost of the last pairs at the result (½Σρ).
  double final_cost = 0.0;
  /// Pairs at the last linearization.
  std::size_t correspondences = 0;
  /// Linearizations done.
  int iterations = 0;
  /// λmin/λmax of the normalized point-to-plane information (NaN if not
  /// computed).
  double conditioning = 0.0;
  /// Why the run stopped.
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;
  /// True only when termination is Converged (succeeded()).
  bool ok() const noexcept { return succeeded(termination); }
};

/// Registers `source` onto `target` from `initial_T_target_source`.
/// Preconditions (InvalidArgument): options.check(); point-to-plane needs
/// target.has_normals(); GICP needs covariances on both clouds. Empty clouds give InvalidInput.
Icp3dResult icp_3d(const PreparedCloud3D& target, const PreparedCloud3D& source,
                   const SE3d& initial_T_target_source, const Icp3dOptions& options = {});

}  // namespace rove
