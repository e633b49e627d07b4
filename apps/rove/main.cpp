#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <exception>

#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"

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
  rove::install_interrupt_handler();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const rove::cli::IssuesExit& e) {
    return e.code;
  } catch (const rove::Interrupted& e) {
    fmt::print(stderr, "rove: {}\n", e.message());
    return rove::cli::kExitInterrupted;
  } catch (const rove::Error& e) {
    fmt::print(stderr, "rove: error: {}\n", rove::printable(e.message()));
    return rove::cli::kExitError;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rove: error: {}\n", rove::printable(e.what()));
    return rove::cli::kExitError;
  }
  return rove::cli::kExitOk;
}
