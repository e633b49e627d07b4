#pragma once
/// \file
/// Views of an OccupancyOctree for other tools: its occupied cells as a point
/// cloud (written as PLY or PCD by rove::io), and a horizontal slice as an
/// occupancy grid (written as a ROS map_server image + map.yaml by rove::io).

#include <optional>

#include "rove/maps/occupancy_grid.h"
#include "rove/maps/occupancy_octree.h"
#include "rove/maps/point_cloud.h"

namespace rove {

/// Options of octree_occupied_cloud.
struct OctreeCloudOptions {
  /// One point per finest cell of a pruned leaf (else one per leaf, at its
  /// centre).
  bool finest_cells = false;
  /// Refuse (ResourceError) a cloud of more points than this.
  std::size_t max_points = 100'000'000;
};

/// The centres of the occupied leaves (map frame, meters, float), in the
/// tree's depth-first order, with the leaves' colours when the tree has the
/// Color channel.
PointCloud octree_occupied_cloud(const OccupancyOctree& tree, const OctreeCloudOptions& options = {});

/// Options of octree_slice.
struct OctreeSliceOptions {
  /// The area to cover, meters (min x, min y, max x, max y); default: the
  /// tree's known cells.
  std::optional<Eigen::Vector4d> area;
  /// Refuse (ResourceError) a grid of more cells than this.
  std::size_t max_cells = 200'000'000;
};

/// The cells of the tree at height `z` (meters) as a 2D occupancy grid of
/// the tree's resolution, aligned with its cells: each grid cell holds the
/// occupancy probability of the leaf at (x, y, z), unknown cells 0.5.
/// Throws InvalidArgument if z is not finite or outside the tree.
OccupancyGrid octree_slice(const OccupancyOctree& tree, double z, const OctreeSliceOptions& options = {});

}  // namespace rove
