#pragma once
// Log-weight helpers shared by PoseParticles and PoseSOG.

#include <cstddef>
#include <random>
#include <span>
#include <vector>

namespace rove::detail {

// Throws InvalidArgument if a log-weight is NaN or +inf (−inf is a zero weight).
void check_log_weight(double log_weight);
// log Σ exp(lwᵢ), computed stably. Precondition: not empty, not all −inf.
double log_sum_exp(std::span<const double> log_weights);
// exp(lwᵢ − log_sum_exp(lw)), summing to one.
std::vector<double> normalized_weights(std::span<const double> log_weights);
// An index drawn with probability weights[i] (normalized weights).
std::size_t draw_index(std::span<const double> weights, std::mt19937_64& rng);

}  // namespace rove::detail
