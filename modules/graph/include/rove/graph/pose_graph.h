#pragma once
/// \file
/// Pose graphs: vertices are absolute poses T_world_vertex, edges are
/// measured relative poses Z = T_from_to with a full information matrix.
///
/// Error convention (g2o's, and the one every χ² in rove::graph uses): for an
/// edge i → j with measurement Z, the error transform is E = Z⁻¹·(Xi⁻¹·Xj)
/// and the error vector is
///   2D: e = [t_E; θ_E]                (meters, meters, radians),
///   3D: e = [t_E; q_E.xyz]            (q_E the unit quaternion of E with w ≥ 0),
/// so an edge contributes eᵀ·Ω·e to χ² (or ρ(eᵀ·Ω·e) with a robust kernel).
/// The information matrix Ω is expressed in that error vector's coordinates.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/math/robust_kernel.h"
#include "rove/math/se2.h"
#include "rove/math/se3.h"

namespace rove {

/// Identifier of a vertex as written in graph files (any non-negative integer).
using VertexId = std::uint64_t;

/// One vertex: the absolute pose T_world_vertex and whether it is held fixed
/// (anchored) during optimization.
template <class PoseT>
struct PoseGraphVertex {
  PoseT pose;          ///< T_world_vertex
  bool fixed = false;  ///< anchored: never moved by the optimizer
};

/// One relative-pose edge from vertex `from` to vertex `to`.
template <class PoseT>
struct PoseGraphEdge {
  static constexpr int kDof = PoseT::kDof;
  /// Information matrix of the error vector (see the file comment), kDof×kDof.
  using Information = Eigen::Matrix<double, kDof, kDof>;

  VertexId from = 0;               ///< vertex i
  VertexId to = 0;                 ///< vertex j
  PoseT measurement;               ///< Z = measured T_i_j
  Information information = Information::Identity();  ///< Ω, symmetric positive definite
  RobustKernel kernel;             ///< robust kernel of this edge (plain least squares by default)
  int level = 0;                   ///< optimization level (g2o's setLevel): an optimizer run
                                   ///< uses only the edges of its chosen level
};

/// Why an information matrix is not acceptable, or std::nullopt if it is:
/// every entry finite, symmetric (relative tolerance 1e-9) and positive
/// definite (a Cholesky factorization succeeds).
template <int N>
std::optional<std::string> information_problem(const Eigen::Matrix<double, N, N>& information);

/// The symmetric positive definite matrix nearest to `information` by
/// eigenvalue clamping: Ω' = V·max(Λ, f)·Vᵀ with f = relative_floor · max|λ|
/// (relative_floor itself when every λ is 0). With f = 0 this is the nearest
/// positive semidefinite matrix in the Frobenius norm (Higham, "Computing a
/// nearest symmetric positive semidefinite matrix", Linear Algebra Appl.
/// 1988, Theorem 2.1); the floor keeps Ω' invertible, so an edge whose
/// matrix had a negative direction keeps a weak, positive weight along it.
/// `information` is symmetrized first. Preconditions (InvalidArgument): all
/// entries finite, 0 < relative_floor < 1.
template <int N>
Eigen::Matrix<double, N, N> nearest_positive_definite(const Eigen::Matrix<double, N, N>& information,
                                                      double relative_floor = 1e-6);

/// A 2D (PoseT = SE2d) or 3D (PoseT = SE3d) pose graph.
///
/// Vertices are kept ordered by id. Edge indices are positions in edges();
/// remove_edge() and merge_vertices() shift the indices of later edges.
/// Thread-safety: const members may be called concurrently; nothing else.
template <class PoseT>
class PoseGraph {
 public:
  using Pose = PoseT;
  using Vertex = PoseGraphVertex<PoseT>;
  using Edge = PoseGraphEdge<PoseT>;
  using Information = typename Edge::Information;
  static constexpr int kDof = PoseT::kDof;

  /// Adds a vertex. Throws InvalidArgument if `id` already exists.
  void add_vertex(VertexId id, const Pose& pose, bool fixed = false);
  /// True if vertex `id` exists.
  bool has_vertex(VertexId id) const { return vertices_.count(id) != 0; }
  /// Pose of vertex `id`. Throws InvalidArgument if it does not exist.
  const Pose& pose(VertexId id) const;
  /// Replaces the pose of vertex `id`. Throws InvalidArgument if it does not exist.
  void set_pose(VertexId id, const Pose& pose);
  /// Anchors (or releases) vertex `id`. Throws InvalidArgument if it does not exist.
  void set_fixed(VertexId id, bool fixed = true);
  /// True if vertex `id` is anchored. Throws InvalidArgument if it does not exist.
  bool is_fixed(VertexId id) const;
  /// All vertices, ordered by id.
  const std::map<VertexId, Vertex>& vertices() const noexcept { return vertices_; }

  /// Adds an edge and returns its index. Throws InvalidArgument if an end
  /// vertex does not exist, if from == to, or if the information matrix is
  /// not finite, symmetric and positive definite.
  std::size_t add_edge(const Edge& edge);
  /// Convenience: add_edge({from, to, measurement, information}).
  std::size_t add_edge(VertexId from, VertexId to, const Pose& measurement,
                       const Information& information = Information::Identity());
  /// All edges, in insertion order.
  const std::vector<Edge>& edges() const noexcept { return edges_; }
  /// Removes edge `index` (later edges move down by one). Throws
  /// InvalidArgument if index ≥ num_edges().
  void remove_edge(std::size_t index);
  /// Sets the optimization level of edge `index`.
  void set_edge_level(std::size_t index, int level);
  /// Sets the robust kernel of edge `index`.
  void set_edge_kernel(std::size_t index, const RobustKernel& kernel);

  /// Topological merge (MRPT's EQUIV): vertex `drop` becomes vertex `keep`.
  /// Edges touching `drop` are redirected to `keep`; edges that become self
  /// loops are removed; `drop` is deleted (its pose is discarded unless
  /// `keep` had no vertex, in which case `keep` takes it over; keep is fixed
  /// if either was). Returns the number of edges removed. Throws
  /// InvalidArgument if neither vertex exists or keep == drop.
  std::size_t merge_vertices(VertexId keep, VertexId drop);

  std::size_t num_vertices() const noexcept { return vertices_.size(); }
  std::size_t num_edges() const noexcept { return edges_.size(); }
  /// Number of anchored vertices.
  std::size_t num_fixed() const;
  /// Removes everything.
  void clear();

 private:
  Vertex& vertex(VertexId id);
  const Vertex& vertex(VertexId id) const;

  std::map<VertexId, Vertex> vertices_;
  std::vector<Edge> edges_;
};

/// 2D pose graph: vertices and measurements in SE(2) (x, y in m, θ in rad).
using PoseGraph2D = PoseGraph<SE2d>;
/// 3D pose graph: vertices and measurements in SE(3).
using PoseGraph3D = PoseGraph<SE3d>;

extern template class PoseGraph<SE2d>;
extern template class PoseGraph<SE3d>;

}  // namespace rove
