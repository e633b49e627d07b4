#pragma once
/// \file
/// Counts that describe a pose graph before anyone optimizes it: vertices,
/// anchors, edges per level, odometry edges against loop closures, and the
/// connectivity over all edges (components, isolated vertices, degrees).

#include <cstddef>
#include <map>

#include "rove/graph/pose_graph.h"

namespace rove {

/// What graph_statistics() counts.
struct GraphStatistics {
  std::size_t vertices = 0;        ///< all vertices
  std::size_t fixed = 0;           ///< anchored vertices
  std::size_t edges = 0;           ///< all edges, every level
  std::size_t odometry_edges = 0;  ///< edges between consecutive ids (|from − to| = 1)
  std::size_t loop_closures = 0;   ///< the other edges
  std::size_t components = 0;      ///< connected components over all edges (isolated
                                   ///< vertices count one each)
  std::size_t isolated = 0;        ///< vertices without any edge
  std::size_t max_degree = 0;      ///< most edges at one vertex
  double mean_degree = 0.0;        ///< 2·edges / vertices (0 without vertices)
  std::map<int, std::size_t> edges_per_level;  ///< level → number of edges
};

/// Counts the statistics of `graph`. O(V + E·α(V)).
template <class PoseT>
GraphStatistics graph_statistics(const PoseGraph<PoseT>& graph);

}  // namespace rove
