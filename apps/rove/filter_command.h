#pragma once
/// \file
/// The frame the filter commands (pf-localization, rbpf-slam) share around
/// their run: the output folder's checks, progress on stderr with Ctrl-C
/// reported, and the summary written, printed and turned into the exit
/// status.

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/core/parallel.h"
#include "rove/core/progress.h"

namespace rove::cli {

/// The log to read: `given` (the command line's), else the config's
/// `rawlog_file` resolved (config.resolve). ConfigError naming
/// `config_path`, [`section`] rawlog_file when there is neither.
template <typename Config>
std::string rawlog_to_read(const std::string& given, const std::string& config_path,
                           const Config& config, const char* section) {
  if (!given.empty()) return given;
  if (config.rawlog_file.empty()) {
    throw ConfigError(config_path, section, "rawlog_file",
                      "no rawlog given on the command line and none in the config file");
  }
  return config.resolve(config.rawlog_file, "rawlog_file");
}

/// Adds --seed and --threads (whose results do not depend on it) to `cmd`.
inline void add_seed_and_threads(CLI::App* cmd, std::uint64_t& seed, int& threads) {
  cmd->add_option("--seed", seed, "seed of the random numbers (same seed, same result)")
      ->capture_default_str();
  cmd->add_option("--threads", threads,
                  fmt::format("threads, 1 to {}, 0 for all hardware threads (results do not "
                              "depend on it)",
                              kMaxThreads))
      ->capture_default_str();
}

/// The output folder -o: IoError if it exists and is not a folder.
inline std::filesystem::path output_folder(const std::string& out_dir) {
  const std::filesystem::path dir(out_dir);
  if (std::filesystem::exists(dir) && !std::filesystem::is_directory(dir)) {
    throw IoError(out_dir, "the output folder (-o) exists and is not a folder");
  }
  return dir;
}

/// Creates the output folder (and its parents); IoError if it cannot.
inline void create_output_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw IoError(dir.string(), "cannot create the output folder: " + ec.message());
}

/// Runs `body(on_step)`, where on_step() is to be called after each step:
/// a progress line on stderr when `show`; on Ctrl-C, says how many steps
/// were done and that nothing was written to `out_dir`, and rethrows.
template <typename Body>
auto run_with_progress(bool show, const std::string& label, const std::string& out_dir, Body&& body) {
  std::optional<Progress> progress;
  if (show) progress.emplace(std::nullopt, label, std::cerr);
  std::uint64_t steps_done = 0;
  const std::function<void()> on_step = [&] {
    ++steps_done;
    if (progress) progress->advance();
  };
  try {
    auto result = body(on_step);
    if (progress) progress->finish();
    return result;
  } catch (const Interrupted&) {
    if (progress) progress->finish();
    fmt::print(stderr, "rove: interrupted after {} steps; nothing written to {}\n", steps_done,
               printable(out_dir));
    throw;
  }
}

/// The issues of a run result (anything with `code` and `message`).
template <typename RunIssue>
std::vector<Issue> to_issues(const std::vector<RunIssue>& run_issues) {
  std::vector<Issue> out;
  for (const auto& i : run_issues) out.push_back({i.code, i.message});
  return out;
}

/// Adds `dir`/summary.json to `files`, writes summary() there, prints it
/// (with `json`) or calls print_text(), and ends the command with the
/// issues (rove::cli::finish).
inline void publish_summary(const std::filesystem::path& dir, std::vector<std::string>& files,
                            bool json, const std::function<std::string()>& summary,
                            const std::function<void()>& print_text,
                            const std::vector<Issue>& issues) {
  const std::filesystem::path path = dir / "summary.json";
  files.push_back(path.string());
  const std::string text = summary();
  write_text_file_atomically(path, text);
  if (json) {
    fmt::print("{}", text);
  } else {
    print_text();
  }
  finish(issues);
}

}  // namespace rove::cli
