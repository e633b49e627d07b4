#pragma once
/// \file
/// Numerically stable statistics for filters and estimators: log-sum-exp,
/// averaging likelihoods given their logarithms (MRPT's
/// math::averageLogLikelihood), normalizing log-weights, and weighted mean
/// and covariance of vectors.
///
/// Log-domain inputs follow one rule: −inf is allowed (a zero likelihood or
/// weight), NaN is rejected with InvalidArgument naming its index, +inf is
/// rejected too (an infinite likelihood has no meaningful average). Sums are
/// evaluated as m + log Σ exp(xᵢ − m) with m = max xᵢ, so no exponential
/// overflows and the largest term is exactly exp(0) = 1.

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace rove {

/// log Σᵢ exp(xᵢ), stable for any magnitude. All −inf gives −inf.
/// Preconditions (InvalidArgument): non-empty; no NaN or +inf.
double log_sum_exp(std::span<const double> x);

/// log(exp(a) + exp(b)), stable. Preconditions: a, b not NaN nor +inf.
double log_add_exp(double a, double b);

/// log((1/N) Σᵢ exp(lᵢ)): the log of the average likelihood given the
/// log-likelihoods lᵢ. All −inf gives −inf.
/// Preconditions (InvalidArgument): non-empty; no NaN or +inf.
double average_log_likelihood(std::span<const double> log_likelihoods);

/// log(Σᵢ exp(wᵢ + lᵢ) / Σᵢ exp(wᵢ)): the weighted average likelihood with
/// weights given as logs wᵢ (need not be normalized). All lᵢ with a nonzero
/// weight at −inf gives −inf.
/// Preconditions (InvalidArgument): equal non-zero sizes; no NaN or +inf;
/// at least one finite log-weight.
double average_log_likelihood_log_weights(std::span<const double> log_weights,
                                          std::span<const double> log_likelihoods);

/// log(Σᵢ wᵢ exp(lᵢ) / Σᵢ wᵢ) with linear weights wᵢ ≥ 0 (need not be
/// normalized). Preconditions (InvalidArgument): equal non-zero sizes;
/// weights finite and ≥ 0 with a positive sum; lᵢ not NaN nor +inf.
double average_log_likelihood_weights(std::span<const double> weights,
                                      std::span<const double> log_likelihoods);

/// Shifts log-weights in place so that Σ exp(wᵢ) = 1 and returns the shift
/// subtracted (the previous log Σ exp(wᵢ)); −inf entries stay −inf.
/// Preconditions (InvalidArgument): non-empty; no NaN or +inf; at least one
/// finite entry.
double normalize_log_weights(std::span<double> log_weights);

/// Linear weights exp(wᵢ − log Σ exp(wⱼ)) summing to 1, from log-weights.
/// Preconditions as normalize_log_weights().
std::vector<double> weights_from_log_weights(std::span<const double> log_weights);

/// Divisor of the weighted scatter in weighted_mean_covariance().
enum class CovarianceNormalization {
  /// Σ wᵢ (xᵢ−μ)(xᵢ−μ)ᵀ / V₁ with V₁ = Σ wᵢ: the maximum-likelihood
  /// (biased) estimate, as MRPT's weightedMeanAndCov and particle filters.
  MaximumLikelihood,
  /// Divided by V₁ − V₂/V₁ with V₂ = Σ wᵢ²: unbiased for reliability
  /// weights (equals N − 1 for unit weights). Needs more than one sample
  /// with positive weight.
  Unbiased,
};

/// Mean and covariance of a weighted set of vectors.
struct MeanCovariance {
  /// Weighted mean μ = Σ wᵢ xᵢ / Σ wᵢ (d).
  Eigen::VectorXd mean;
  /// Weighted covariance (d × d, symmetric, positive semi-definite).
  Eigen::MatrixXd covariance;
};

/// Weighted mean and covariance of the columns of `samples` (d × N, one
/// sample per column) with linear weights (N entries, ≥ 0, positive sum,
/// need not be normalized). Two passes (mean, then centered scatter) for
/// accuracy when the samples are far from the origin.
/// Preconditions (InvalidArgument): d ≥ 1, N ≥ 1, weights.size() = N,
/// samples and weights finite, weights ≥ 0 with a positive sum; for
/// Unbiased, V₁² > V₂ (more than one sample with positive weight).
MeanCovariance weighted_mean_covariance(
    const Eigen::Ref<const Eigen::MatrixXd>& samples, std::span<const double> weights,
    CovarianceNormalization normalization = CovarianceNormalization::MaximumLikelihood);

/// Unweighted mean and covariance of the columns of `samples` (d × N).
/// Preconditions as weighted_mean_covariance() with unit weights.
MeanCovariance mean_covariance(
    const Eigen::Ref<const Eigen::MatrixXd>& samples,
    CovarianceNormalization normalization = CovarianceNormalization::MaximumLikelihood);

}  // namespace rove
