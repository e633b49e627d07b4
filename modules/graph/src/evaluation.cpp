// Ground-truth comparison after rigid alignment.
#include "rove/graph/evaluation.h"

#include <cmath>
#include <vector>

#include <Eigen/SVD>

#include "rove/core/check.h"

namespace rove {
namespace {

template <class PoseT>
AlignedPositionError aligned_error(const PoseGraph<PoseT>& est, const PoseGraph<PoseT>& truth) {
  constexpr int N = PoseT::kDof == 3 ? 2 : 3;
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  std::vector<Vec> a, b;
  for (const auto& [id, v] : est.vertices()) {
    if (!truth.has_vertex(id)) continue;
    a.push_back(v.pose.translation());
    b.push_back(truth.pose(id).translation());
  }
  ROVE_CHECK_MSG(a.size() >= 3, "only {} vertex ids are common to the estimate and the truth",
                 a.size());
  const double n = static_cast<double>(a.size());
  Vec ma = Vec::Zero(), mb = Vec::Zero();
  for (std::size_t k = 0; k < a.size(); ++k) ma += a[k], mb += b[k];
  ma /= n;
  mb /= n;
  Mat S = Mat::Zero();  // cross-covariance of truth and estimate
  for (std::size_t k = 0; k < a.size(); ++k) S += (b[k] - mb) * (a[k] - ma).transpose();
  Eigen::JacobiSVD<Mat> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat D = Mat::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) D(N - 1, N - 1) = -1.0;
  const Mat R = svd.matrixU() * D * svd.matrixV().transpose();  // truth ≈ R·estimate + t
  const Vec t = mb - R * ma;
  AlignedPositionError out;
  out.matched = a.size();
  double sq = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double e = (R * a[k] + t - b[k]).norm();
    sq += e * e;
    out.max = std::max(out.max, e);
  }
  out.rmse = std::sqrt(sq / n);
  return out;
}

}  // namespace

AlignedPositionError aligned_position_error(const PoseGraph2D& estimate, const PoseGraph2D& truth) {
  return aligned_error(estimate, truth);
}
AlignedPositionError aligned_position_error(const PoseGraph3D& estimate, const PoseGraph3D& truth) {
  return aligned_error(estimate, truth);
}

}  // namespace rove
