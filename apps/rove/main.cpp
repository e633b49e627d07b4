#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <exception>

#include "commands.h"
#include "rove/core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"rove: localize, map and navigate mobile robots from real sensor data"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rove ") + ROVE_VERSION);
  auto* version = app.add_subcommand("version", "Print rove's version");
  version->callback([] { fmt::print("rove {}\n", ROVE_VERSION); });
  rove::cli::add_demo_command(app);
  rove::cli::add_config_command(app);
  rove::cli::add_rawlog_command(app);
  rove::cli::add_icp_slam_command(app);
  rove::cli::add_graph_slam_command(app);
  rove::cli::add_map_command(app);
  rove::cli::add_align_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const rove::Error& e) {
    fmt::print(stderr, "rove: error: {}\n", e.message());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rove: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
