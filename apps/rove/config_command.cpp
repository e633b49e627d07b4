#include <fmt/format.h>

#include <string>
#include <vector>

#include "commands.h"
#include "rove/core/error.h"
#include "rove/core/ini.h"

namespace rove::cli {

namespace {
struct ConfigCheckOptions {
  std::vector<std::string> files;
  bool lenient = false;
  bool list = false;
};
}  // namespace

void add_config_command(CLI::App& app) {
  auto* config = app.add_subcommand("config", "Work with MRPT-style INI configuration files");
  config->require_subcommand(1);
  auto options = std::make_shared<ConfigCheckOptions>();
  auto* check = config->add_subcommand(
      "check", "Load INI files as rove reads them and report sections, keys and errors");
  check->add_option("files", options->files, "INI files")->required()->check(CLI::ExistingFile);
  check->add_flag("--lenient", options->lenient,
                  "Skip lines MRPT would silently skip (and list them) instead of failing");
  check->add_flag("--list", options->list, "Print every section with its keys and values");
  check->callback([options] {
    int failed = 0;
    for (const auto& file : options->files) {
      try {
        IniOptions ini_options;
        ini_options.strict = !options->lenient;
        const IniFile ini = IniFile::load(file, ini_options);
        std::size_t keys = 0;
        for (const auto& s : ini.sections()) keys += ini.keys(s).size();
        fmt::print("{}: ok, {} sections, {} keys\n", file, ini.sections().size(), keys);
        for (const auto& skipped : ini.skipped_lines()) {
          fmt::print("  skipped line {}: {} ({})\n", skipped.line, skipped.text, skipped.reason);
        }
        if (options->list) {
          for (const auto& s : ini.sections()) {
            fmt::print("  [{}]\n", s);
            for (const auto& k : ini.keys(s)) fmt::print("    {} = {}\n", k, ini.raw(s, k));
          }
        }
      } catch (const ParseError& e) {
        fmt::print(stderr, "{}\n", e.message());
        if (!options->lenient) {
          fmt::print(stderr, "  (--lenient skips such lines as MRPT does, and lists them)\n");
        }
        ++failed;
      } catch (const Error& e) {
        fmt::print(stderr, "{}\n", e.message());
        ++failed;
      }
    }
    if (failed > 0) throw CLI::RuntimeError(1);
  });
}

}  // namespace rove::cli
