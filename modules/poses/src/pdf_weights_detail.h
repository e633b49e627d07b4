#pragma once
// Log-weight helpers shared by PoseParticles and PoseSOG (normalization is
// rove/math/statistics.h).

#include <cstddef>
#include <random>
#include <span>
#include <vector>

namespace rove::detail {

// Throws InvalidArgument if a log-weight is NaN or +inf (−inf is a zero weight).
void check_log_weight(double log_weight);
// An index drawn with probability weights[i] (normalized weights).
std::size_t draw_index(std::span<const double> weights, std::mt19937_64& rng);

}  // namespace rove::detail
