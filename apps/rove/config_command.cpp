#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/json.h"
#include "rove/slam/icp_slam.h"
#include "rove/slam/metric_map_builder.h"

namespace rove::cli {

namespace {

/// The applications whose configuration `config check --for` validates.
enum class ConfigTarget { None, IcpSlam, MapBuild };

struct ConfigCheckOptions {
  std::vector<std::string> files;
  ConfigTarget target = ConfigTarget::None;
  std::string section;
  bool lenient = false;
  bool list = false;
  bool json = false;
};

/// What checking one file found.
struct FileCheck {
  std::string file;
  bool ok = false;
  std::string error;  ///< the error that failed the check (empty when ok)
  std::size_t sections = 0, keys = 0;
  std::string validated;  ///< what the values were validated for ("" = not validated)
  std::vector<std::string> notes;  ///< keys without effect
  std::vector<Issue> issues;       ///< warnings: duplicates, skipped lines
};

void warn_about_duplicates(const IniFile& ini, FileCheck& c) {
  for (const auto& d : ini.duplicates()) {
    if (d.is_section) {
      c.issues.push_back(
          {"duplicate-section",
           fmt::format("{}:{}: section [{}] appears again (first at line {}); its keys are "
                       "merged, a repeated key keeps its last value",
                       printable(ini.source()), d.line, printable(d.section), d.first_line)});
    } else {
      c.issues.push_back(
          {"duplicate-key",
           fmt::format("{}:{}: [{}] {} repeats line {}; the last value wins", printable(ini.source()),
                       d.line, printable(d.section), printable(d.key), d.first_line)});
    }
  }
  for (const auto& s : ini.skipped_lines()) {
    c.issues.push_back({"skipped-line", fmt::format("{}:{}: skipped '{}' ({})", printable(ini.source()),
                                                    s.line, printable(s.text), s.reason)});
  }
}

void add_notes(const std::vector<IgnoredConfigKey>& ignored, FileCheck& c) {
  for (const auto& k : ignored) {
    c.notes.push_back(fmt::format("[{}] {}: {}", printable(k.section), printable(k.key), k.reason));
  }
}

// Loads and validates one file the way the command named by `target` does.
FileCheck check_file(const std::string& file, const ConfigCheckOptions& o) {
  FileCheck c;
  c.file = file;
  try {
    IniOptions ini_options;
    // As the commands read them: icp-slam strictly, map build as MRPT
    // (lines it would skip are skipped, and listed here as warnings).
    ini_options.strict = !o.lenient && o.target != ConfigTarget::MapBuild;
    const IniFile ini = IniFile::load(file, ini_options);
    c.sections = ini.sections().size();
    for (const auto& s : ini.sections()) c.keys += ini.keys(s).size();
    warn_about_duplicates(ini, c);
    if (o.list) {
      for (const auto& s : ini.sections()) {
        fmt::print("  [{}]\n", printable(s));
        for (const auto& k : ini.keys(s)) {
          fmt::print("    {} = {}\n", printable(k), printable(ini.raw(s, k)));
        }
      }
    }
    if (o.target == ConfigTarget::IcpSlam) {
      IcpSlamConfig cfg = load_icp_slam_config(ini);
      add_notes(cfg.ignored_keys, c);
      // The command's next step: the algorithm checks its options.
      const IcpSlam slam(cfg.options, std::move(cfg.map));
      c.validated = "icp-slam";
    } else if (o.target == ConfigTarget::MapBuild) {
      const MapBuildConfig cfg = load_map_build_config(ini, o.section);
      add_notes(cfg.ignored_keys, c);
      c.validated = fmt::format("map-build [{}]: {} map{}", printable(cfg.section), cfg.maps.size(),
                                cfg.maps.size() == 1 ? "" : "s");
    }
    c.ok = true;
  } catch (const ParseError& e) {
    c.error = e.message();
    if (!o.lenient && o.target != ConfigTarget::MapBuild) {
      c.error += " (--lenient skips such lines as MRPT does, and lists them)";
    }
  } catch (const Error& e) {
    c.error = e.message();
  }
  return c;
}

void print_json(const std::vector<FileCheck>& checks, const std::vector<Issue>& issues) {
  JsonWriter j;
  j.begin_object().key("files").begin_array();
  for (const auto& c : checks) {
    j.begin_object().key("file").value(c.file).key("ok").value(c.ok);
    if (!c.ok) j.key("error").value(c.error);
    j.key("sections").value(c.sections).key("keys").value(c.keys);
    j.key("validated_for");
    if (c.validated.empty()) {
      j.null();
    } else {
      j.value(c.validated);
    }
    j.key("without_effect").value(c.notes);
    write_issues(j, c.issues);
    j.end_object();
  }
  j.end_array();
  write_issues(j, issues);
  j.end_object();
  fmt::print("{}\n", j.str());
}

void run_config_check(const ConfigCheckOptions& o) {
  std::vector<FileCheck> checks;
  std::vector<Issue> issues;
  int failed = 0;
  for (const auto& file : o.files) {
    FileCheck c = check_file(file, o);
    issues.insert(issues.end(), c.issues.begin(), c.issues.end());
    if (!c.ok) ++failed;
    if (!o.json) {
      if (!c.ok) {
        fmt::print(stderr, "rove: error: {}\n", printable(c.error));
      } else if (c.validated.empty()) {
        fmt::print("{}: ok, {} sections, {} keys (syntax only: values not validated; add --for "
                   "icp-slam or --for map-build)\n",
                   printable(file), c.sections, c.keys);
      } else {
        fmt::print("{}: ok, {} sections, {} keys, valid for {}\n", printable(file), c.sections,
                   c.keys, c.validated);
      }
      for (const auto& n : c.notes) fmt::print("  without effect: {}\n", n);
    }
    checks.push_back(std::move(c));
  }
  if (o.json) {
    print_json(checks, issues);
    print_issues(issues);
  } else {
    print_issues(issues);
  }
  if (failed > 0) throw IssuesExit{kExitError};
  if (!issues.empty()) throw IssuesExit{kExitIssues};
}

}  // namespace

void add_config_command(CLI::App& app) {
  auto* config = app.add_subcommand("config", "Work with MRPT-style INI configuration files");
  config->require_subcommand(1);
  auto options = std::make_shared<ConfigCheckOptions>();
  auto* check = config->add_subcommand(
      "check",
      "Load INI files as rove reads them; with --for, validate every value as that command "
      "does. Warns on repeated keys and sections. Exit status: 0 ok, 1 a file failed, 3 "
      "warnings only");
  check->add_option("files", options->files, "INI files")->required();
  auto target = std::make_shared<std::string>();
  check
      ->add_option("--for", *target,
                   "validate the values as this command does (default: none, syntax and "
                   "duplicates only)")
      ->check(CLI::IsMember({"icp-slam", "map-build"}));
  check->add_option("--section", options->section,
                    "with --for map-build: the section with the `<kind>_count` keys (default: "
                    "the first such, as `map build`)");
  check->add_flag("--lenient", options->lenient,
                  "skip lines MRPT would silently skip (and list them) instead of failing "
                  "(default: strict, except for --for map-build, which reads as MRPT)");
  check->add_flag("--list", options->list, "print every section with its keys and values");
  check->add_flag("--json", options->json, "print the result as JSON");
  check->callback([options, target] {
    options->target = *target == "icp-slam"    ? ConfigTarget::IcpSlam
                      : *target == "map-build" ? ConfigTarget::MapBuild
                                               : ConfigTarget::None;
    run_config_check(*options);
  });
}

}  // namespace rove::cli
