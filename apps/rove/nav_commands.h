#pragma once
/// \file
/// The subcommands of `rove nav` defined outside nav_command.cpp.

#include <CLI/CLI.hpp>

namespace rove::cli {

/// `rove nav run MAP --start x,y,yaw --goal x,y -o DIR`: drive in the simulator.
void add_nav_run_command(CLI::App& nav);

}  // namespace rove::cli
