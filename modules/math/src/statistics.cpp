#include "rove/math/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"

namespace rove {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Log-domain values: −inf allowed, NaN and +inf rejected with the index.
void check_log_values(std::span<const double> x, const char* name) {
  for (std::size_t i = 0; i < x.size(); ++i) {
    ROVE_CHECK_MSG(!std::isnan(x[i]) && x[i] != kInf,
                   "{}[{}] = {}: log-domain values may be finite or -inf, not NaN or +inf", name,
                   i, x[i]);
  }
}

/// log Σ exp(a(i)) for i in [0, n), shifted by the maximum. −inf if all are.
template <typename Term>
double shifted_log_sum_exp(std::size_t n, Term a) {
  double m = -kInf;
  for (std::size_t i = 0; i < n; ++i) m = std::max(m, a(i));
  if (m == -kInf) return -kInf;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += std::exp(a(i) - m);  // each term ≤ 1, one is 1
  return m + std::log(sum);
}

void check_weights(std::span<const double> w) {
  for (std::size_t i = 0; i < w.size(); ++i) {
    ROVE_CHECK_MSG(std::isfinite(w[i]) && w[i] >= 0.0,
                   "weights[{}] = {}: weights must be finite and >= 0", i, w[i]);
  }
}

}  // namespace

double log_sum_exp(std::span<const double> x) {
  ROVE_CHECK_MSG(!x.empty(), "log_sum_exp of an empty sequence");
  check_log_values(x, "x");
  return shifted_log_sum_exp(x.size(), [&](std::size_t i) { return x[i]; });
}

double log_add_exp(double a, double b) {
  ROVE_CHECK_MSG(!std::isnan(a) && a != kInf, "a = {}: must be finite or -inf", a);
  ROVE_CHECK_MSG(!std::isnan(b) && b != kInf, "b = {}: must be finite or -inf", b);
  const double m = std::max(a, b);
  if (m == -kInf) return -kInf;
  // log(eᵃ + eᵇ) = m + log1p(e^(min − m)); log1p keeps the small term exact.
  return m + std::log1p(std::exp(std::min(a, b) - m));
}

double average_log_likelihood(std::span<const double> log_likelihoods) {
  ROVE_CHECK_MSG(!log_likelihoods.empty(), "average of an empty set of log-likelihoods");
  check_log_values(log_likelihoods, "log_likelihoods");
  const double lse = shifted_log_sum_exp(log_likelihoods.size(),
                                         [&](std::size_t i) { return log_likelihoods[i]; });
  if (lse == -kInf) return -kInf;
  return lse - std::log(static_cast<double>(log_likelihoods.size()));
}

double average_log_likelihood_log_weights(std::span<const double> log_weights,
                                          std::span<const double> log_likelihoods) {
  ROVE_CHECK_EQ(log_weights.size(), log_likelihoods.size());
  ROVE_CHECK_MSG(!log_weights.empty(), "average of an empty set of log-likelihoods");
  check_log_values(log_weights, "log_weights");
  check_log_values(log_likelihoods, "log_likelihoods");
  const std::size_t n = log_weights.size();
  const double log_total_weight =
      shifted_log_sum_exp(n, [&](std::size_t i) { return log_weights[i]; });
  ROVE_CHECK_MSG(log_total_weight > -kInf, "all {} log-weights are -inf (total weight 0)", n);
  // wᵢ + lᵢ is never NaN: neither term is +inf.
  const double lse = shifted_log_sum_exp(
      n, [&](std::size_t i) { return log_weights[i] + log_likelihoods[i]; });
  if (lse == -kInf) return -kInf;
  return lse - log_total_weight;
}

double average_log_likelihood_weights(std::span<const double> weights,
                                      std::span<const double> log_likelihoods) {
  ROVE_CHECK_EQ(weights.size(), log_likelihoods.size());
  ROVE_CHECK_MSG(!weights.empty(), "average of an empty set of log-likelihoods");
  check_weights(weights);
  check_log_values(log_likelihoods, "log_likelihoods");
  double total = 0.0;
  double m = -kInf;  // largest log-likelihood with a positive weight
  for (std::size_t i = 0; i < weights.size(); ++i) {
    total += weights[i];
    if (weights[i] > 0.0) m = std::max(m, log_likelihoods[i]);
  }
  ROVE_CHECK_MSG(total > 0.0 && std::isfinite(total),
                 "weights must have a finite positive sum, got {}", total);
  if (m == -kInf) return -kInf;
  double sum = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (weights[i] > 0.0) sum += weights[i] * std::exp(log_likelihoods[i] - m);
  }
  return m + std::log(sum) - std::log(total);
}

double normalize_log_weights(std::span<double> log_weights) {
  ROVE_CHECK_MSG(!log_weights.empty(), "cannot normalize an empty set of log-weights");
  const std::span<const double> view(log_weights.data(), log_weights.size());
  check_log_values(view, "log_weights");
  const double lse =
      shifted_log_sum_exp(view.size(), [&](std::size_t i) { return view[i]; });
  ROVE_CHECK_MSG(lse > -kInf, "all {} log-weights are -inf (total weight 0)", view.size());
  for (double& w : log_weights) w -= lse;  // −inf stays −inf
  return lse;
}

std::vector<double> weights_from_log_weights(std::span<const double> log_weights) {
  std::vector<double> w(log_weights.begin(), log_weights.end());
  normalize_log_weights(w);
  for (double& v : w) v = std::exp(v);
  return w;
}

MeanCovariance weighted_mean_covariance(const Eigen::Ref<const Eigen::MatrixXd>& samples,
                                        std::span<const double> weights,
                                        CovarianceNormalization normalization) {
  const Eigen::Index d = samples.rows();
  const Eigen::Index n = samples.cols();
  ROVE_CHECK_GE(d, Eigen::Index{1});
  ROVE_CHECK_GE(n, Eigen::Index{1});
  ROVE_CHECK_EQ(weights.size(), static_cast<std::size_t>(n));
  for (Eigen::Index j = 0; j < n; ++j) {
    ROVE_CHECK_MSG(samples.col(j).allFinite(), "sample {} (column) is not finite", j);
  }
  check_weights(weights);
  const Eigen::Map<const Eigen::VectorXd> w(weights.data(), n);
  const double v1 = w.sum();
  ROVE_CHECK_MSG(v1 > 0.0 && std::isfinite(v1), "weights must have a finite positive sum, got {}",
                 v1);
  double divisor = v1;
  if (normalization == CovarianceNormalization::Unbiased) {
    const double v2 = w.squaredNorm();
    divisor = v1 - v2 / v1;
    ROVE_CHECK_MSG(divisor > 0.0,
                   "unbiased covariance needs more than one sample with positive weight "
                   "(V1 = {}, V2 = {})",
                   v1, v2);
  }
  MeanCovariance out;
  out.mean = samples * w / v1;
  const Eigen::MatrixXd centered = samples.colwise() - out.mean;
  out.covariance = centered * w.asDiagonal() * centered.transpose() / divisor;
  // Exactly symmetric despite rounding.
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  return out;
}

MeanCovariance mean_covariance(const Eigen::Ref<const Eigen::MatrixXd>& samples,
                               CovarianceNormalization normalization) {
  const std::vector<double> ones(static_cast<std::size_t>(samples.cols()), 1.0);
  return weighted_mean_covariance(samples, ones, normalization);
}

}  // namespace rove
