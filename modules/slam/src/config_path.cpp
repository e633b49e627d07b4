#include "rove/slam/config_path.h"

#include <filesystem>

#include <fmt/format.h>

#include "rove/core/error.h"

namespace rove {

std::string resolve_config_path(const std::string& config_file, const std::string& section,
                                const std::string& key, const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return path;
  if (fs::exists(path)) return path;
  const fs::path beside = fs::path(config_file).parent_path() / path;
  if (fs::path(path).is_relative() && fs::exists(beside)) return beside.string();
  throw ConfigError(config_file, section, key,
                    fmt::format("'{}' does not exist{}", path,
                                fs::path(path).is_relative()
                                    ? fmt::format(" (also tried '{}')", beside.string())
                                    : std::string()));
}

}  // namespace rove
