#pragma once
/// \file
/// Scan-to-grid matching by nonlinear least squares: the pose T_grid_robot
/// that puts the points of a scan on the occupied cells of a
/// ProbabilityGrid, near a prior pose. As Cartographer's scan matcher
/// (Hess et al. 2016, Sec. IV-C, Eq. (CS)), the cost is
///
///   Σᵢ (w_occ/√N · (1 − M_smooth(T·pᵢ)))² + w_t²·‖t − t₀‖² + w_r²·(θ − θ₀)²
///
/// with M_smooth the bicubic (Catmull–Rom) interpolation of the cells'
/// probabilities (unknown cells read as ProbabilityGrid::kMinProbability),
/// T = (t, θ) and the prior (t₀, θ₀). It is minimized by
/// Levenberg–Marquardt on (x, y, θ) with analytic Jacobians. The basin is a
/// cell or two wide: the initial pose must be that close.

#include <span>
#include <string>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/math/se2.h"
#include "rove/registration/termination.h"
#include "rove/slam/probability_grid.h"

namespace rove {

/// Options of match_scan_to_grid (keys in parentheses, each with the
/// loader's prefix).
struct GridScanMatcherOptions {
  /// (occupied_space_weight) w_occ, > 0. Default 1.
  double occupied_space_weight = 1.0;
  /// (translation_weight) w_t, per meter, >= 0. Default 10.
  double translation_weight = 10.0;
  /// (rotation_weight) w_r, per radian, >= 0. Default 40.
  double rotation_weight = 40.0;
  /// (max_iterations) Levenberg–Marquardt iterations, >= 1. Default 20.
  int max_iterations = 20;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The keys above, each prefixed with `prefix`, from `section` over
  /// `defaults`. ConfigError (file, section, key) for a malformed or
  /// out-of-range value.
  static GridScanMatcherOptions from_config(const ConfigSection& section, std::string_view prefix,
                                            const GridScanMatcherOptions& defaults);
};

/// Result of match_scan_to_grid.
struct GridScanMatchResult {
  /// The estimate (the prior when nothing could be matched).
  SE2d T_grid_robot;
  /// Cost (see the file comment) at the prior and at the estimate.
  double initial_cost = 0.0;
  double final_cost = 0.0;
  /// Mean probability of the cells holding the transformed points, in
  /// [kMinProbability, kMaxProbability]: how well the scan fits the grid.
  double score = 0.0;
  /// Iterations run.
  int iterations = 0;
  /// Converged (a step below 1e-6 of a cell / radian, or no decrease
  /// possible at a minimum), MaxIterations, or InvalidInput (no finite point).
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;
  /// True when termination is Converged.
  bool ok() const noexcept { return succeeded(termination); }
};

/// Matches `points_robot` (robot frame, meters; non-finite points skipped)
/// against `grid` from `prior_T_grid_robot` (also the initial guess).
/// Precondition (InvalidArgument): options.check().
GridScanMatchResult match_scan_to_grid(const ProbabilityGrid& grid,
                                       std::span<const Eigen::Vector2d> points_robot,
                                       const SE2d& prior_T_grid_robot,
                                       const GridScanMatcherOptions& options = {});

/// Mean of the cells' probabilities at `points_robot` moved by T_grid_robot
/// (nearest cell, unknown as kMinProbability); kMinProbability when no
/// point is finite.
double grid_match_score(const ProbabilityGrid& grid, std::span<const Eigen::Vector2d> points_robot,
                        const SE2d& T_grid_robot);

/// Options of correlative_search_2d.
struct CorrelativeSearchOptions {
  /// Half-width of the translation window, meters, >= 0 (searched in steps
  /// of one cell). Default 0 (rotation only).
  double linear_window = 0.0;
  /// Half-width of the rotation window, radians, in [0, π].
  double angular_window = 15.0 * 3.14159265358979323846 / 180.0;
  /// Rotation step, radians, > 0.
  double angular_step = 0.5 * 3.14159265358979323846 / 180.0;
  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Exhaustive correlative scan matching (Olson, "Real-time correlative
/// scan matching", ICRA 2009): of the poses of the window around
/// `initial_T_grid_robot` (whole cells, rotation steps), the one whose
/// points fall on the most likely occupied cells (grid_match_score), ties
/// going to the pose nearest the initial one. For predictions whose
/// rotation may be off by more than the matcher's basin (a robot turning
/// fast). Precondition (InvalidArgument): options.check().
SE2d correlative_search_2d(const ProbabilityGrid& grid, std::span<const Eigen::Vector2d> points_robot,
                           const SE2d& initial_T_grid_robot,
                           const CorrelativeSearchOptions& options = {});

/// The bicubic (Catmull–Rom) interpolation of the cells' probabilities at
/// point p (grid frame, meters) and its gradient (per meter), exactly as
/// the matcher evaluates them (cell centers are the interpolation nodes).
double interpolate_probability(const ProbabilityGrid& grid, const Eigen::Vector2d& p,
                               Eigen::Vector2d* gradient = nullptr);

}  // namespace rove
