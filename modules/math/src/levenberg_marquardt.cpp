#include "rove/math/levenberg_marquardt.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {

std::string_view to_string(LmTermination t) {
  switch (t) {
    case LmTermination::GradientTolerance: return "GradientTolerance";
    case LmTermination::StepTolerance: return "StepTolerance";
    case LmTermination::CostTolerance: return "CostTolerance";
    case LmTermination::MaxIterations: return "MaxIterations";
    case LmTermination::NumericFailure: return "NumericFailure";
  }
  ROVE_CHECK_MSG(false, "invalid LmTermination value {}", static_cast<int>(t));
  return {};
}

namespace {

/// Index of the first non-finite entry (column-major for matrices), or -1.
Eigen::Index first_non_finite(const Eigen::MatrixXd& m) {
  const Eigen::Index n = m.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(m.data()[i])) return i;
  }
  return -1;
}

Eigen::VectorXd evaluate_checked(const ResidualFunction& residual, const Eigen::VectorXd& x,
                                 Eigen::Index expected_size) {
  Eigen::VectorXd r = residual(x);
  ROVE_CHECK_MSG(r.size() == expected_size,
                 "the residual function returned {} components, earlier {}", r.size(),
                 expected_size);
  return r;
}

double default_relative_step(NumericDiffScheme scheme) {
  const double eps = std::numeric_limits<double>::epsilon();
  return scheme == NumericDiffScheme::Forward ? std::sqrt(eps) : std::cbrt(eps);
}

void check_options(const LmOptions& o) {
  ROVE_CHECK_GE(o.max_iterations, 0);
  ROVE_CHECK_MSG(std::isfinite(o.initial_lambda) && o.initial_lambda > 0.0,
                 "initial_lambda must be finite and > 0, got {}", o.initial_lambda);
  ROVE_CHECK_MSG(std::isfinite(o.gradient_tolerance) && o.gradient_tolerance >= 0.0,
                 "gradient_tolerance must be finite and >= 0, got {}", o.gradient_tolerance);
  ROVE_CHECK_MSG(std::isfinite(o.step_tolerance) && o.step_tolerance >= 0.0,
                 "step_tolerance must be finite and >= 0, got {}", o.step_tolerance);
  ROVE_CHECK_MSG(std::isfinite(o.cost_change_tolerance) && o.cost_change_tolerance >= 0.0,
                 "cost_change_tolerance must be finite and >= 0, got {}",
                 o.cost_change_tolerance);
  if (o.numeric_relative_step) {
    ROVE_CHECK_MSG(std::isfinite(*o.numeric_relative_step) && *o.numeric_relative_step > 0.0,
                   "numeric_relative_step must be finite and > 0, got {}",
                   *o.numeric_relative_step);
  }
}

/// Computes J at x (given r(x)); `numeric` only changes the failure text.
using JacobianAt = std::function<Eigen::MatrixXd(const Eigen::VectorXd&, const Eigen::VectorXd&)>;

/// Damping diagonal D: diag(JᵀJ) floored (Marquardt) or ones (Levenberg).
Eigen::VectorXd damping_diagonal(const Eigen::MatrixXd& A, LmDamping damping) {
  if (damping == LmDamping::Levenberg) return Eigen::VectorXd::Ones(A.rows());
  const Eigen::VectorXd diag = A.diagonal();
  const double top = diag.maxCoeff();
  // A parameter the residuals do not depend on has a zero column in J; a
  // floor keeps (A + μD) positive definite so that it is simply not moved.
  const double floor = top > 0.0 ? 1e-12 * top : 1.0;
  return diag.cwiseMax(floor);
}

LmResult solve(const ResidualFunction& residual, const JacobianAt& jacobian_at, bool numeric,
               const Eigen::VectorXd& x0, const LmOptions& o) {
  check_options(o);
  ROVE_CHECK_GT(x0.size(), Eigen::Index{0});
  ROVE_CHECK_FINITE(x0);
  const Eigen::Index n = x0.size();
  const char* jac_name = numeric ? "numeric Jacobian" : "Jacobian";

  LmResult result;
  result.x = x0;
  result.gradient_max_norm = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd r = residual(x0);
  ++result.residual_evaluations;
  const Eigen::Index m = r.size();
  ROVE_CHECK_MSG(m > 0, "the residual function returned an empty vector");
  if (const Eigen::Index bad = first_non_finite(r); bad >= 0) {
    result.initial_cost = result.final_cost = std::numeric_limits<double>::quiet_NaN();
    result.termination = LmTermination::NumericFailure;
    result.message = fmt::format("residual component {} = {} at the initial x", bad, r[bad]);
    return result;
  }
  double cost = 0.5 * r.squaredNorm();
  result.initial_cost = result.final_cost = cost;

  Eigen::MatrixXd A;
  Eigen::VectorXd g;
  Eigen::VectorXd D;
  // Evaluates J, A = JᵀJ, g = Jᵀr, D at the current x; false on non-finite J.
  auto linearize = [&](int iteration) {
    const Eigen::MatrixXd J = jacobian_at(result.x, r);
    ROVE_CHECK_MSG(J.rows() == m && J.cols() == n, "the {} is {}x{}, expected {}x{}", jac_name,
                   J.rows(), J.cols(), m, n);
    if (const Eigen::Index bad = first_non_finite(J); bad >= 0) {
      result.termination = LmTermination::NumericFailure;
      result.message = fmt::format("{} entry ({}, {}) = {} at iteration {}", jac_name, bad % m,
                                   bad / m, J.data()[bad], iteration);
      return false;
    }
    A.noalias() = J.transpose() * J;
    g.noalias() = J.transpose() * r;
    D = damping_diagonal(A, o.damping);
    result.gradient_max_norm = g.lpNorm<Eigen::Infinity>();
    return true;
  };

  if (!linearize(0)) return result;
  if (result.gradient_max_norm <= o.gradient_tolerance) {
    result.termination = LmTermination::GradientTolerance;
    result.message = fmt::format("gradient max-norm {:.3e} <= {:.3e} at the initial x",
                                 result.gradient_max_norm, o.gradient_tolerance);
    return result;
  }

  // MNT Algorithm 3.16: μ₀ = τ·max(aᵢᵢ) for D = I; with D = diag(A) the
  // same relative damping is μ₀ = τ.
  double mu = o.damping == LmDamping::Levenberg ? o.initial_lambda * A.diagonal().maxCoeff()
                                                : o.initial_lambda;
  double nu = 2.0;
  int rejected_non_finite = 0;

  auto reject = [&] {
    mu *= nu;
    nu *= 2.0;
  };

  for (int k = 1; k <= o.max_iterations; ++k) {
    result.iterations = k;
    Eigen::MatrixXd M = A;
    M.diagonal() += mu * D;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
    Eigen::VectorXd h;
    if (ldlt.info() == Eigen::Success && ldlt.isPositive()) h = ldlt.solve(-g);
    if (h.size() != n || !h.allFinite()) {
      reject();
      result.cost_history.push_back(cost);
      if (!std::isfinite(mu)) {
        result.termination = LmTermination::NumericFailure;
        result.message = fmt::format(
            "the damped normal equations could not be solved (damping overflowed) at "
            "iteration {}",
            k);
        return result;
      }
      continue;
    }
    // Step test of MNT Algorithm 3.16: ‖h‖ ≤ ε₂(‖x‖ + ε₂).
    if (h.norm() <= o.step_tolerance * (result.x.norm() + o.step_tolerance)) {
      result.cost_history.push_back(cost);
      result.termination = LmTermination::StepTolerance;
      result.message = fmt::format(
          "step norm {:.3e} <= {:.3e} relative to |x| = {:.3e}{}", h.norm(), o.step_tolerance,
          result.x.norm(),
          rejected_non_finite > 0
              ? fmt::format(" ({} trial points had non-finite residuals)", rejected_non_finite)
              : std::string());
      return result;
    }

    const Eigen::VectorXd x_new = result.x + h;
    Eigen::VectorXd r_new = evaluate_checked(residual, x_new, m);
    ++result.residual_evaluations;
    const bool finite = r_new.allFinite();
    if (!finite) ++rejected_non_finite;
    const double cost_new = finite ? 0.5 * r_new.squaredNorm()
                                   : std::numeric_limits<double>::infinity();
    // L(0) − L(h) = ½ hᵀ(μDh − g): the decrease the linear model predicts.
    const double predicted = 0.5 * h.dot(mu * D.cwiseProduct(h) - g);
    const double actual = cost - cost_new;
    if (finite && predicted > 0.0 && actual > 0.0) {
      const double rho = actual / predicted;  // gain ratio ϱ
      const double previous_cost = cost;
      result.x = x_new;
      r = std::move(r_new);
      cost = cost_new;
      result.final_cost = cost;
      ++result.accepted_steps;
      result.cost_history.push_back(cost);
      if (!linearize(k)) return result;
      // Nielsen's update of μ (MNT Sec. 3.2).
      const double t = 2.0 * rho - 1.0;
      mu *= std::max(1.0 / 3.0, 1.0 - t * t * t);
      nu = 2.0;
      if (result.gradient_max_norm <= o.gradient_tolerance) {
        result.termination = LmTermination::GradientTolerance;
        result.message = fmt::format("gradient max-norm {:.3e} <= {:.3e} after {} iterations",
                                     result.gradient_max_norm, o.gradient_tolerance, k);
        return result;
      }
      if (actual <= o.cost_change_tolerance * previous_cost) {
        result.termination = LmTermination::CostTolerance;
        result.message = fmt::format("cost decrease {:.3e} <= {:.3e} x cost {:.6e}", actual,
                                     o.cost_change_tolerance, previous_cost);
        return result;
      }
    } else {
      reject();
      result.cost_history.push_back(cost);
      if (!std::isfinite(mu)) {
        result.termination = LmTermination::NumericFailure;
        result.message = fmt::format(
            "damping overflowed at iteration {}: no step lowers the cost{}", k,
            rejected_non_finite > 0
                ? fmt::format(" ({} trial points had non-finite residuals)", rejected_non_finite)
                : std::string());
        return result;
      }
    }
  }
  result.termination = LmTermination::MaxIterations;
  result.message = fmt::format("reached max_iterations = {}; cost {:.6e}, gradient max-norm {:.3e}",
                               o.max_iterations, cost, result.gradient_max_norm);
  return result;
}

}  // namespace

Eigen::MatrixXd numeric_jacobian(const ResidualFunction& residual, const Eigen::VectorXd& x,
                                 const Eigen::VectorXd& r_at_x, NumericDiffScheme scheme,
                                 double relative_step) {
  ROVE_CHECK_FINITE(x);
  ROVE_CHECK_MSG(std::isfinite(relative_step) && relative_step > 0.0,
                 "relative_step must be finite and > 0, got {}", relative_step);
  const Eigen::Index m = r_at_x.size();
  Eigen::MatrixXd J(m, x.size());
  Eigen::VectorXd xp = x;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double xj = x[j];
    const double h = xj == 0.0 ? relative_step : relative_step * std::abs(xj);
    // Differences of the representable points, not h itself, so that the
    // divisor matches the actual perturbation.
    const double plus = xj + h;
    xp[j] = plus;
    const Eigen::VectorXd r_plus = evaluate_checked(residual, xp, m);
    if (scheme == NumericDiffScheme::Forward) {
      J.col(j) = (r_plus - r_at_x) / (plus - xj);
    } else {
      const double minus = xj - h;
      xp[j] = minus;
      const Eigen::VectorXd r_minus = evaluate_checked(residual, xp, m);
      J.col(j) = (r_plus - r_minus) / (plus - minus);
    }
    xp[j] = xj;
  }
  return J;
}

LmResult levenberg_marquardt(const ResidualFunction& residual, const JacobianFunction& jacobian,
                             const Eigen::VectorXd& x0, const LmOptions& options) {
  ROVE_CHECK_MSG(static_cast<bool>(residual), "residual function is empty");
  ROVE_CHECK_MSG(static_cast<bool>(jacobian), "Jacobian function is empty");
  return solve(
      residual,
      [&jacobian](const Eigen::VectorXd& x, const Eigen::VectorXd&) { return jacobian(x); },
      false, x0, options);
}

LmResult levenberg_marquardt(const ResidualFunction& residual, const Eigen::VectorXd& x0,
                             const LmOptions& options) {
  ROVE_CHECK_MSG(static_cast<bool>(residual), "residual function is empty");
  check_options(options);
  const double step =
      options.numeric_relative_step.value_or(default_relative_step(options.numeric_scheme));
  int extra_evaluations = 0;
  const ResidualFunction counted = [&](const Eigen::VectorXd& x) {
    ++extra_evaluations;
    return residual(x);
  };
  LmResult result = solve(
      residual,
      [&](const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
        return numeric_jacobian(counted, x, r, options.numeric_scheme, step);
      },
      true, x0, options);
  result.residual_evaluations += extra_evaluations;
  return result;
}

}  // namespace rove
