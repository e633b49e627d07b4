#include "rove/math/line_detection.h"

#include <algorithm>

#include "hyperplane_fit.h"

namespace rove {

std::optional<Line2> fit_line(std::span<const Eigen::Vector2d> points) {
  Line2 line;
  if (!detail::fit_hyperplane_pca<2>(points, line.normal, line.offset)) return std::nullopt;
  return line;
}

bool LineRansacProblem::is_degenerate(std::span<const Datum> sample) const {
  ROVE_CHECK_EQ(sample.size(), std::size_t{2});
  const double scale = std::max(sample[0].norm(), sample[1].norm());
  return !((sample[1] - sample[0]).norm() > 1e-12 * scale);
}

void LineRansacProblem::fit(std::span<const Datum> sample, std::vector<Model>& models) const {
  if (is_degenerate(sample)) return;
  const Eigen::Vector2d e = (sample[1] - sample[0]).normalized();
  Line2 line;
  line.normal = Eigen::Vector2d(-e.y(), e.x());
  line.offset = -line.normal.dot(0.5 * (sample[0] + sample[1]));
  detail::canonicalize<2>(line.normal, line.offset);
  models.push_back(line);
}

bool LineRansacProblem::refit(std::span<const Datum> inliers, Model& line) const {
  const auto fitted = fit_line(inliers);
  if (!fitted) return false;
  line = *fitted;
  return true;
}

LineDetectionResult detect_lines(std::span<const Eigen::Vector2d> points,
                                 const LineDetectionOptions& options) {
  detail::check_points_finite<2>(points);
  return detect_sequential(LineRansacProblem{}, points, options);
}

}  // namespace rove
