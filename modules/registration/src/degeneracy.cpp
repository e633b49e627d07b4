#include "rove/registration/degeneracy.h"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {

double point_to_plane_conditioning(std::span<const Eigen::Vector3d> points,
                                   std::span<const Eigen::Vector3d> normals) {
  ROVE_CHECK_EQ(points.size(), normals.size());
  if (points.size() < 6) return 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p;
  c /= static_cast<double>(points.size());
  double r2 = 0;
  for (const auto& p : points) r2 += (p - c).squaredNorm();
  const double L = std::sqrt(r2 / static_cast<double>(points.size()));
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Matrix<double, 6, 1> j;
    j.head<3>() = normals[i];
    j.tail<3>() = L > 0 ? Eigen::Vector3d((points[i] - c).cross(normals[i]) / L)
                        : Eigen::Vector3d::Zero();
    A += j * j.transpose();
  }
  const auto ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(A).eigenvalues();
  return ev(5) > 0 ? std::max(ev(0), 0.0) / ev(5) : 0.0;
}

std::string degenerate_geometry_message(double conditioning, double threshold,
                                        std::string_view example) {
  return fmt::format(
      "the matched geometry leaves a direction unconstrained (conditioning {:.3g} < {:.3g}, "
      "e.g. {})",
      conditioning, threshold, example);
}

}  // namespace rove
