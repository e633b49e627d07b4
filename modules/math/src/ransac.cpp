#include "rove/math/ransac.h"

#include <cmath>
#include <limits>

namespace rove {

std::string_view to_string(RansacTermination t) {
  switch (t) {
    case RansacTermination::Converged: return "Converged";
    case RansacTermination::MaxIterations: return "MaxIterations";
    case RansacTermination::NotEnoughData: return "NotEnoughData";
    case RansacTermination::Degenerate: return "Degenerate";
  }
  ROVE_CHECK_MSG(false, "invalid RansacTermination value {}", static_cast<int>(t));
  return {};
}

std::size_t ransac_required_iterations(double inlier_ratio, std::size_t sample_size,
                                       double success_probability) {
  ROVE_CHECK_MSG(inlier_ratio >= 0.0 && inlier_ratio <= 1.0,
                 "inlier ratio must be in [0, 1], got {}", inlier_ratio);
  ROVE_CHECK_GE(sample_size, std::size_t{1});
  ROVE_CHECK_MSG(success_probability > 0.0 && success_probability < 1.0,
                 "success probability must be in (0, 1), got {}", success_probability);
  constexpr std::size_t kUnbounded = std::numeric_limits<std::size_t>::max();
  if (inlier_ratio >= 1.0) return 0;
  const double all_inliers = std::pow(inlier_ratio, static_cast<double>(sample_size));
  // log1p keeps log(1 - w^s) accurate when w^s is tiny (many outliers).
  const double denominator = std::log1p(-all_inliers);
  if (!(denominator < 0.0)) return kUnbounded;
  const double n = std::ceil(std::log1p(-success_probability) / denominator);
  if (!(n < static_cast<double>(kUnbounded))) return kUnbounded;
  return static_cast<std::size_t>(n);
}

namespace detail {

void check_ransac_options(const RansacOptions& o) {
  ROVE_CHECK_MSG(std::isfinite(o.distance_threshold) && o.distance_threshold > 0.0,
                 "RANSAC distance threshold must be finite and > 0, got {}",
                 o.distance_threshold);
  ROVE_CHECK_MSG(o.success_probability > 0.0 && o.success_probability < 1.0,
                 "RANSAC success probability must be in (0, 1), got {}", o.success_probability);
  ROVE_CHECK_GE(o.max_iterations, std::size_t{1});
  ROVE_CHECK_LE(o.min_iterations, o.max_iterations);
  ROVE_CHECK_GE(o.max_refit_rounds, 0);
}

}  // namespace detail
}  // namespace rove
