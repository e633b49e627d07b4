#pragma once
/// \file
/// Occupancy grids given on the command line: a ROS map.yaml (with its
/// image), an MRPT .gridmap[.gz] or a rove .rovegrid[.gz].

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "rove/maps/occupancy_grid.h"

namespace rove::cli {

/// True if `s` ends with `suffix`, ignoring ASCII case (suffix lower-case).
bool ends_with_ci(std::string s, std::string_view suffix);

/// A grid read from the command line, with the files it came from.
struct LoadedGrid {
  OccupancyGrid grid;                        ///< the grid
  std::string kind;                          ///< "ROS map", "MRPT gridmap", "rove grid"
  std::vector<std::filesystem::path> files;  ///< every file read (a map.yaml and its image)
  std::vector<std::string> notes;            ///< keys without effect
};

/// Reads a grid from a ROS map.yaml, an MRPT .gridmap or a .rovegrid, told
/// apart by the name's ending. `arg` names the command-line argument in
/// errors (CLI::ValidationError for an unknown ending; IoError/ParseError
/// from the readers).
LoadedGrid load_any_grid(const std::string& path, const std::string& arg);

}  // namespace rove::cli
