#include "rove/bayes/log_weights.h"

#include <cmath>
#include <limits>

#include "rove/core/check.h"

namespace rove {

LogWeightSummary summarize_log_weights(std::span<const double> log_weights) {
  ROVE_CHECK_MSG(!log_weights.empty(), "no log-weights");
  LogWeightSummary s;
  s.max_log_weight = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < log_weights.size(); ++i) {
    const double w = log_weights[i];
    ROVE_CHECK_MSG(!std::isnan(w) && w != std::numeric_limits<double>::infinity(),
                   "log-weight {} is {}", i, w);
    if (w > s.max_log_weight) {
      s.max_log_weight = w;
      s.max_index = i;
    }
  }
  ROVE_CHECK_MSG(std::isfinite(s.max_log_weight), "every one of the {} log-weights is -inf",
                 log_weights.size());
  double sum = 0.0, sum_sq = 0.0;
  for (const double w : log_weights) {
    const double e = std::exp(w - s.max_log_weight);
    sum += e;
    sum_sq += e * e;
  }
  s.log_sum = s.max_log_weight + std::log(sum);
  s.effective_sample_size = sum * sum / sum_sq;
  s.normalized_ess = s.effective_sample_size / static_cast<double>(log_weights.size());
  return s;
}

double effective_sample_size(std::span<const double> log_weights) {
  return summarize_log_weights(log_weights).effective_sample_size;
}

}  // namespace rove
