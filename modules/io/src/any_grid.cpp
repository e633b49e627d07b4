#include "rove/io/any_grid.h"

#include <fmt/format.h>

#include <cctype>
#include <string_view>
#include <utility>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/grid_binary.h"
#include "rove/io/grid_image.h"
#include "rove/io/mrpt_gridmap.h"

namespace rove {

namespace {

bool ends_with_lower(std::string s, std::string_view suffix) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s.ends_with(suffix);
}

}  // namespace

std::optional<GridFileKind> grid_file_kind(const std::string& path) {
  if (ends_with_lower(path, ".yaml") || ends_with_lower(path, ".yml")) return GridFileKind::RosMap;
  if (ends_with_lower(path, ".gridmap") || ends_with_lower(path, ".gridmap.gz")) return GridFileKind::MrptGridmap;
  if (ends_with_lower(path, ".rovegrid") || ends_with_lower(path, ".rovegrid.gz")) return GridFileKind::RoveGrid;
  return std::nullopt;
}

LoadedGrid read_any_grid(const std::string& path) {
  const std::optional<GridFileKind> kind = grid_file_kind(path);
  if (!kind)
    throw IoError(printable(path), "unknown input kind (expected .yaml, .gridmap[.gz] or .rovegrid[.gz])");
  LoadedGrid g;
  g.files.push_back(path);
  switch (*kind) {
    case GridFileKind::RosMap: {
      RosMap m = load_ros_map(path);
      for (const auto& k : m.yaml.unknown_keys) {
        g.notes.push_back(fmt::format("{} key '{}'", printable(path), printable(k)));
      }
      g.kind = "ROS map";
      g.files.push_back(m.image_path);
      g.grid = std::move(m.grid);
      break;
    }
    case GridFileKind::MrptGridmap:
      check_regular_input(path, "grid map");
      g.kind = "MRPT gridmap";
      g.grid = load_mrpt_gridmap(path).grid;
      break;
    case GridFileKind::RoveGrid:
      check_regular_input(path, "grid map");
      g.kind = "rove grid";
      g.grid = load_grid(path);
      break;
  }
  return g;
}

}  // namespace rove
