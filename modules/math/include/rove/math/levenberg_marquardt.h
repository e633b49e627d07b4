#pragma once
/// \file
/// Dense Levenberg–Marquardt: minimizes F(x) = ½‖r(x)‖² over x ∈ ℝⁿ, with
/// r : ℝⁿ → ℝᵐ. Implements Algorithm 3.16 of Madsen, Nielsen, Tingleff,
/// "Methods for non-linear least squares problems", 2nd ed., IMM DTU, 2004:
/// damped Gauss–Newton steps (JᵀJ + μD) h = −Jᵀr, the gain ratio
/// ϱ = (F(x) − F(x+h)) / (L(0) − L(h)) of the linear model L, and Nielsen's
/// damping update (their Section 3.2): on acceptance
/// μ ← μ·max(⅓, 1 − (2ϱ − 1)³), ν ← 2; on rejection μ ← μν, ν ← 2ν.
/// D is Marquardt's scaling diag(JᵀJ) by default, or the identity
/// (Levenberg) as an option. Steps are accepted only when they lower F, so
/// the cost never increases.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace rove {

/// The residual vector r(x) (size m ≥ 1, the same at every x).
using ResidualFunction = std::function<Eigen::VectorXd(const Eigen::VectorXd& x)>;
/// The Jacobian ∂r/∂x (m × n) at x.
using JacobianFunction = std::function<Eigen::MatrixXd(const Eigen::VectorXd& x)>;

/// Finite-difference scheme for numeric Jacobians.
enum class NumericDiffScheme {
  Forward,  ///< (r(x + hⱼeⱼ) − r(x)) / hⱼ: n extra residual evaluations
  Central,  ///< (r(x + hⱼeⱼ) − r(x − hⱼeⱼ)) / 2hⱼ: 2n evaluations, more accurate
};

/// Damping matrix D in (JᵀJ + μD) h = −g.
enum class LmDamping {
  Marquardt,  ///< D = diag(JᵀJ) (entries floored at 1e-12·max): scale invariant
  Levenberg,  ///< D = I
};

/// Options of levenberg_marquardt(). Defaults are documented per field.
struct LmOptions {
  /// Most iterations (step computations, accepted or not), ≥ 0. Default 100.
  int max_iterations = 100;
  /// τ, the initial damping relative to the problem's curvature (MNT
  /// Sec. 3.2): μ₀ = τ·max(diag(JᵀJ)) with Levenberg damping, μ₀ = τ with
  /// Marquardt damping (D already carries the scale). > 0. Default 1e-3.
  double initial_lambda = 1e-3;
  /// Stop when ‖Jᵀr‖∞ ≤ this (MNT ε₁). ≥ 0. Default 1e-10.
  double gradient_tolerance = 1e-10;
  /// Stop when ‖h‖ ≤ this·(‖x‖ + this) (MNT ε₂). ≥ 0. Default 1e-10.
  double step_tolerance = 1e-10;
  /// Stop when an accepted step lowers F by ≤ this·F. ≥ 0. Default 1e-12.
  double cost_change_tolerance = 1e-12;
  /// Damping matrix. Default Marquardt.
  LmDamping damping = LmDamping::Marquardt;
  /// Scheme for numeric Jacobians (overload without a JacobianFunction).
  NumericDiffScheme numeric_scheme = NumericDiffScheme::Central;
  /// Relative finite-difference step: hⱼ = step·|xⱼ| (step itself when
  /// xⱼ = 0). Empty selects √ε ≈ 1.5e-8 for Forward and ∛ε ≈ 6.1e-6 for
  /// Central (ε = machine epsilon), which balance truncation and rounding.
  std::optional<double> numeric_relative_step;
};

/// Why levenberg_marquardt() stopped.
enum class LmTermination {
  GradientTolerance,  ///< ‖Jᵀr‖∞ ≤ gradient_tolerance
  StepTolerance,      ///< the step became negligible relative to x
  CostTolerance,      ///< an accepted step lowered F by ≤ cost_change_tolerance·F
  MaxIterations,      ///< max_iterations reached
  NumericFailure,     ///< residuals or Jacobian not finite at an accepted x
                      ///< (the message names the component), or the damped
                      ///< system could not be solved
};

/// Name of a termination reason ("GradientTolerance", ...).
std::string_view to_string(LmTermination t);

/// Outcome of levenberg_marquardt().
struct LmResult {
  /// Best x found (the last accepted iterate).
  Eigen::VectorXd x;
  /// F(x₀) = ½‖r(x₀)‖² (NaN if r(x₀) was not finite).
  double initial_cost = 0.0;
  /// F(x) at the returned x.
  double final_cost = 0.0;
  /// ‖Jᵀr‖∞ at the returned x (NaN if never computed).
  double gradient_max_norm = 0.0;
  /// Iterations done (steps computed, accepted or rejected).
  int iterations = 0;
  /// Steps accepted.
  int accepted_steps = 0;
  /// Residual evaluations, including those of numeric Jacobians.
  int residual_evaluations = 0;
  /// F after each iteration (one entry per iteration; non-increasing).
  std::vector<double> cost_history;
  /// Why the solver stopped.
  LmTermination termination = LmTermination::MaxIterations;
  /// One line explaining the termination.
  std::string message;
};

/// Minimizes ½‖r(x)‖² from x0 with the analytic Jacobian `jacobian`.
/// Trial points where r is not finite are rejected like cost increases.
/// Preconditions (InvalidArgument): x0 non-empty and finite, options valid.
/// A residual function whose size changes, or a Jacobian of the wrong shape,
/// also throws InvalidArgument.
LmResult levenberg_marquardt(const ResidualFunction& residual, const JacobianFunction& jacobian,
                             const Eigen::VectorXd& x0, const LmOptions& options = {});

/// As above with a numeric Jacobian (options.numeric_scheme and
/// numeric_relative_step).
LmResult levenberg_marquardt(const ResidualFunction& residual, const Eigen::VectorXd& x0,
                             const LmOptions& options = {});

/// Numeric Jacobian of `residual` at x by finite differences (the one the
/// solver uses). `r_at_x` is r(x), reused by the forward scheme.
/// Preconditions: x finite; relative_step finite and > 0.
Eigen::MatrixXd numeric_jacobian(const ResidualFunction& residual, const Eigen::VectorXd& x,
                                 const Eigen::VectorXd& r_at_x, NumericDiffScheme scheme,
                                 double relative_step);

}  // namespace rove
