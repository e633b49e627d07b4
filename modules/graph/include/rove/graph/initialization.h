#pragma once
/// \file
/// Initial guesses for pose-graph optimization. Each function overwrites the
/// poses of the non-fixed vertices and leaves fixed vertices where they are.

#include <cstddef>
#include <optional>
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
  Auto,          ///< the better of AsIs and Chordal by χ² at the start (initialize_best())
};

/// "as-is", "odometry", "spanning-tree", "chordal", "auto".
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

/// Applies `guess` (AsIs does nothing and returns 0; Auto as initialize_best()).
template <class PoseT>
std::size_t initialize(PoseGraph<PoseT>& graph, InitialGuess guess, int level = 0);

/// What initialize_best() chose and why.
struct InitialGuessChoice {
  InitialGuess requested = InitialGuess::Auto;  ///< the guess asked for
  InitialGuess used = InitialGuess::AsIs;       ///< the guess whose poses the graph now holds
  std::size_t vertices_placed = 0;              ///< vertices the used guess placed
  double chi2 = 0.0;                            ///< χ² (edges of `level`) at the used guess
  std::optional<double> as_is_chi2;    ///< Auto: χ² at the stored poses
  std::optional<double> chordal_chi2;  ///< Auto: χ² at the chordal guess (unset if it failed)
  std::string note;  ///< one line: why `used` (Auto), or empty
};

/// Applies `guess` and reports it. For InitialGuess::Auto it evaluates χ² at
/// the stored poses and at the chordal relaxation and keeps the lower (a
/// chordal start is the stored poses' equal or better on every public graph
/// tried: MIT, torus3D, sphere_bignoise end in worse local minima from their
/// stored poses, χ² 770.7 vs 41.2, 19,972 vs 14,575, 892,660 vs 743,863; the
/// stored poses win when they are already near the optimum, e.g. a graph
/// that was optimized before). When the chordal relaxation cannot be
/// computed (a vertex not connected to an anchor), the stored poses are kept
/// and the note says why. Costs one chordal solve and two χ² passes.
template <class PoseT>
InitialGuessChoice initialize_best(PoseGraph<PoseT>& graph, InitialGuess guess, int level = 0);

}  // namespace rove
