// Connectivity and counts of a pose graph.
#include "rove/graph/statistics.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace rove {

template <class PoseT>
GraphStatistics graph_statistics(const PoseGraph<PoseT>& graph) {
  GraphStatistics s;
  s.vertices = graph.num_vertices();
  s.fixed = graph.num_fixed();
  s.edges = graph.num_edges();
  std::unordered_map<VertexId, std::size_t> index;
  index.reserve(s.vertices);
  for (const auto& kv : graph.vertices()) index.emplace(kv.first, index.size());
  // Union-find with path halving.
  std::vector<std::size_t> parent(index.size()), degree(index.size(), 0);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& e : graph.edges()) {
    const std::size_t i = index.at(e.from), j = index.at(e.to);
    parent[find(i)] = find(j);
    ++degree[i];
    ++degree[j];
    ++s.edges_per_level[e.level];
    if (e.to == e.from + 1 || e.from == e.to + 1) ++s.odometry_edges;
  }
  s.loop_closures = s.edges - s.odometry_edges;
  for (std::size_t v = 0; v < parent.size(); ++v) {
    if (find(v) == v) ++s.components;
    if (degree[v] == 0) ++s.isolated;
  }
  s.max_degree = degree.empty() ? 0 : *std::max_element(degree.begin(), degree.end());
  s.mean_degree = s.vertices == 0 ? 0.0
                                  : 2.0 * static_cast<double>(s.edges) /
                                        static_cast<double>(s.vertices);
  return s;
}

template GraphStatistics graph_statistics(const PoseGraph2D&);
template GraphStatistics graph_statistics(const PoseGraph3D&);

}  // namespace rove
