#pragma once
/// \file
/// The picture `rove lidar-slam` draws of its result: the rebuilt grid
/// (free white, occupied black, unknown gray), the optimized path (blue),
/// the accepted loop closures (red, from the submap's origin to the node)
/// and the submaps' origins (green), one pixel per cell (coarser when the
/// grid is wider than max_side), written as a palette PNG.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "rove/maps/occupancy_grid.h"

namespace rove::cli {

/// What the picture shows besides the grid, in the grid's frame (meters).
struct SlamPlotContent {
  std::vector<Eigen::Vector2d> path;                                    ///< robot path
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> loop_edges;  ///< submap → node
  std::vector<Eigen::Vector2d> submap_origins;                          ///< submap frames
};

/// Writes `path` atomically. Throws IoError if it cannot be written,
/// InvalidArgument if the grid has no cells or max_side < 64.
void write_slam_plot(const OccupancyGrid& grid, const SlamPlotContent& content,
                     const std::string& path, int max_side = 4096);

}  // namespace rove::cli
