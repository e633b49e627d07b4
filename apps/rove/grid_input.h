#pragma once
/// \file
/// Occupancy grids given on the command line: a ROS map.yaml (with its
/// image), an MRPT .gridmap[.gz] or a rove .rovegrid[.gz] (rove/io/any_grid.h).

#include <string>
#include <string_view>

#include "rove/io/any_grid.h"

namespace rove::cli {

/// True if `s` ends with `suffix`, ignoring ASCII case (suffix lower-case).
bool ends_with_ci(std::string s, std::string_view suffix);

/// read_any_grid, with an unknown ending reported as a usage error of the
/// command-line argument `arg` (CLI::ValidationError).
LoadedGrid load_any_grid(const std::string& path, const std::string& arg);

}  // namespace rove::cli
