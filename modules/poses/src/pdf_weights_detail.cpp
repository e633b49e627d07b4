#include "pdf_weights_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"

namespace rove::detail {

void check_log_weight(double log_weight) {
  ROVE_CHECK_MSG(!std::isnan(log_weight) && log_weight != std::numeric_limits<double>::infinity(),
                 "log-weight must not be NaN or +inf, got {}", log_weight);
}

std::size_t draw_index(std::span<const double> weights, std::mt19937_64& rng) {
  ROVE_CHECK_MSG(!weights.empty(), "cannot draw from an empty set");
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double u = uniform(rng);
  double acc = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    acc += weights[i];
    if (u < acc) return i;
  }
  // Round-off left the cumulative sum just below u: take the last non-zero weight.
  for (std::size_t i = weights.size(); i-- > 0;)
    if (weights[i] > 0.0) return i;
  return weights.size() - 1;
}

}  // namespace rove::detail
