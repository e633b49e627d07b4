#include "rove/bayes/kalman.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "rove/bayes/distributions.h"
#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {

void KalmanOptions::check() const {
  ROVE_CHECK_MSG(numeric_step > 0.0 && numeric_step < 1.0, "numeric_step must be in (0, 1), got {}",
                 numeric_step);
  ROVE_CHECK_MSG(gate_probability >= 0.0 && gate_probability < 1.0,
                 "gate_probability must be 0 (off) or in (0, 1), got {}", gate_probability);
  ROVE_CHECK_MSG(max_iterations >= 1, "max_iterations must be >= 1, got {}", max_iterations);
  ROVE_CHECK_MSG(tolerance > 0.0 && std::isfinite(tolerance), "tolerance must be finite and > 0, got {}",
                 tolerance);
  for (const int i : angle_states) ROVE_CHECK_MSG(i >= 0, "angle_states holds {}", i);
}

void wrap_angles(Eigen::VectorXd& v, const std::vector<int>& angle_states) {
  for (const int i : angle_states) {
    ROVE_CHECK_MSG(i >= 0 && i < v.size(), "angle state {} outside a vector of size {}", i, v.size());
    // (−π, π], as MRPT's wrapToPi.
    double a = std::remainder(v[i], 2.0 * std::numbers::pi);
    if (a <= -std::numbers::pi) a += 2.0 * std::numbers::pi;
    v[i] = a;
  }
}

double nees(const Eigen::VectorXd& error, const Eigen::MatrixXd& covariance,
            const std::vector<int>& angle_states) {
  ROVE_CHECK_MSG(error.size() > 0 && covariance.rows() == error.size() &&
                     covariance.cols() == error.size(),
                 "NEES of a {}-vector with a {}x{} covariance", error.size(), covariance.rows(),
                 covariance.cols());
  ROVE_CHECK_FINITE(error);
  ROVE_CHECK_FINITE(covariance);
  Eigen::VectorXd e = error;
  wrap_angles(e, angle_states);
  const Eigen::LLT<Eigen::MatrixXd> llt(covariance);
  if (llt.info() != Eigen::Success) throw NumericError("NEES: the covariance is not positive definite");
  return e.dot(llt.solve(e));
}

ChiSquareInterval average_chi_square_interval(int dof, int runs, double probability) {
  ROVE_CHECK_MSG(dof >= 1 && runs >= 1, "needs dof >= 1 and runs >= 1, got {} and {}", dof, runs);
  ROVE_CHECK_MSG(probability > 0.0 && probability < 1.0, "probability must be in (0, 1), got {}",
                 probability);
  const double k = static_cast<double>(dof) * runs;
  return {chi_square_quantile(0.5 * (1.0 - probability), k) / runs,
          chi_square_quantile(0.5 * (1.0 + probability), k) / runs};
}

double gate_threshold(int dof, double probability) {
  ROVE_CHECK_MSG(dof >= 1, "gate needs dof >= 1, got {}", dof);
  return chi_square_quantile(probability, dof);
}

namespace detail {

double numeric_jacobian_step(double x_j, const KalmanOptions& options) {
  return options.numeric_step * std::max(1.0, std::abs(x_j));
}

void check_gaussian(const GaussianState& g, const char* what) {
  const auto n = g.mean.size();
  ROVE_CHECK_MSG(n > 0, "the {} state is empty", what);
  ROVE_CHECK_MSG(g.covariance.rows() == n && g.covariance.cols() == n,
                 "the {} covariance is {}x{} for a state of size {}", what, g.covariance.rows(),
                 g.covariance.cols(), n);
  ROVE_CHECK_MSG(g.mean.allFinite() && g.covariance.allFinite(), "the {} state is not finite", what);
}

void check_model_output(const Eigen::MatrixXd& m, Eigen::Index rows, Eigen::Index cols,
                        const char* function) {
  ROVE_CHECK_MSG(m.rows() == rows && m.cols() == cols, "the model's {} gave a {}x{} result, not {}x{}",
                 function, m.rows(), m.cols(), rows, cols);
  ROVE_CHECK_MSG(m.allFinite(), "the model's {} gave a non-finite value", function);
}

void check_measurement(const Eigen::VectorXd& z) {
  ROVE_CHECK_MSG(z.size() > 0, "empty measurement");
  for (Eigen::Index i = 0; i < z.size(); ++i)
    ROVE_CHECK_MSG(std::isfinite(z[i]), "measurement component {} is {}", i, z[i]);
}

void missing_jacobian(const char* function) {
  ROVE_CHECK_MSG(false, "KalmanJacobians::Analytic needs the model's {}(x); use "
                 "KalmanJacobians::Numeric for central differences", function);
  throw InvalidArgument("unreachable");
}

Eigen::VectorXd state_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                 const std::vector<int>& angle_states) {
  Eigen::VectorXd d = a - b;
  wrap_angles(d, angle_states);
  return d;
}

GaussianState kalman_predict_linearized(const GaussianState& prior, Eigen::VectorXd mean,
                                        const Eigen::MatrixXd& F, const Eigen::MatrixXd& Q,
                                        const KalmanOptions& options) {
  const auto n = prior.mean.size();
  check_model_output(mean, n, 1, "transition");
  check_model_output(F, n, n, "transition_jacobian");
  check_model_output(Q, n, n, "process_noise");
  GaussianState out;
  out.mean = std::move(mean);
  wrap_angles(out.mean, options.angle_states);
  out.covariance = F * prior.covariance * F.transpose() + Q;
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  return out;
}

bool kalman_gain(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H, const Eigen::MatrixXd& R,
                 Eigen::MatrixXd& K) {
  const Eigen::MatrixXd PHt = P * H.transpose();
  const Eigen::MatrixXd S = H * PHt + R;
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (S + S.transpose()));
  if (llt.info() != Eigen::Success) return false;
  // K = P Hᵀ S⁻¹ = (S⁻¹ H P)ᵀ with S symmetric.
  K = llt.solve(PHt.transpose()).transpose();
  return true;
}

void kalman_innovation(const GaussianState& prior, const Eigen::VectorXd& innovation,
                       const Eigen::MatrixXd& H, const Eigen::MatrixXd& R,
                       const KalmanOptions& options, KalmanUpdateResult& result) {
  check_model_output(innovation, H.rows(), 1, "innovation");
  result.innovation = innovation;
  const Eigen::MatrixXd PHt = prior.covariance * H.transpose();
  result.innovation_covariance = H * PHt + R;
  result.innovation_covariance =
      0.5 * (result.innovation_covariance + result.innovation_covariance.transpose()).eval();
  const Eigen::LLT<Eigen::MatrixXd> llt(result.innovation_covariance);
  if (llt.info() != Eigen::Success) {
    result.nis = std::numeric_limits<double>::infinity();
    result.termination = KalmanTermination::NotPositiveDefinite;
    return;
  }
  result.nis = innovation.dot(llt.solve(innovation));
  if (options.gate_probability > 0.0 &&
      result.nis > gate_threshold(static_cast<int>(innovation.size()), options.gate_probability)) {
    result.termination = KalmanTermination::Gated;
    return;
  }
  result.termination = KalmanTermination::Updated;
  result.gain = llt.solve(PHt.transpose()).transpose();
}

Eigen::MatrixXd joseph_covariance(const Eigen::MatrixXd& P, const Eigen::MatrixXd& K,
                                  const Eigen::MatrixXd& H, const Eigen::MatrixXd& R) {
  const auto n = P.rows();
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n) - K * H;
  Eigen::MatrixXd out = A * P * A.transpose() + K * R * K.transpose();
  return 0.5 * (out + out.transpose());
}

void describe(KalmanUpdateResult& r, const char* filter) {
  const char* what = "";
  switch (r.termination) {
    case KalmanTermination::Updated: what = "updated"; break;
    case KalmanTermination::Converged: what = "converged"; break;
    case KalmanTermination::MaxIterations: what = "stopped at the iteration limit"; break;
    case KalmanTermination::Gated: what = "measurement rejected by the gate"; break;
    case KalmanTermination::NotPositiveDefinite:
      what = "innovation covariance not positive definite, measurement ignored";
      break;
  }
  r.message = fmt::format("{}: {} (NIS {:.4g}, dim {}, {} iteration{})", filter, what, r.nis,
                          r.innovation.size(), r.iterations, r.iterations == 1 ? "" : "s");
}

}  // namespace detail
}  // namespace rove
