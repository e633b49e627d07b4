#pragma once
/// \file
/// An occupancy grid from any of the files rove reads grids from: a ROS
/// map.yaml (with its image), an MRPT .gridmap[.gz] or a rove
/// .rovegrid[.gz], told apart by the name's ending.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "rove/maps/occupancy_grid.h"

namespace rove {

/// The kinds of grid file read_any_grid reads.
enum class GridFileKind {
  RosMap,       ///< map.yaml (.yaml, .yml) and the image it names
  MrptGridmap,  ///< .gridmap or .gridmap.gz
  RoveGrid,     ///< .rovegrid or .rovegrid.gz
};

/// The kind of grid file `path` names by its ending (ASCII case ignored);
/// nullopt for another ending.
std::optional<GridFileKind> grid_file_kind(const std::string& path);

/// A grid read from a file, with the files it came from.
struct LoadedGrid {
  OccupancyGrid grid;                        ///< the grid
  std::string kind;                          ///< "ROS map", "MRPT gridmap", "rove grid"
  std::vector<std::filesystem::path> files;  ///< every file read (a map.yaml and its image)
  std::vector<std::string> notes;            ///< keys without effect
};

/// Reads the grid of a ROS map.yaml, an MRPT .gridmap or a .rovegrid.
/// Throws IoError for another ending (naming the expected ones) or an
/// unreadable file, ParseError from the readers for malformed contents.
LoadedGrid read_any_grid(const std::string& path);

}  // namespace rove
