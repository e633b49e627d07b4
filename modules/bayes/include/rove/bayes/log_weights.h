#pragma once
/// \file
/// Particle weights are kept as logarithms everywhere in rove::bayes: a
/// likelihood of 1e-300 per ray times 500 rays is far below the smallest
/// double, its logarithm is not. This header adds what particle filters need
/// on top of rove/math/statistics.h (log_sum_exp, normalize_log_weights,
/// weights_from_log_weights, which it includes): the effective sample size
/// and a one-pass summary (normalizer, largest weight).
///
/// Input rules as in rove/math/statistics.h: −inf is a zero weight, NaN and
/// +inf are rejected (InvalidArgument naming the index), at least one weight
/// must be finite.

#include <cstddef>
#include <span>

#include "rove/math/statistics.h"

namespace rove {

/// One pass over a set of log-weights.
struct LogWeightSummary {
  /// log Σᵢ exp(wᵢ): subtract it to normalize.
  double log_sum = 0.0;
  /// The largest log-weight.
  double max_log_weight = 0.0;
  /// Index of the largest log-weight (the first one on ties).
  std::size_t max_index = 0;
  /// Effective sample size (Σ wᵢ)² / Σ wᵢ² (Kong, Liu & Wong 1994), in
  /// [1, N]: N for equal weights, 1 when one particle holds all the weight.
  double effective_sample_size = 0.0;
  /// effective_sample_size / N in (0, 1]: MRPT's ESS(), compared with the
  /// resampling threshold BETA.
  double normalized_ess = 0.0;
};

/// Normalizer, maximum and effective sample size of `log_weights` (which
/// need not be normalized). Stable for any magnitude (every sum is taken
/// relative to the maximum).
/// Preconditions (InvalidArgument): non-empty; no NaN or +inf; at least one
/// finite entry.
LogWeightSummary summarize_log_weights(std::span<const double> log_weights);

/// The effective sample size (Σ wᵢ)² / Σ wᵢ² of the weights exp(log_weights),
/// in [1, N]. Preconditions as summarize_log_weights().
double effective_sample_size(std::span<const double> log_weights);

}  // namespace rove
