#include "grid_input.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cctype>

#include "rove/core/files.h"

namespace rove::cli {

bool ends_with_ci(std::string s, std::string_view suffix) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s.ends_with(suffix);
}

LoadedGrid load_any_grid(const std::string& path, const std::string& arg) {
  if (!grid_file_kind(path)) {
    throw CLI::ValidationError(arg, fmt::format("{}: unknown input kind (expected .yaml, "
                                                ".gridmap[.gz] or .rovegrid[.gz])",
                                                printable(path)));
  }
  return read_any_grid(path);
}

}  // namespace rove::cli
