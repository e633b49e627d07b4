#pragma once
/// \file
/// MRPT's four resampling schemes (CParticleFilter::TParticleResamplingAlgorithm),
/// taking log-weights and an Rng and giving how many copies of each input
/// particle the new set holds. All four are unbiased: the expected number
/// of copies of particle i is n_out · w̄ᵢ (w̄ the normalized weights). They
/// differ in variance (Douc, Cappé & Moulines, "Comparison of resampling
/// schemes for particle filtering", ISPA 2005):
///
/// - Multinomial: n_out independent draws from the weights (MRPT's
///   "select with replacement"); copy counts are multinomial, variance
///   n_out w̄ᵢ (1 − w̄ᵢ). Drawn as n_out sorted uniforms from exponential
///   spacings in O(N + n_out).
/// - Residual: ⌊n_out w̄ᵢ⌋ copies deterministically, the remaining
///   R = n_out − Σ⌊n_out w̄ᵢ⌋ by multinomial draws from the residual weights
///   (n_out w̄ᵢ − ⌊n_out w̄ᵢ⌋) / R.
/// - Stratified: one uniform in each stratum [k/n_out, (k+1)/n_out).
/// - Systematic: one uniform u, points (k + u)/n_out; each particle gets
///   ⌊n_out w̄ᵢ⌋ or ⌈n_out w̄ᵢ⌉ copies (the lowest variance of the four).
///
/// A particle with zero weight (log-weight −inf) is never chosen. Unlike
/// MRPT, every scheme honours n_out ≠ N (MRPT's residual scheme assumes
/// equality).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "rove/bayes/random.h"

namespace rove {

/// The resampling scheme (MRPT's TParticleResamplingAlgorithm; the
/// underlying values are MRPT's).
enum class ResamplingMethod : std::uint8_t {
  Multinomial = 0,  ///< MRPT prMultinomial
  Residual = 1,     ///< MRPT prResidual
  Stratified = 2,   ///< MRPT prStratified
  Systematic = 3,   ///< MRPT prSystematic
};

/// MRPT's name of the method ("prMultinomial", ...).
std::string_view mrpt_name(ResamplingMethod method);

/// Copies of each particle: counts[i] for input i (size N), summing to
/// n_out. `log_weights` need not be normalized.
/// Preconditions (InvalidArgument): log_weights non-empty, no NaN or +inf,
/// at least one finite; n_out ≥ 1 and < 2³².
std::vector<std::uint32_t> resampling_counts(ResamplingMethod method,
                                             std::span<const double> log_weights,
                                             std::size_t n_out, Rng& rng);

/// The chosen input index of each of the n_out outputs, in ascending order
/// (so a particle's copies are adjacent). Same draws and preconditions as
/// resampling_counts().
std::vector<std::size_t> resample_indices(ResamplingMethod method,
                                          std::span<const double> log_weights,
                                          std::size_t n_out, Rng& rng);

/// The indices listing input i counts[i] times, in ascending order.
std::vector<std::size_t> indices_from_counts(std::span<const std::uint32_t> counts);

/// One index drawn from the weights exp(log_weights) by inverting their
/// cumulative sum at u ∈ [0, 1). `cumulative` is the normalized cumulative
/// sum of the weights (nondecreasing, last entry 1, see
/// cumulative_weights()). Never returns an index of zero weight.
/// Precondition (InvalidArgument): cumulative non-empty.
std::size_t draw_from_cumulative(std::span<const double> cumulative, double u);

/// The normalized cumulative sums c₀ = w̄₀, cᵢ = cᵢ₋₁ + w̄ᵢ of exp(log_weights),
/// with the entries from the last positive weight on set to exactly 1.
/// Preconditions as resampling_counts().
std::vector<double> cumulative_weights(std::span<const double> log_weights);

/// draw_from_cumulative() in expected constant time per draw, for drawing
/// many single indices from one set of weights (KLD-sampling draws each
/// offspring's ancestor from its own random stream): the guide table of
/// Chen and Asau ("On generating random variates from an empirical
/// distribution", AIIE Transactions 6(2), 1974) points each of N equal
/// slices of [0, 1) at the first index whose cumulative sum exceeds the
/// slice's start, and a draw scans forward from there. The index drawn
/// for u is exactly draw_from_cumulative(cumulative(), u).
class CumulativeSampler {
 public:
  /// The table of `log_weights`. Preconditions (InvalidArgument) as
  /// cumulative_weights(), and fewer than 2³² weights.
  explicit CumulativeSampler(std::span<const double> log_weights);
  /// The index for u. Precondition (InvalidArgument): 0 ≤ u < 1.
  std::size_t draw(double u) const;
  /// The cumulative sums (cumulative_weights() of the weights).
  const std::vector<double>& cumulative() const noexcept { return cumulative_; }

 private:
  std::vector<double> cumulative_;
  std::vector<std::uint32_t> guide_;  // guide_[j]: first i with cᵢ > j / N
};

}  // namespace rove
