#include "grid_input.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cctype>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/grid_binary.h"
#include "rove/io/grid_image.h"
#include "rove/io/mrpt_gridmap.h"

namespace rove::cli {

bool ends_with_ci(std::string s, std::string_view suffix) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s.ends_with(suffix);
}

LoadedGrid load_any_grid(const std::string& path, const std::string& arg) {
  LoadedGrid g;
  g.files.push_back(path);
  if (ends_with_ci(path, ".yaml") || ends_with_ci(path, ".yml")) {
    RosMap m = load_ros_map(path);
    for (const auto& k : m.yaml.unknown_keys) {
      g.notes.push_back(fmt::format("{} key '{}'", printable(path), printable(k)));
    }
    g.kind = "ROS map";
    g.files.push_back(m.image_path);
    g.grid = std::move(m.grid);
    return g;
  }
  if (ends_with_ci(path, ".gridmap") || ends_with_ci(path, ".gridmap.gz")) {
    check_regular_input(path, "grid map");
    g.kind = "MRPT gridmap";
    g.grid = load_mrpt_gridmap(path).grid;
    return g;
  }
  if (ends_with_ci(path, ".rovegrid") || ends_with_ci(path, ".rovegrid.gz")) {
    check_regular_input(path, "grid map");
    g.kind = "rove grid";
    g.grid = load_grid(path);
    return g;
  }
  throw CLI::ValidationError(arg, fmt::format("{}: unknown input kind (expected .yaml, "
                                              ".gridmap[.gz] or .rovegrid[.gz])",
                                              printable(path)));
}

}  // namespace rove::cli
