// Ground-truth comparison after rigid alignment.
#include "rove/graph/evaluation.h"

#include <algorithm>
#include <vector>

#include "rove/core/check.h"
#include "rove/math/point_set_alignment.h"

namespace rove {
namespace {

template <class PoseT>
AlignedPositionError aligned_error(const PoseGraph<PoseT>& est, const PoseGraph<PoseT>& truth) {
  constexpr int N = PoseT::kDof == 3 ? 2 : 3;
  using Vec = Eigen::Matrix<double, N, 1>;
  std::vector<Vec> a, b;
  for (const auto& [id, v] : est.vertices()) {
    if (!truth.has_vertex(id)) continue;
    a.push_back(v.pose.translation());
    b.push_back(truth.pose(id).translation());
  }
  ROVE_CHECK_MSG(a.size() >= 3, "only {} vertex ids are common to the estimate and the truth",
                 a.size());
  const PointSetAlignment<N> fit = align_point_sets<N>(a, b);
  AlignedPositionError out;
  out.matched = a.size();
  out.rmse = fit.rmse;
  for (std::size_t k = 0; k < a.size(); ++k)
    out.max = std::max(out.max, (fit.R * a[k] + fit.t - b[k]).norm());
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
