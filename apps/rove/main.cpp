#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cctype>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#ifdef ROVE_HAVE_ROS
#include "rove/ros/bag_reader.h"
#endif

namespace {

// Prints a message whose text may come from a file or an argument: each line
// made printable (no raw control bytes or invalid UTF-8 reach the terminal).
void print_error(std::string_view prefix, std::string_view message) {
  std::size_t start = 0;
  bool first = true;
  while (start <= message.size()) {
    const std::size_t end = std::min(message.find('\n', start), message.size());
    const std::string line = rove::printable(message.substr(start, end - start));
    fmt::print(stderr, "{}{}\n", first ? prefix : std::string_view("  "), line);
    first = false;
    start = end + 1;
  }
}

// CLI11's range checks print their bounds with std::to_string, so an open
// bound (a "non-negative" or "positive" number) becomes a 309-digit number.
// Say what is expected instead.
std::string readable_usage_error(std::string message) {
  // "Value V not in range LOW to HIGH" where HIGH has 30 or more digits.
  const std::string head = "Value ", mid = " not in range ", to = " to ";
  const std::size_t v = message.find(head);
  const std::size_t r = message.find(mid, v == std::string::npos ? 0 : v);
  if (v == std::string::npos || r == std::string::npos) return message;
  const std::size_t low_at = r + mid.size();
  const std::size_t t = message.find(to, low_at);
  if (t == std::string::npos) return message;
  std::size_t end = t + to.size(), digits = 0;
  while (end < message.size() && (std::isdigit(static_cast<unsigned char>(message[end])) ||
                                  message[end] == '.')) {
    digits += message[end] != '.';
    ++end;
  }
  if (digits < 30) return message;
  const std::string value = message.substr(v + head.size(), r - v - head.size());
  const std::string low_text = message.substr(low_at, t - low_at);
  const double low = std::strtod(low_text.c_str(), nullptr);
  char* num_end = nullptr;
  const double x = std::strtod(value.c_str(), &num_end);
  const bool numeric = !value.empty() && num_end != nullptr && *num_end == '\0';
  std::string want;
  if (low > 0.0 || (low == 0.0 && numeric && x >= 0.0)) {
    want = "must be a number greater than 0";  // CLI11's "positive" bound prints as 0.000000
  } else if (low == 0.0) {
    want = "must be a number >= 0";
  } else {
    want = "must be a number >= " + low_text;
  }
  return message.substr(0, v) + "'" + value + "' " + want + message.substr(end);
}

// The deepest subcommand the command line reached ("rove rawlog cut").
std::string command_path(const CLI::App& app) {
  std::string path = "rove";
  const CLI::App* at = &app;
  while (true) {
    const auto subs = at->get_subcommands();
    if (subs.empty()) break;
    at = subs.front();
    path += " " + at->get_name();
  }
  return path;
}

// "rove frobnicate": name the unknown command and list the known ones,
// instead of CLI11's "A subcommand is required".
bool unknown_command(const CLI::App& app, int argc, char** argv) {
  if (argc < 2) return false;
  const std::string_view first = argv[1];
  if (first.empty() || first.front() == '-') return false;
  std::string known;
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == first) return false;
    known += (known.empty() ? "" : ", ") + sub->get_name();
  }
  fmt::print(stderr, "rove: unknown command '{}' (commands: {}); see rove --help\n",
             rove::printable(first), known);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rove: localize, map and navigate mobile robots from real sensor data"};
  app.name("rove");
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rove ") + ROVE_VERSION);
  auto* version = app.add_subcommand("version", "Print rove's version");
  version->callback([] { fmt::print("rove {}\n", ROVE_VERSION); });
#ifdef ROVE_HAVE_ROS
  rove::register_bag_reader();  // AnyRawlogReader, so every command, reads ROS bags
#endif
  rove::cli::add_demo_command(app);
  rove::cli::add_config_command(app);
  rove::cli::add_rawlog_command(app);
  rove::cli::add_icp_slam_command(app);
  rove::cli::add_lidar_slam_command(app);
#ifdef ROVE_HAVE_RGBD_SLAM
  rove::cli::add_rgbd_slam_command(app);
#endif
  rove::cli::add_pf_localization_command(app);
  rove::cli::add_kf_slam_command(app);
  rove::cli::add_rbpf_slam_command(app);
  rove::cli::add_graph_slam_command(app);
  rove::cli::add_map_command(app);
  rove::cli::add_align_command(app);
  rove::cli::add_eval_command(app);
  rove::cli::add_octomap_command(app);
  rove::cli::add_nav_command(app);
  rove::cli::add_view_command(app);
  rove::cli::add_batch_command(app);
  rove::install_interrupt_handler();
  if (argc < 2) {
    fmt::print(stderr, "{}", app.help());
    return rove::cli::kExitUsage;
  }
  if (unknown_command(app, argc, argv)) return rove::cli::kExitUsage;
  if (std::string_view(argv[1]) == "batch") return rove::cli::run_batch_command(argc - 2, argv + 2);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" that exit 0: let CLI11 print them.
    if (e.get_exit_code() == 0) return app.exit(e);
    const std::string where = command_path(app);
    print_error("rove: usage error: ", readable_usage_error(e.what()));
    fmt::print(stderr, "  see {} --help\n", where);
    return rove::cli::kExitUsage;
  } catch (const rove::cli::IssuesExit& e) {
    return e.code;
  } catch (const rove::Interrupted& e) {
    fmt::print(stderr, "rove: {}\n", e.message());
    return rove::cli::kExitInterrupted;
  } catch (const rove::Error& e) {
    print_error("rove: error: ", e.message());
    return rove::cli::kExitError;
  } catch (const std::exception& e) {
    print_error("rove: error: ", e.what());
    return rove::cli::kExitError;
  }
  return rove::cli::kExitOk;
}
