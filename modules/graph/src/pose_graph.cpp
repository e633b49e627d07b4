// Pose graphs: storage of vertices, edges, anchors and topological merges.
#include "rove/graph/pose_graph.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {

template <int N>
std::optional<std::string> information_problem(const Eigen::Matrix<double, N, N>& information) {
  if (!information.allFinite()) return std::string("information matrix has a NaN or infinite entry");
  const double scale = information.cwiseAbs().maxCoeff();
  const double asym = (information - information.transpose()).cwiseAbs().maxCoeff();
  if (asym > 1e-9 * scale) {
    return fmt::format("information matrix is not symmetric (max |Ω - Ωᵀ| = {})", asym);
  }
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(information);
  if (scale <= 0.0 || llt.info() != Eigen::Success) {
    return std::string("information matrix is not positive definite");
  }
  // A Cholesky factorization can succeed on a matrix whose smallest pivot is
  // lost in rounding; require a pivot above the relative noise floor.
  const double min_pivot = llt.matrixLLT().diagonal().minCoeff();
  if (!(min_pivot * min_pivot > 1e-14 * scale)) {
    return std::string("information matrix is numerically singular (not positive definite)");
  }
  return std::nullopt;
}

template <int N>
Eigen::Matrix<double, N, N> nearest_positive_definite(const Eigen::Matrix<double, N, N>& information,
                                                      double relative_floor) {
  using Mat = Eigen::Matrix<double, N, N>;
  ROVE_CHECK_MSG(information.allFinite(), "nearest_positive_definite: a non-finite entry");
  ROVE_CHECK_MSG(relative_floor > 0.0 && relative_floor < 1.0,
                 "nearest_positive_definite: relative_floor {} outside (0, 1)", relative_floor);
  const Mat sym = 0.5 * (information + information.transpose());
  Eigen::SelfAdjointEigenSolver<Mat> eig(sym);
  const auto& lambda = eig.eigenvalues();
  const double scale = lambda.cwiseAbs().maxCoeff();
  const double floor = relative_floor * (scale > 0.0 ? scale : 1.0);
  const Eigen::Matrix<double, N, 1> clamped = lambda.cwiseMax(floor);
  const Mat out = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
  return 0.5 * (out + out.transpose());
}

template Eigen::Matrix<double, 3, 3> nearest_positive_definite<3>(const Eigen::Matrix<double, 3, 3>&,
                                                                  double);
template Eigen::Matrix<double, 6, 6> nearest_positive_definite<6>(const Eigen::Matrix<double, 6, 6>&,
                                                                  double);

template std::optional<std::string> information_problem<3>(const Eigen::Matrix<double, 3, 3>&);
template std::optional<std::string> information_problem<6>(const Eigen::Matrix<double, 6, 6>&);

template <class PoseT>
typename PoseGraph<PoseT>::Vertex& PoseGraph<PoseT>::vertex(VertexId id) {
  auto it = vertices_.find(id);
  ROVE_CHECK_MSG(it != vertices_.end(), "vertex {} does not exist", id);
  return it->second;
}

template <class PoseT>
const typename PoseGraph<PoseT>::Vertex& PoseGraph<PoseT>::vertex(VertexId id) const {
  auto it = vertices_.find(id);
  ROVE_CHECK_MSG(it != vertices_.end(), "vertex {} does not exist", id);
  return it->second;
}

template <class PoseT>
void PoseGraph<PoseT>::add_vertex(VertexId id, const Pose& pose, bool fixed) {
  const bool inserted = vertices_.emplace(id, Vertex{pose, fixed}).second;
  ROVE_CHECK_MSG(inserted, "vertex {} already exists", id);
}

template <class PoseT>
const PoseT& PoseGraph<PoseT>::pose(VertexId id) const {
  return vertex(id).pose;
}

template <class PoseT>
void PoseGraph<PoseT>::set_pose(VertexId id, const Pose& pose) {
  vertex(id).pose = pose;
}

template <class PoseT>
void PoseGraph<PoseT>::set_fixed(VertexId id, bool fixed) {
  vertex(id).fixed = fixed;
}

template <class PoseT>
bool PoseGraph<PoseT>::is_fixed(VertexId id) const {
  return vertex(id).fixed;
}

template <class PoseT>
std::size_t PoseGraph<PoseT>::add_edge(const Edge& edge) {
  ROVE_CHECK_MSG(has_vertex(edge.from), "edge {} -> {}: vertex {} does not exist", edge.from,
                 edge.to, edge.from);
  ROVE_CHECK_MSG(has_vertex(edge.to), "edge {} -> {}: vertex {} does not exist", edge.from,
                 edge.to, edge.to);
  ROVE_CHECK_MSG(edge.from != edge.to, "edge {} -> {} is a self loop", edge.from, edge.to);
  if (auto problem = information_problem<kDof>(edge.information)) {
    ROVE_CHECK_MSG(false, "edge {} -> {}: {}", edge.from, edge.to, *problem);
  }
  edges_.push_back(edge);
  return edges_.size() - 1;
}

template <class PoseT>
std::size_t PoseGraph<PoseT>::add_edge(VertexId from, VertexId to, const Pose& measurement,
                                       const Information& information) {
  Edge e;
  e.from = from;
  e.to = to;
  e.measurement = measurement;
  e.information = information;
  return add_edge(e);
}

template <class PoseT>
void PoseGraph<PoseT>::remove_edge(std::size_t index) {
  ROVE_CHECK_LT(index, edges_.size());
  edges_.erase(edges_.begin() + static_cast<std::ptrdiff_t>(index));
}

template <class PoseT>
void PoseGraph<PoseT>::set_edge_level(std::size_t index, int level) {
  ROVE_CHECK_LT(index, edges_.size());
  edges_[index].level = level;
}

template <class PoseT>
void PoseGraph<PoseT>::set_edge_kernel(std::size_t index, const RobustKernel& kernel) {
  ROVE_CHECK_LT(index, edges_.size());
  edges_[index].kernel = kernel;
}

template <class PoseT>
std::size_t PoseGraph<PoseT>::merge_vertices(VertexId keep, VertexId drop) {
  ROVE_CHECK_NE(keep, drop);
  auto it_drop = vertices_.find(drop);
  auto it_keep = vertices_.find(keep);
  ROVE_CHECK_MSG(it_drop != vertices_.end() || it_keep != vertices_.end(),
                 "cannot merge vertex {} into {}: neither exists", drop, keep);
  if (it_drop != vertices_.end()) {
    if (it_keep == vertices_.end()) {
      vertices_.emplace(keep, it_drop->second);
    } else {
      it_keep->second.fixed = it_keep->second.fixed || it_drop->second.fixed;
    }
    vertices_.erase(drop);
  }
  for (Edge& e : edges_) {
    if (e.from == drop) e.from = keep;
    if (e.to == drop) e.to = keep;
  }
  const std::size_t before = edges_.size();
  std::erase_if(edges_, [](const Edge& e) { return e.from == e.to; });
  return before - edges_.size();
}

template <class PoseT>
std::size_t PoseGraph<PoseT>::num_fixed() const {
  return static_cast<std::size_t>(std::count_if(
      vertices_.begin(), vertices_.end(), [](const auto& kv) { return kv.second.fixed; }));
}

template <class PoseT>
void PoseGraph<PoseT>::clear() {
  vertices_.clear();
  edges_.clear();
}

template class PoseGraph<SE2d>;
template class PoseGraph<SE3d>;

}  // namespace rove
