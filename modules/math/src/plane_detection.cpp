#include "rove/math/plane_detection.h"

#include "hyperplane_fit.h"

namespace rove {

std::optional<Plane3> fit_plane(std::span<const Eigen::Vector3d> points) {
  Plane3 plane;
  if (!detail::fit_hyperplane_pca<3>(points, plane.normal, plane.offset)) return std::nullopt;
  return plane;
}

bool PlaneRansacProblem::is_degenerate(std::span<const Datum> sample) const {
  ROVE_CHECK_EQ(sample.size(), std::size_t{3});
  const Eigen::Vector3d e1 = sample[1] - sample[0];
  const Eigen::Vector3d e2 = sample[2] - sample[0];
  // ‖e1 × e2‖ = ‖e1‖‖e2‖ sin θ; also true when two points coincide.
  return !(e1.cross(e2).norm() > min_sine * e1.norm() * e2.norm());
}

void PlaneRansacProblem::fit(std::span<const Datum> sample, std::vector<Model>& models) const {
  if (is_degenerate(sample)) return;
  Plane3 plane;
  plane.normal = (sample[1] - sample[0]).cross(sample[2] - sample[0]).normalized();
  plane.offset = -plane.normal.dot((sample[0] + sample[1] + sample[2]) / 3.0);
  detail::canonicalize<3>(plane.normal, plane.offset);
  models.push_back(plane);
}

bool PlaneRansacProblem::refit(std::span<const Datum> inliers, Model& plane) const {
  const auto fitted = fit_plane(inliers);
  if (!fitted) return false;
  plane = *fitted;
  return true;
}

PlaneDetectionResult detect_planes(std::span<const Eigen::Vector3d> points,
                                   const PlaneDetectionOptions& options) {
  detail::check_points_finite<3>(points);
  return detect_sequential(PlaneRansacProblem{}, points, options);
}

}  // namespace rove
