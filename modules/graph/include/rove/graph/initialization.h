#pragma once
/// \file
/// Initial guesses for pose-graph optimization. Each function overwrites the
/// poses of the non-fixed vertices and leaves fixed vertices where they are.

#include <cstddef>
#include <string>
#include <string_view>

#include "rove/graph/pose_graph.h"

namespace rove {

/// How an optimizer run is initialized.
enum class InitialGuess {
  AsIs,          ///< the poses stored in the graph (e.g. the file's vertices)
  Odometry,      ///< initialize_odometry()
  SpanningTree,  ///< initialize_spanning_tree()
  Chordal,       ///< initialize_chordal()
};

/// "as-is", "odometry", "spanning-tree", "chordal".
std::string_view to_string(InitialGuess guess);
/// Inverse of to_string(InitialGuess); throws InvalidArgument on other text.
InitialGuess parse_initial_guess(std::string_view text);

/// Odometry chain. Vertices are visited in increasing id; the first keeps
/// its pose. Each later vertex v is placed by composing the first edge (in
/// edge order) between v and the vertex just before it in id order; if there
/// is none, the first edge between v and any already placed vertex; if there
/// is none either, v keeps its pose and starts a new chain. Edges of every
/// level are used. Returns the number of vertices placed by an edge.
template <class PoseT>
std::size_t initialize_odometry(PoseGraph<PoseT>& graph);

/// Spanning tree (MRPT's graph-slam --dijkstra): a shortest-path tree by
/// number of edges from the anchors (the fixed vertices, or the vertex with
/// the smallest id when none is fixed), ties broken by the lower edge index;
/// each vertex is placed by composing the tree edges from its root. Only
/// edges of `level` are used. Vertices not reached keep their pose. Returns
/// the number of vertices placed.
template <class PoseT>
std::size_t initialize_spanning_tree(PoseGraph<PoseT>& graph, int level = 0);

/// Chordal relaxation (Carlone, Tron, Daniilidis, Dellaert, "Initialization
/// techniques for 3D SLAM: a survey on rotation estimation and its use in
/// pose graph optimization", ICRA 2015, Sec. IV): rotations first, as the
/// linear least-squares solution of Ri·Rij = Rj over the entries of the
/// rotation matrices (weighted by the mean rotational information of each
/// edge), projected to SO(n); then translations by linear least squares on
/// tj − ti = Ri·tij with Ω's translational block. Anchors as in
/// initialize_spanning_tree(). Only edges of `level` are used. Throws
/// NumericError naming the problem if a linear system is singular (a vertex
/// not connected to an anchor). Returns the number of vertices placed.
template <class PoseT>
std::size_t initialize_chordal(PoseGraph<PoseT>& graph, int level = 0);

/// Applies `guess` (AsIs does nothing and returns 0).
template <class PoseT>
std::size_t initialize(PoseGraph<PoseT>& graph, InitialGuess guess, int level = 0);

}  // namespace rove
