// `rove batch`: the command line of rove.batch (python/rove/batch.py), the
// Dask scale-out. The arguments go unchanged to `python3 -m rove.batch`, run
// with the interpreter the bindings were built for, the bindings' package on
// PYTHONPATH and this executable as the `rove` the runs call.

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "commands.h"
#include "report.h"

namespace rove::cli {

namespace {

constexpr const char* kBatchHelp =
    "Run a rove command over many inputs and a parameter grid on a Dask cluster and write a "
    "table of the runs (python3 -m rove.batch; rove batch --help, docs/batch.md)";

// The interpreter and package folder the build configured (python/CMakeLists.txt),
// or the ones found at run time.
#ifdef ROVE_PYTHON_EXECUTABLE
constexpr const char* kPython = ROVE_PYTHON_EXECUTABLE;
#else
constexpr const char* kPython = "python3";
#endif
#ifdef ROVE_PYTHON_PACKAGE_DIR
constexpr const char* kPackageDir = ROVE_PYTHON_PACKAGE_DIR;
#else
constexpr const char* kPackageDir = "";
#endif

}  // namespace

void add_batch_command(CLI::App& app) {
  // Registered for `rove --help` and the list of commands; main() hands the
  // arguments to run_batch_command() before CLI11 parses anything, so that
  // rove.batch's own options (and --help) reach it unchanged.
  app.add_subcommand("batch", kBatchHelp)->allow_extras();
}

int run_batch_command(int argc, char** argv) {
  std::error_code ec;
  if (*kPackageDir != '\0' && std::filesystem::is_directory(kPackageDir, ec)) {
    const char* old = std::getenv("PYTHONPATH");
    const std::string path = std::string(kPackageDir) + (old && *old ? ":" + std::string(old) : "");
    ::setenv("PYTHONPATH", path.c_str(), 1);
  }
  if (const char* cli = std::getenv("ROVE_CLI"); cli == nullptr || *cli == '\0') {
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) ::setenv("ROVE_CLI", self.c_str(), 1);
  }
  std::vector<char*> args;
  std::string python = kPython, dash_m = "-m", module = "rove.batch";
  args.push_back(python.data());
  args.push_back(dash_m.data());
  args.push_back(module.data());
  for (int i = 0; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  ::execvp(python.c_str(), args.data());
  fmt::print(stderr,
             "rove: error: rove batch runs '{} -m rove.batch' (the Python bindings with Debian's "
             "python3-distributed), which could not be started: {}\n",
             python, std::strerror(errno));
  return kExitError;
}

}  // namespace rove::cli
