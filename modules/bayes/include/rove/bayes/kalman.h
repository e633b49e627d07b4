#pragma once
/// \file
/// Extended and iterated extended Kalman filters over user-supplied models.
///
/// A state is a mean and a covariance (GaussianState, dynamic size). The
/// user writes a process model and an observation model as small structs
/// (the KalmanProcessModel and KalmanObservationModel concepts):
///
///   struct Motion {                                   // x_{k+1} = f(x_k) + w, w ~ N(0, Q)
///     Eigen::VectorXd transition(const Eigen::VectorXd& x) const;           // f(x)
///     Eigen::MatrixXd process_noise(const Eigen::VectorXd& x) const;        // Q at x
///     Eigen::MatrixXd transition_jacobian(const Eigen::VectorXd& x) const;  // optional: ∂f/∂x
///   };
///   struct Sensor {                                   // z = h(x) + v, v ~ N(0, R)
///     Eigen::VectorXd observe(const Eigen::VectorXd& x) const;              // h(x)
///     Eigen::MatrixXd observation_noise(const Eigen::VectorXd& x) const;    // R at x
///     Eigen::MatrixXd observation_jacobian(const Eigen::VectorXd& x) const; // optional: ∂h/∂x
///     Eigen::VectorXd innovation(const Eigen::VectorXd& z,
///                                const Eigen::VectorXd& z_pred) const;      // optional: z ⊖ ẑ
///   };
///
/// The Jacobians are the model's own (KalmanJacobians::Analytic) or central
/// differences (Numeric). `innovation` lets a model wrap angles (a bearing
/// residual of 359° is −1°); without it the innovation is z − ẑ. State
/// components listed in KalmanOptions::angle_states are wrapped to (−π, π]
/// in means and in differences.
///
/// Updates use the Joseph form P⁺ = (I − KH) P (I − KH)ᵀ + K R Kᵀ (Bucy &
/// Joseph 1968), which stays symmetric positive semi-definite when rounding
/// makes K slightly suboptimal, where the short form (I − KH) P does not.
/// The innovation ν, its covariance S = H P Hᵀ + R and the normalized
/// innovation squared NIS = νᵀ S⁻¹ ν are returned with every update; a gate
/// rejects a measurement whose NIS exceeds the χ² quantile of the chosen
/// probability (Bar-Shalom, Li & Kirubarajan, "Estimation with Applications
/// to Tracking and Navigation", 2001, §5.4; consistency tests §5.4.2).

#include <concepts>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "rove/bayes/detail/numeric_jacobian.h"

namespace rove {

/// A Gaussian belief: mean and covariance (n and n × n).
struct GaussianState {
  /// Mean.
  Eigen::VectorXd mean;
  /// Covariance, symmetric positive semi-definite.
  Eigen::MatrixXd covariance;
};

/// Where the filters take their Jacobians from.
enum class KalmanJacobians : std::uint8_t {
  /// The model's transition_jacobian / observation_jacobian (required).
  Analytic,
  /// Central differences of the model's functions.
  Numeric,
};

/// Options of ekf_predict, ekf_update and iekf_update.
struct KalmanOptions {
  /// Jacobian source. Default Analytic.
  KalmanJacobians jacobians = KalmanJacobians::Analytic;
  /// Numeric Jacobians: the step for component j is
  /// numeric_step · max(1, |x_j|) (central differences, error O(step²)).
  /// In (0, 1). Default 1e-6.
  double numeric_step = 1e-6;
  /// State components that are angles (radians): wrapped to (−π, π] in the
  /// mean after predict and update, and in state differences.
  std::vector<int> angle_states;
  /// Mahalanobis gate: a measurement whose NIS exceeds
  /// chi_square_quantile(gate_probability, dim z) is rejected (the state is
  /// left unchanged). 0 disables the gate; else in (0, 1). Default 0.
  double gate_probability = 0.0;
  /// Iterated EKF: most linearizations, the first being the EKF's (≥ 1;
  /// 1 gives the EKF update). Default 20.
  int max_iterations = 20;
  /// Iterated EKF: converged when the step ‖x_{i+1} − x_i‖∞ ≤
  /// tolerance · (1 + ‖x_{i+1}‖∞) (> 0). Default 1e-9.
  double tolerance = 1e-9;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// How an update ended.
enum class KalmanTermination : std::uint8_t {
  /// EKF update applied.
  Updated,
  /// Iterated EKF converged and its update was applied.
  Converged,
  /// Iterated EKF reached max_iterations; the last iterate was applied.
  MaxIterations,
  /// The measurement failed the Mahalanobis gate; the state is unchanged.
  Gated,
  /// The innovation covariance was not positive definite; the state is
  /// unchanged.
  NotPositiveDefinite,
};

/// What an update did.
struct KalmanUpdateResult {
  /// How the update ended.
  KalmanTermination termination = KalmanTermination::Updated;
  /// One line (NIS, gate, iterations).
  std::string message;
  /// The posterior (the prior when Gated or NotPositiveDefinite).
  GaussianState posterior;
  /// Innovation ν = z ⊖ h(x̂) at the prior mean (dim z).
  Eigen::VectorXd innovation;
  /// Its covariance S = H P Hᵀ + R at the prior mean (dim z × dim z).
  Eigen::MatrixXd innovation_covariance;
  /// The gain K of the applied update (n × dim z; empty if not applied).
  Eigen::MatrixXd gain;
  /// NIS = νᵀ S⁻¹ ν, the squared Mahalanobis distance of the measurement
  /// (χ²(dim z) when the filter is consistent); +inf if S is not positive
  /// definite.
  double nis = 0.0;
  /// Iterations run (1 for the EKF).
  int iterations = 0;
  /// True if the update was applied and (for the IEKF) converged.
  bool ok() const noexcept {
    return termination == KalmanTermination::Updated || termination == KalmanTermination::Converged;
  }
  /// True if the measurement changed the state (Updated, Converged,
  /// MaxIterations).
  bool applied() const noexcept {
    return ok() || termination == KalmanTermination::MaxIterations;
  }
};

/// The χ² interval a consistency statistic must fall in.
struct ChiSquareInterval {
  double lower = 0.0;  ///< lower bound
  double upper = 0.0;  ///< upper bound
  /// lower ≤ value ≤ upper.
  bool contains(double value) const noexcept { return value >= lower && value <= upper; }
};

/// NEES εᵀ P⁻¹ ε of an estimation error ε = x_true − x̂ with covariance P
/// (χ²(n) when the filter is consistent). Angles in `angle_states` of ε are
/// wrapped first. Preconditions (InvalidArgument): sizes agree, finite
/// values; throws NumericError if P is not positive definite.
double nees(const Eigen::VectorXd& error, const Eigen::MatrixXd& covariance,
            const std::vector<int>& angle_states = {});

/// The two-sided interval for the average of `runs` independent χ²(dof)
/// statistics (average NEES or NIS over Monte-Carlo runs): runs · average
/// is χ²(runs · dof), so the bounds are χ²_{runs·dof}((1 ∓ probability)/2) /
/// runs (Bar-Shalom et al. 2001, eq. 5.4.2-5). Preconditions
/// (InvalidArgument): dof ≥ 1, runs ≥ 1, 0 < probability < 1.
ChiSquareInterval average_chi_square_interval(int dof, int runs, double probability);

/// The gate threshold on NIS for a measurement of dimension `dof` accepted
/// with probability `probability`: χ²_{dof}(probability).
double gate_threshold(int dof, double probability);

/// Wraps the listed components of v to (−π, π] (MRPT's wrapToPi).
/// Precondition (InvalidArgument): indices in range.
void wrap_angles(Eigen::VectorXd& v, const std::vector<int>& angle_states);

namespace detail {
/// P' = F P Fᵀ + Q, symmetrized; mean wrapped. Checks sizes and finiteness.
GaussianState kalman_predict_linearized(const GaussianState& prior, Eigen::VectorXd mean,
                                        const Eigen::MatrixXd& F, const Eigen::MatrixXd& Q,
                                        const KalmanOptions& options);
/// The innovation statistics (ν, S, NIS) of a linearized measurement and
/// the gate decision; fills result.innovation, innovation_covariance, nis
/// and sets termination to Gated / NotPositiveDefinite when the update must
/// not be applied (posterior = prior then).
void kalman_innovation(const GaussianState& prior, const Eigen::VectorXd& innovation,
                       const Eigen::MatrixXd& H, const Eigen::MatrixXd& R,
                       const KalmanOptions& options, KalmanUpdateResult& result);
/// The gain K = P Hᵀ (H P Hᵀ + R)⁻¹; false if H P Hᵀ + R is not positive
/// definite.
bool kalman_gain(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H, const Eigen::MatrixXd& R,
                 Eigen::MatrixXd& K);
/// Joseph-form covariance (I − KH) P (I − KH)ᵀ + K R Kᵀ, symmetrized.
Eigen::MatrixXd joseph_covariance(const Eigen::MatrixXd& P, const Eigen::MatrixXd& K,
                                  const Eigen::MatrixXd& H, const Eigen::MatrixXd& R);
/// Checks a prior: finite, square covariance of the mean's size.
void check_gaussian(const GaussianState& g, const char* what);
/// Checks a model output's size and finiteness, naming the model function.
void check_model_output(const Eigen::MatrixXd& m, Eigen::Index rows, Eigen::Index cols,
                        const char* function);
/// Checks a measurement: finite, non-empty.
void check_measurement(const Eigen::VectorXd& z);
/// a − b with the listed components wrapped.
Eigen::VectorXd state_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                 const std::vector<int>& angle_states);
/// Throws InvalidArgument: KalmanJacobians::Analytic and the model lacks
/// `function`.
[[noreturn]] void missing_jacobian(const char* function);
/// The one-line message of an update.
void describe(KalmanUpdateResult& result, const char* filter);
}  // namespace detail

/// A process model x_{k+1} = f(x_k) + w, w ~ N(0, Q(x_k)); optionally with
/// `transition_jacobian(x)` → ∂f/∂x (n × n). See the file comment.
template <typename M>
concept KalmanProcessModel = requires(const M& m, const Eigen::VectorXd& x) {
  { m.transition(x) } -> std::convertible_to<Eigen::VectorXd>;
  { m.process_noise(x) } -> std::convertible_to<Eigen::MatrixXd>;
};

/// An observation model z = h(x) + v, v ~ N(0, R(x)); optionally with
/// `observation_jacobian(x)` → ∂h/∂x (dim z × n) and `innovation(z, ẑ)` →
/// z ⊖ ẑ. See the file comment.
template <typename M>
concept KalmanObservationModel = requires(const M& m, const Eigen::VectorXd& x) {
  { m.observe(x) } -> std::convertible_to<Eigen::VectorXd>;
  { m.observation_noise(x) } -> std::convertible_to<Eigen::MatrixXd>;
};

/// z ⊖ ẑ: the model's innovation() if it has one, else z − ẑ.
template <KalmanObservationModel M>
Eigen::VectorXd observation_residual(const M& model, const Eigen::VectorXd& z,
                                     const Eigen::VectorXd& z_pred) {
  if constexpr (requires { { model.innovation(z, z_pred) } -> std::convertible_to<Eigen::VectorXd>; }) {
    return model.innovation(z, z_pred);
  } else {
    return z - z_pred;
  }
}

/// ∂f/∂x at x: the model's transition_jacobian (Analytic; InvalidArgument if
/// it has none) or central differences of f with angle states wrapped
/// (Numeric).
template <KalmanProcessModel M>
Eigen::MatrixXd transition_jacobian(const M& model, const Eigen::VectorXd& x,
                                    const KalmanOptions& options) {
  if (options.jacobians == KalmanJacobians::Analytic) {
    if constexpr (requires { { model.transition_jacobian(x) } -> std::convertible_to<Eigen::MatrixXd>; }) {
      return model.transition_jacobian(x);
    } else {
      detail::missing_jacobian("transition_jacobian");
    }
  }
  return detail::numeric_jacobian(x, options, [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return detail::state_difference(model.transition(a), model.transition(b), options.angle_states);
  });
}

/// ∂h/∂x at x: the model's observation_jacobian (Analytic; InvalidArgument if
/// it has none) or central differences of h through observation_residual
/// (Numeric).
template <KalmanObservationModel M>
Eigen::MatrixXd observation_jacobian(const M& model, const Eigen::VectorXd& x,
                                     const KalmanOptions& options) {
  if (options.jacobians == KalmanJacobians::Analytic) {
    if constexpr (requires { { model.observation_jacobian(x) } -> std::convertible_to<Eigen::MatrixXd>; }) {
      return model.observation_jacobian(x);
    } else {
      detail::missing_jacobian("observation_jacobian");
    }
  }
  return detail::numeric_jacobian(x, options, [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return observation_residual(model, model.observe(a), model.observe(b));
  });
}

/// EKF prediction: mean f(x̂) (angles wrapped), covariance F P Fᵀ + Q with F
/// and Q at the prior mean. Preconditions (InvalidArgument): options.check();
/// prior finite with a square covariance of the mean's size; the model's
/// outputs finite and of matching sizes.
template <KalmanProcessModel M>
GaussianState ekf_predict(const GaussianState& prior, const M& model,
                          const KalmanOptions& options = {}) {
  options.check();
  detail::check_gaussian(prior, "prior");
  Eigen::VectorXd mean = model.transition(prior.mean);
  const Eigen::MatrixXd F = transition_jacobian(model, prior.mean, options);
  const Eigen::MatrixXd Q = model.process_noise(prior.mean);
  return detail::kalman_predict_linearized(prior, std::move(mean), F, Q, options);
}

/// EKF update with measurement z: innovation ν = z ⊖ h(x̂), S = H P Hᵀ + R,
/// gain K = P Hᵀ S⁻¹, mean x̂ + K ν, Joseph-form covariance; H and R at the
/// prior mean. Gated (unchanged state) when the gate is on and NIS exceeds
/// its threshold. Preconditions as ekf_predict, and z finite and of h's size.
template <KalmanObservationModel M>
KalmanUpdateResult ekf_update(const GaussianState& prior, const Eigen::VectorXd& z, const M& model,
                              const KalmanOptions& options = {}) {
  options.check();
  detail::check_gaussian(prior, "prior");
  detail::check_measurement(z);
  const Eigen::Index n = prior.mean.size(), m = z.size();
  const Eigen::VectorXd z_pred = model.observe(prior.mean);
  detail::check_model_output(z_pred, m, 1, "observe");
  const Eigen::MatrixXd H = observation_jacobian(model, prior.mean, options);
  detail::check_model_output(H, m, n, "observation_jacobian");
  const Eigen::MatrixXd R = model.observation_noise(prior.mean);
  detail::check_model_output(R, m, m, "observation_noise");
  KalmanUpdateResult r;
  r.posterior = prior;
  r.iterations = 1;
  detail::kalman_innovation(prior, observation_residual(model, z, z_pred), H, R, options, r);
  if (r.termination == KalmanTermination::Updated) {
    r.posterior.mean = prior.mean + r.gain * r.innovation;
    wrap_angles(r.posterior.mean, options.angle_states);
    r.posterior.covariance = detail::joseph_covariance(prior.covariance, r.gain, H, R);
  }
  detail::describe(r, "EKF");
  return r;
}

/// Iterated EKF update (Bell & Cathey, "The iterated Kalman filter update as
/// a Gauss–Newton method", IEEE TAC 1993): relinearize h at the iterate xᵢ,
/// xᵢ₊₁ = x̂ + Kᵢ (z ⊖ h(xᵢ) − Hᵢ (x̂ ⊖ xᵢ)), until the step is below
/// options.tolerance (relative); the covariance is the Joseph form with the last
/// linearization. The reported innovation, S, NIS and the gate are those of
/// the prior mean (as the EKF's). Preconditions as ekf_update.
template <KalmanObservationModel M>
KalmanUpdateResult iekf_update(const GaussianState& prior, const Eigen::VectorXd& z, const M& model,
                               const KalmanOptions& options = {}) {
  // Iteration 1 is the EKF update (which also applies the gate).
  KalmanUpdateResult r = ekf_update(prior, z, model, options);
  if (r.termination != KalmanTermination::Updated) return r;
  const Eigen::Index n = prior.mean.size(), m = z.size();
  Eigen::VectorXd x = r.posterior.mean;
  Eigen::MatrixXd H, R, K;
  r.termination = KalmanTermination::MaxIterations;
  while (r.iterations < options.max_iterations) {
    ++r.iterations;
    const Eigen::VectorXd z_pred = model.observe(x);
    detail::check_model_output(z_pred, m, 1, "observe");
    H = observation_jacobian(model, x, options);
    detail::check_model_output(H, m, n, "observation_jacobian");
    R = model.observation_noise(x);
    detail::check_model_output(R, m, m, "observation_noise");
    if (!detail::kalman_gain(prior.covariance, H, R, K)) {
      r.termination = KalmanTermination::NotPositiveDefinite;
      r.posterior = prior;
      r.gain.resize(0, 0);
      detail::describe(r, "IEKF");
      return r;
    }
    Eigen::VectorXd next =
        prior.mean + K * (observation_residual(model, z, z_pred) -
                          H * detail::state_difference(prior.mean, x, options.angle_states));
    wrap_angles(next, options.angle_states);
    const double step =
        detail::state_difference(next, x, options.angle_states).template lpNorm<Eigen::Infinity>();
    x = std::move(next);
    r.posterior.mean = x;
    r.posterior.covariance = detail::joseph_covariance(prior.covariance, K, H, R);
    r.gain = K;
    if (step <= options.tolerance * (1.0 + x.template lpNorm<Eigen::Infinity>())) {
      r.termination = KalmanTermination::Converged;
      break;
    }
  }
  detail::describe(r, "IEKF");
  return r;
}

}  // namespace rove
