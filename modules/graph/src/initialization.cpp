// Initial guesses: odometry chain, spanning tree, chordal relaxation.
#include "rove/graph/initialization.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <unordered_map>

#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/graph/optimizer.h"

namespace rove {
namespace {

// Pose of `to_place` from the pose of `known` through edge e.
template <class PoseT>
PoseT through_edge(const PoseGraphEdge<PoseT>& e, VertexId known, const PoseT& known_pose) {
  return e.from == known ? known_pose * e.measurement : known_pose * e.measurement.inverse();
}

template <class PoseT>
struct Adjacency {
  // Vertex id → dense index (ids in increasing order), and per vertex the
  // edge indices touching it, in edge order.
  std::vector<VertexId> ids;
  std::unordered_map<VertexId, std::size_t> index;
  std::vector<std::vector<std::size_t>> edges_of;
};

template <class PoseT>
Adjacency<PoseT> adjacency(const PoseGraph<PoseT>& graph, std::optional<int> level) {
  Adjacency<PoseT> a;
  a.ids.reserve(graph.num_vertices());
  for (const auto& kv : graph.vertices()) {
    a.index.emplace(kv.first, a.ids.size());
    a.ids.push_back(kv.first);
  }
  a.edges_of.resize(a.ids.size());
  const auto& edges = graph.edges();
  for (std::size_t k = 0; k < edges.size(); ++k) {
    if (level && edges[k].level != *level) continue;
    a.edges_of[a.index.at(edges[k].from)].push_back(k);
    a.edges_of[a.index.at(edges[k].to)].push_back(k);
  }
  return a;
}

// Anchors: fixed vertices touched by the edges, else the lowest-id touched vertex.
template <class PoseT>
std::vector<std::size_t> anchors(const PoseGraph<PoseT>& graph, const Adjacency<PoseT>& a) {
  std::vector<std::size_t> out;
  for (std::size_t v = 0; v < a.ids.size(); ++v)
    if (!a.edges_of[v].empty() && graph.is_fixed(a.ids[v])) out.push_back(v);
  if (out.empty()) {
    for (std::size_t v = 0; v < a.ids.size(); ++v) {
      if (!a.edges_of[v].empty()) {
        out.push_back(v);
        break;
      }
    }
  }
  return out;
}

// Breadth-first tree from the anchors: parent edge per vertex (or npos).
template <class PoseT>
std::vector<std::size_t> bfs_tree(const PoseGraph<PoseT>& graph, const Adjacency<PoseT>& a,
                                  const std::vector<std::size_t>& roots,
                                  std::vector<std::size_t>& order) {
  constexpr std::size_t npos = static_cast<std::size_t>(-1);
  std::vector<std::size_t> parent_edge(a.ids.size(), npos);
  std::vector<char> seen(a.ids.size(), 0);
  std::deque<std::size_t> queue;
  for (std::size_t r : roots) {
    seen[r] = 1;
    queue.push_back(r);
  }
  const auto& edges = graph.edges();
  order.clear();
  while (!queue.empty()) {
    const std::size_t v = queue.front();
    queue.pop_front();
    order.push_back(v);
    for (std::size_t k : a.edges_of[v]) {
      const VertexId other = edges[k].from == a.ids[v] ? edges[k].to : edges[k].from;
      const std::size_t w = a.index.at(other);
      if (seen[w]) continue;
      seen[w] = 1;
      parent_edge[w] = k;
      queue.push_back(w);
    }
  }
  return parent_edge;
}

// Nearest rotation (Frobenius) to M; M may be any 3x3 matrix.
Eigen::Matrix3d project_to_so3(const Eigen::Matrix3d& M) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) S(2, 2) = -1.0;
  return svd.matrixU() * S * svd.matrixV().transpose();
}

template <int K>
using Block = Eigen::Matrix<double, K, K>;

// Solves the sparse normal equations Σ over block rows; throws NumericError
// naming the problem if the system is singular.
Eigen::MatrixXd solve_normal(int n, int k, const std::vector<Eigen::Triplet<double>>& trip,
                             const Eigen::MatrixXd& rhs, const char* what) {
  Eigen::SparseMatrix<double> H(n * k, n * k);
  H.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
  if (ldlt.info() != Eigen::Success) {
    throw NumericError(fmt::format("chordal initialization: the {} system is singular", what));
  }
  Eigen::MatrixXd x = ldlt.solve(rhs);
  if (!x.allFinite()) {
    throw NumericError(fmt::format("chordal initialization: the {} system gave NaN", what));
  }
  return x;
}

void add_block(std::vector<Eigen::Triplet<double>>& trip, int r, int c, const Eigen::MatrixXd& B) {
  for (Eigen::Index i = 0; i < B.rows(); ++i)
    for (Eigen::Index j = 0; j < B.cols(); ++j)
      if (B(i, j) != 0.0)
        trip.emplace_back(r + static_cast<int>(i), c + static_cast<int>(j), B(i, j));
}

}  // namespace

std::string_view to_string(InitialGuess guess) {
  switch (guess) {
    case InitialGuess::AsIs: return "as-is";
    case InitialGuess::Odometry: return "odometry";
    case InitialGuess::SpanningTree: return "spanning-tree";
    case InitialGuess::Chordal: return "chordal";
    case InitialGuess::Auto: return "auto";
  }
  return "?";
}

InitialGuess parse_initial_guess(std::string_view text) {
  if (text == "as-is" || text == "none" || text == "file") return InitialGuess::AsIs;
  if (text == "odometry") return InitialGuess::Odometry;
  if (text == "spanning-tree" || text == "dijkstra") return InitialGuess::SpanningTree;
  if (text == "chordal") return InitialGuess::Chordal;
  if (text == "auto") return InitialGuess::Auto;
  ROVE_CHECK_MSG(false, "unknown initial guess '{}' (expected auto, as-is, odometry, "
                        "spanning-tree or chordal)", text);
  return InitialGuess::AsIs;
}

template <class PoseT>
std::size_t initialize_odometry(PoseGraph<PoseT>& graph) {
  const Adjacency<PoseT> a = adjacency(graph, std::nullopt);
  const auto& edges = graph.edges();
  std::vector<char> placed(a.ids.size(), 0);
  std::size_t count = 0;
  for (std::size_t v = 0; v < a.ids.size(); ++v) {
    const VertexId id = a.ids[v];
    if (v == 0 || graph.is_fixed(id)) {
      placed[v] = 1;
      continue;
    }
    const VertexId prev = a.ids[v - 1];
    std::size_t chosen = static_cast<std::size_t>(-1);
    for (std::size_t k : a.edges_of[v]) {
      const VertexId other = edges[k].from == id ? edges[k].to : edges[k].from;
      if (other == prev) {
        chosen = k;
        break;
      }
    }
    if (chosen == static_cast<std::size_t>(-1)) {
      for (std::size_t k : a.edges_of[v]) {
        const VertexId other = edges[k].from == id ? edges[k].to : edges[k].from;
        if (placed[a.index.at(other)]) {
          chosen = k;
          break;
        }
      }
    }
    placed[v] = 1;
    if (chosen == static_cast<std::size_t>(-1)) continue;
    const auto& e = edges[chosen];
    const VertexId other = e.from == id ? e.to : e.from;
    graph.set_pose(id, through_edge(e, other, graph.pose(other)));
    ++count;
  }
  return count;
}

template <class PoseT>
std::size_t initialize_spanning_tree(PoseGraph<PoseT>& graph, int level) {
  const Adjacency<PoseT> a = adjacency(graph, level);
  const std::vector<std::size_t> roots = anchors(graph, a);
  std::vector<std::size_t> order;
  const auto parent = bfs_tree(graph, a, roots, order);
  const auto& edges = graph.edges();
  std::size_t count = 0;
  for (std::size_t v : order) {
    const std::size_t k = parent[v];
    if (k == static_cast<std::size_t>(-1) || graph.is_fixed(a.ids[v])) continue;
    const auto& e = edges[k];
    const VertexId other = e.from == a.ids[v] ? e.to : e.from;
    graph.set_pose(a.ids[v], through_edge(e, other, graph.pose(other)));
    ++count;
  }
  return count;
}

template <class PoseT>
std::size_t initialize_chordal(PoseGraph<PoseT>& graph, int level) {
  constexpr bool k3d = PoseT::kDof == 6;
  constexpr int K = k3d ? 3 : 2;  // unknowns per vertex in the rotation system
  const Adjacency<PoseT> a = adjacency(graph, level);
  const std::vector<std::size_t> roots = anchors(graph, a);
  std::vector<std::size_t> order;
  const auto parent = bfs_tree(graph, a, roots, order);
  // Unknowns: every touched, reached, non-anchor vertex.
  std::vector<char> is_root(a.ids.size(), 0);
  for (std::size_t r : roots) is_root[r] = 1;
  std::vector<int> var(a.ids.size(), -1);
  std::vector<VertexId> unreached;
  int n = 0;
  for (std::size_t v = 0; v < a.ids.size(); ++v) {
    if (a.edges_of[v].empty() || is_root[v]) continue;
    if (parent[v] == static_cast<std::size_t>(-1)) {
      unreached.push_back(a.ids[v]);
      continue;
    }
    var[v] = n++;
  }
  if (!unreached.empty()) {
    std::string list;
    for (std::size_t k = 0; k < unreached.size() && k < 10; ++k)
      list += (k ? ", " : "") + std::to_string(unreached[k]);
    throw NumericError(fmt::format(
        "chordal initialization: {} vertices are not connected to an anchor (e.g. {})",
        unreached.size(), list));
  }
  if (n == 0) return 0;
  const auto& edges = graph.edges();
  std::vector<std::size_t> used;
  for (std::size_t k = 0; k < edges.size(); ++k)
    if (edges[k].level == level) used.push_back(k);

  // 1) Rotations. 2D: z = (cos θ, sin θ) with z_j = M(θ_ij) z_i; 3D: each row
  // r of R with r_jᵀ = R_ijᵀ r_iᵀ (three right-hand sides).
  auto rotation_of = [](const PoseT& p) -> Eigen::Matrix<double, K, K> {
    return p.rotation_matrix();
  };
  auto known_unknowns = [&](const PoseT& p) -> Eigen::Matrix<double, K, Eigen::Dynamic> {
    if constexpr (k3d) {
      return p.rotation_matrix().transpose();  // column a = row a of R
    } else {
      Eigen::Matrix<double, 2, Eigen::Dynamic> z(2, 1);
      z << std::cos(p.angle()), std::sin(p.angle());
      return z;
    }
  };
  const int rhs_cols = k3d ? 3 : 1;
  {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n * K, rhs_cols);
    for (std::size_t k : used) {
      const auto& e = edges[k];
      const std::size_t vi = a.index.at(e.from), vj = a.index.at(e.to);
      const int xi = var[vi], xj = var[vj];
      if (xi < 0 && xj < 0) continue;
      Eigen::Matrix<double, K, K> A;
      if constexpr (k3d) {
        A = e.measurement.rotation_matrix().transpose();
      } else {
        A = rotation_of(e.measurement);
      }
      const double w = e.information.template bottomRightCorner<PoseT::kDof - K, PoseT::kDof - K>()
                           .trace() /
                       (PoseT::kDof - K);
      const Block<K> I = Block<K>::Identity();
      // Residual x_j − A x_i.
      if (xj >= 0) add_block(trip, xj * K, xj * K, w * I);
      if (xi >= 0) add_block(trip, xi * K, xi * K, w * A.transpose() * A);
      if (xi >= 0 && xj >= 0) {
        add_block(trip, xi * K, xj * K, -w * A.transpose());
        add_block(trip, xj * K, xi * K, -w * A);
      }
      if (xi < 0) rhs.middleRows(xj * K, K) += w * A * known_unknowns(graph.pose(e.from));
      if (xj < 0) rhs.middleRows(xi * K, K) += w * A.transpose() * known_unknowns(graph.pose(e.to));
    }
    const Eigen::MatrixXd x = solve_normal(n, K, trip, rhs, "rotation");
    for (std::size_t v = 0; v < a.ids.size(); ++v) {
      if (var[v] < 0) continue;
      const PoseT old = graph.pose(a.ids[v]);
      if constexpr (k3d) {
        const Eigen::Matrix3d M = x.middleRows(var[v] * 3, 3).transpose();
        graph.set_pose(a.ids[v], SE3d(SO3d::from_matrix_orthonormalized(project_to_so3(M)),
                                      old.translation()));
      } else {
        const double theta = std::atan2(x(var[v] * 2 + 1, 0), x(var[v] * 2, 0));
        graph.set_pose(a.ids[v], SE2d(SO2d::from_angle(theta), old.translation()));
      }
    }
  }
  // 2) Translations: t_j − t_i = R_i t_ij, weighted by the translational
  // information rotated into the world frame.
  {
    constexpr int T = k3d ? 3 : 2;
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n * T, 1);
    for (std::size_t k : used) {
      const auto& e = edges[k];
      const std::size_t vi = a.index.at(e.from), vj = a.index.at(e.to);
      const int xi = var[vi], xj = var[vj];
      if (xi < 0 && xj < 0) continue;
      const PoseT& Pi = graph.pose(e.from);
      const Eigen::Matrix<double, T, T> Ri = Pi.rotation_matrix();
      const Eigen::Matrix<double, T, T> Rz = e.measurement.rotation_matrix();
      const Eigen::Matrix<double, T, T> W =
          (Ri * Rz) * e.information.template topLeftCorner<T, T>() * (Ri * Rz).transpose();
      const Eigen::Matrix<double, T, 1> c = Ri * e.measurement.translation();
      if (xi >= 0) add_block(trip, xi * T, xi * T, W);
      if (xj >= 0) add_block(trip, xj * T, xj * T, W);
      if (xi >= 0 && xj >= 0) {
        add_block(trip, xi * T, xj * T, -W);
        add_block(trip, xj * T, xi * T, -W);
      }
      // Normal equations of r = t_j − t_i − c.
      if (xj >= 0) {
        Eigen::Matrix<double, T, 1> b = W * c;
        if (xi < 0) b += W * Pi.translation();
        rhs.middleRows(xj * T, T) += b;
      }
      if (xi >= 0) {
        Eigen::Matrix<double, T, 1> b = -W * c;
        if (xj < 0) b += W * graph.pose(e.to).translation();
        rhs.middleRows(xi * T, T) += b;
      }
    }
    const Eigen::MatrixXd x = solve_normal(n, T, trip, rhs, "translation");
    for (std::size_t v = 0; v < a.ids.size(); ++v) {
      if (var[v] < 0) continue;
      const PoseT old = graph.pose(a.ids[v]);
      graph.set_pose(a.ids[v], PoseT(old.rotation(), x.middleRows(var[v] * T, T)));
    }
  }
  return static_cast<std::size_t>(n);
}

template <class PoseT>
std::size_t initialize(PoseGraph<PoseT>& graph, InitialGuess guess, int level) {
  switch (guess) {
    case InitialGuess::AsIs: return 0;
    case InitialGuess::Odometry: return initialize_odometry(graph);
    case InitialGuess::SpanningTree: return initialize_spanning_tree(graph, level);
    case InitialGuess::Chordal: return initialize_chordal(graph, level);
    case InitialGuess::Auto: return initialize_best(graph, guess, level).vertices_placed;
  }
  return 0;
}

template <class PoseT>
InitialGuessChoice initialize_best(PoseGraph<PoseT>& graph, InitialGuess guess, int level) {
  InitialGuessChoice choice;
  choice.requested = guess;
  if (guess != InitialGuess::Auto) {
    choice.used = guess;
    choice.vertices_placed = initialize(graph, guess, level);
    choice.chi2 = compute_chi2(graph, level);
    return choice;
  }
  const double as_is = compute_chi2(graph, level);
  choice.as_is_chi2 = as_is;
  PoseGraph<PoseT> chordal = graph;
  std::size_t placed = 0;
  try {
    placed = initialize_chordal(chordal, level);
  } catch (const NumericError& e) {
    choice.used = InitialGuess::AsIs;
    choice.chi2 = as_is;
    choice.note = fmt::format("stored poses kept: the chordal relaxation failed ({})", e.what());
    return choice;
  }
  const double c = compute_chi2(chordal, level);
  choice.chordal_chi2 = c;
  // NaN compares false: a NaN at the stored poses picks the chordal guess.
  if (!(as_is < c)) {
    graph = std::move(chordal);
    choice.used = InitialGuess::Chordal;
    choice.vertices_placed = placed;
    choice.chi2 = c;
    choice.note = fmt::format("chordal: χ² {:.6g} at the chordal guess vs {:.6g} at the stored poses",
                              c, as_is);
  } else {
    choice.used = InitialGuess::AsIs;
    choice.chi2 = as_is;
    choice.note = fmt::format("stored poses: χ² {:.6g} vs {:.6g} at the chordal guess", as_is, c);
  }
  return choice;
}

template std::size_t initialize_odometry(PoseGraph2D&);
template std::size_t initialize_odometry(PoseGraph3D&);
template std::size_t initialize_spanning_tree(PoseGraph2D&, int);
template std::size_t initialize_spanning_tree(PoseGraph3D&, int);
template std::size_t initialize_chordal(PoseGraph2D&, int);
template std::size_t initialize_chordal(PoseGraph3D&, int);
template std::size_t initialize(PoseGraph2D&, InitialGuess, int);
template std::size_t initialize(PoseGraph3D&, InitialGuess, int);
template InitialGuessChoice initialize_best(PoseGraph2D&, InitialGuess, int);
template InitialGuessChoice initialize_best(PoseGraph3D&, InitialGuess, int);

}  // namespace rove
