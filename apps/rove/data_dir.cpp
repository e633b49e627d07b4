#include "data_dir.h"

#include <unistd.h>

#include <cstdlib>
#include <string>
#include <system_error>

#include "rove/core/error.h"

namespace rove::cli {

namespace {
std::filesystem::path executable_dir() {
  std::error_code ec;
  auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}
}  // namespace

std::filesystem::path data_dir() {
  std::string tried;
  auto usable = [&tried](const std::filesystem::path& p) {
    tried += "\n  " + p.string();
    std::error_code ec;
    return std::filesystem::is_directory(p / "mrpt", ec);
  };
  if (const char* env = std::getenv("ROVE_DATA_DIR"); env != nullptr && *env != '\0') {
    if (usable(env)) return env;
  }
  if (auto exe = executable_dir(); !exe.empty()) {
    if (auto installed = exe.parent_path() / "share" / "rove" / "data"; usable(installed)) {
      return installed;
    }
  }
  if (std::filesystem::path source(ROVE_SOURCE_DATA_DIR); usable(source)) return source;
  throw IoError("rove data folder", "not found; set ROVE_DATA_DIR. Tried:" + tried);
}

}  // namespace rove::cli
