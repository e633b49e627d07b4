#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <string>

#include "commands.h"
#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/maps/metric_map_builder.h"
#include "rove/maps/multi_metric_map.h"

namespace rove::cli {

namespace {

struct MapBuildArgs {
  std::string config;
  std::string input;
  std::string out_dir;
  std::string section;
  bool json = false;
};

std::string json_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          o += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        } else {
          o += c;
        }
    }
  }
  return o;
}

/// The multi-metric map section of an MRPT application file: the one given,
/// else the first section holding a `<map kind>_count` key.
std::string find_map_section(const IniFile& ini) {
  for (const auto& sec : ini.sections()) {
    for (const auto& key : ini.keys(sec)) {
      if (key.size() > 6 && key.ends_with("_count")) {
        const std::string stem = key.substr(0, key.size() - 6);
        for (const auto& k : supported_metric_map_kinds()) {
          if (k.size() == stem.size() &&
              std::equal(k.begin(), k.end(), stem.begin(), [](char a, char b) {
                return std::tolower(static_cast<unsigned char>(a)) ==
                       std::tolower(static_cast<unsigned char>(b));
              })) {
            return sec;
          }
        }
      }
    }
  }
  throw ConfigError(ini.source(), "", "", "no section declares a metric map (no `<kind>_count` key); "
                    "name it with --section");
}

int run_map_build(const MapBuildArgs& a) {
  const IniFile ini = IniFile::load(a.config, IniOptions{.strict = false});
  const std::string section = a.section.empty() ? find_map_section(ini) : a.section;
  if (!ini.has_section(section)) {
    throw ConfigError(a.config, section, "", "section not found");
  }
  MultiMetricMapLoadReport report;
  MultiMetricMap mm = MultiMetricMap::from_config(ini, section, &report);
  if (mm.size() == 0) {
    throw ConfigError(a.config, section, "", "declares no map (every `_count` is 0)");
  }
  const MapBuildResult r = build_map(a.input, mm);
  std::filesystem::create_directories(a.out_dir);
  const auto files = mm.save((std::filesystem::path(a.out_dir) / "map").string());

  if (a.json) {
    std::string maps;
    for (std::size_t i = 0; i < mm.size(); ++i) {
      const auto& e = mm.entries()[i];
      const auto st = e.map->statistics();
      maps += fmt::format(
          "{}    {{\"index\": {}, \"kind\": \"{}\", \"section\": \"{}\", \"{}\": {}, "
          "\"total_cells\": {}, \"observations_inserted\": {}, \"insertion_enabled\": {}}}",
          i ? ",\n" : "", i, e.map->kind(), json_escape(e.section_prefix), st.unit, st.elements,
          st.total_cells, e.observations_inserted, e.params.enable_insertion);
    }
    std::string ignored;
    for (std::size_t i = 0; i < report.ignored_keys.size(); ++i) {
      const auto& k = report.ignored_keys[i];
      ignored += fmt::format("{}    {{\"section\": \"{}\", \"key\": \"{}\", \"reason\": \"{}\"}}",
                             i ? ",\n" : "", json_escape(k.section), json_escape(k.key),
                             json_escape(k.reason));
    }
    std::string out_files;
    for (std::size_t i = 0; i < files.size(); ++i) {
      out_files += fmt::format("{}\"{}\"", i ? ", " : "", json_escape(files[i]));
    }
    fmt::print(
        "{{\n  \"config\": \"{}\",\n  \"section\": \"{}\",\n  \"input\": \"{}\",\n"
        "  \"input_kind\": \"{}\",\n  \"keyframes\": {},\n  \"odometry_steps\": {},\n"
        "  \"observations\": {},\n  \"observations_used\": {},\n  \"seconds\": {:.6f},\n"
        "  \"maps\": [\n{}\n  ],\n  \"ignored_keys\": [\n{}\n  ],\n  \"files\": [{}]\n}}\n",
        json_escape(a.config), json_escape(section), json_escape(a.input),
        r.input == MapInputKind::kSimpleMap ? "simplemap" : "rawlog", r.keyframes,
        r.odometry_steps, r.observations, r.observations_used, r.seconds, maps, ignored, out_files);
    return 0;
  }
  fmt::print("config {} [{}]: {} map{}\n", a.config, section, mm.size(), mm.size() == 1 ? "" : "s");
  fmt::print("input {} ({}): {} keyframes, {} odometry steps, {} observations ({} used), {:.3f} s\n",
             a.input, r.input == MapInputKind::kSimpleMap ? "simplemap" : "rawlog", r.keyframes,
             r.odometry_steps, r.observations, r.observations_used, r.seconds);
  for (std::size_t i = 0; i < mm.size(); ++i) {
    const auto& e = mm.entries()[i];
    const auto st = e.map->statistics();
    std::string extent;
    if (!st.bounds.empty()) {
      extent = fmt::format(", x [{:.2f}, {:.2f}] y [{:.2f}, {:.2f}] m", st.bounds.min.x(),
                           st.bounds.max.x(), st.bounds.min.y(), st.bounds.max.y());
    }
    fmt::print("  map {} {}: {} {}{}{}, {} observations inserted{}\n", i, e.map->kind(),
               st.elements, st.unit,
               st.total_cells ? fmt::format(" of {} cells", st.total_cells) : std::string(),
               extent, e.observations_inserted, e.params.enable_insertion ? "" : " (insertion disabled)");
  }
  for (const auto& k : report.ignored_keys) {
    fmt::print("  without effect: [{}] {}: {}\n", k.section, k.key, k.reason);
  }
  for (const auto& f : files) fmt::print("  wrote {}\n", f);
  return 0;
}

}  // namespace

void add_map_command(CLI::App& app) {
  auto* map = app.add_subcommand("map", "Build metric maps from datasets");
  map->require_subcommand(1);
  auto args = std::make_shared<MapBuildArgs>();
  auto* build = map->add_subcommand(
      "build",
      "Build the maps an MRPT config declares from a rawlog (poses from odometry) or a "
      "simplemap (its poses), as MRPT's observations2map");
  build->add_option("CONFIG", args->config, "MRPT-style config file declaring a multi-metric map")
      ->required()
      ->check(CLI::ExistingFile);
  build->add_option("INPUT", args->input, "MRPT rawlog or simplemap (plain or gzip)")
      ->required()
      ->check(CLI::ExistingFile);
  build->add_option("-o,--out", args->out_dir, "output directory (created)")->required();
  build->add_option("--section", args->section,
                    "config section with the `<kind>_count` keys (default: the first such)");
  build->add_flag("--json", args->json, "print the summary as JSON");
  build->callback([args] {
    const int rc = run_map_build(*args);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace rove::cli
