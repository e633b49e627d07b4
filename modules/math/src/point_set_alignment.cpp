// Umeyama's closed-form similarity between two point sets.
#include "rove/math/point_set_alignment.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "rove/core/check.h"

namespace rove {

template <int N>
PointSetAlignment<N> align_point_sets(std::span<const Eigen::Matrix<double, N, 1>> from,
                                      std::span<const Eigen::Matrix<double, N, 1>> to,
                                      bool with_scale) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  ROVE_CHECK_MSG(from.size() == to.size(), "{} points to align onto {}", from.size(), to.size());
  ROVE_CHECK_MSG(!from.empty(), "no points to align");
  const double n = static_cast<double>(from.size());
  Vec mean_from = Vec::Zero(), mean_to = Vec::Zero();
  for (std::size_t k = 0; k < from.size(); ++k) {
    ROVE_CHECK_MSG(from[k].allFinite() && to[k].allFinite(), "point {} is not finite", k);
    mean_from += from[k];
    mean_to += to[k];
  }
  mean_from /= n;
  mean_to /= n;
  Mat S = Mat::Zero();  // (1/n) Σ (to − mean_to)(from − mean_from)ᵀ
  double var_from = 0.0;
  for (std::size_t k = 0; k < from.size(); ++k) {
    const Vec a = from[k] - mean_from;
    S += (to[k] - mean_to) * a.transpose();
    var_from += a.squaredNorm();
  }
  S /= n;
  var_from /= n;
  Eigen::JacobiSVD<Mat> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat D = Mat::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) D(N - 1, N - 1) = -1.0;

  PointSetAlignment<N> out;
  out.R = svd.matrixU() * D * svd.matrixV().transpose();
  // The rotation is unique when S has rank N − 1 or more (Umeyama's
  // Lemma); a rank below means the points lie on a line (or a point in 2D).
  const auto& sv = svd.singularValues();
  out.degenerate = !(sv(N - 2) > 1e-12 * sv(0)) || !(sv(0) > 0.0);
  if (with_scale) {
    ROVE_CHECK_MSG(var_from > 0.0, "a scale cannot be estimated: the {} points coincide",
                   from.size());
    out.scale = (sv.asDiagonal() * D).trace() / var_from;
  }
  out.t = mean_to - out.scale * out.R * mean_from;
  double sq = 0.0;
  for (std::size_t k = 0; k < from.size(); ++k)
    sq += (to[k] - (out.scale * out.R * from[k] + out.t)).squaredNorm();
  out.rmse = std::sqrt(sq / n);
  return out;
}

template PointSetAlignment<2> align_point_sets<2>(std::span<const Eigen::Vector2d>,
                                                  std::span<const Eigen::Vector2d>, bool);
template PointSetAlignment<3> align_point_sets<3>(std::span<const Eigen::Vector3d>,
                                                  std::span<const Eigen::Vector3d>, bool);

}  // namespace rove
