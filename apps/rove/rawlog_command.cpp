#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "commands.h"
#include "rove/core/progress.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/observation.h"
#include "rove/obs/rawlog_reader.h"
#include "rove/obs/sensory_frame.h"
#include "rove/serialization/input_file.h"

namespace rove::cli {

namespace {

struct RawlogInfoOptions {
  std::string file;
  bool json = false;
  bool progress = true;
};

// What `rove rawlog info` counts while streaming a rawlog once.
struct RawlogSummary {
  std::uint64_t entries = 0;
  std::uint64_t action_collections = 0;
  std::uint64_t actions = 0;
  std::uint64_t sensory_frames = 0;
  std::uint64_t observations_in_frames = 0;
  std::uint64_t bare_observations = 0;
  std::uint64_t bytes = 0;  // decompressed
  // (class name, sensor label) -> count, for observations; class -> count for actions.
  std::map<std::pair<std::string, std::string>, std::uint64_t> observation_kinds;
  std::map<std::string, std::uint64_t> action_kinds;
  // Earliest and latest observation time (actions are not counted, as in
  // rawlog-edit --info).
  std::optional<Timestamp> first, last;

  void add_time(Timestamp t) {
    if (!t.valid()) return;
    if (!first || t < *first) first = t;
    if (!last || *last < t) last = t;
  }
  void add_observation(const Observation& o) {
    ++observation_kinds[{std::string(o.class_name()), o.sensor_label}];
    add_time(o.timestamp);
  }
};

RawlogSummary summarize(const std::string& path, bool show_progress) {
  RawlogSummary s;
  RawlogReader reader(path);
  // Progress against the file size works for plain files only: a gzip
  // stream reports decompressed offsets, so there only counts are shown.
  std::optional<std::uint64_t> total;
  if (!is_gzip_file(path)) total = std::filesystem::file_size(path);
  std::optional<Progress> progress;
  if (show_progress) progress.emplace(total, "reading " + path, std::cerr);
  while (auto entry = reader.next()) {
    ++s.entries;
    std::visit(
        [&s](const auto& e) {
          using T = std::remove_const_t<typename std::decay_t<decltype(e)>::element_type>;
          if constexpr (std::is_same_v<T, ActionCollection>) {
            ++s.action_collections;
            for (const auto& a : e->actions) {
              ++s.actions;
              ++s.action_kinds[std::string(a->class_name())];
            }
          } else if constexpr (std::is_same_v<T, SensoryFrame>) {
            ++s.sensory_frames;
            for (const auto& o : e->observations) {
              ++s.observations_in_frames;
              s.add_observation(*o);
            }
          } else {
            ++s.bare_observations;
            s.add_observation(*e);
          }
        },
        *entry);
    if (progress) {
      if (total) {
        progress->set(std::min<std::uint64_t>(reader.offset(), *total));
      } else {
        progress->advance();
      }
    }
  }
  if (progress) progress->finish();
  s.bytes = reader.offset();
  return s;
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

void print_text(const std::string& path, const RawlogSummary& s) {
  fmt::print("file: {}\n", path);
  fmt::print("entries: {} ({} action collections, {} sensory frames, {} bare observations)\n",
             s.entries, s.action_collections, s.sensory_frames, s.bare_observations);
  fmt::print("layout: {}\n", s.bare_observations == 0 ? "#1 (actions + sensory frames)"
                             : s.sensory_frames == 0 && s.action_collections == 0
                                 ? "#2 (observations)"
                                 : "mixed");
  fmt::print("uncompressed bytes: {}\n", s.bytes);
  if (s.first && s.last) {
    fmt::print("time span: {:.6f} .. {:.6f} s ({:.3f} s)\n", s.first->to_seconds(),
               s.last->to_seconds(), s.last->to_seconds() - s.first->to_seconds());
  } else {
    fmt::print("time span: no timestamps\n");
  }
  fmt::print("observations: {} ({} in sensory frames)\n",
             s.observations_in_frames + s.bare_observations, s.observations_in_frames);
  for (const auto& [kind, n] : s.observation_kinds) {
    fmt::print("  {:>8}  {} [{}]\n", n, kind.first,
               kind.second.empty() ? "no label" : kind.second);
  }
  fmt::print("actions: {}\n", s.actions);
  for (const auto& [kind, n] : s.action_kinds) fmt::print("  {:>8}  {}\n", n, kind);
}

void print_json(const std::string& path, const RawlogSummary& s) {
  fmt::print("{{\"file\": {}, \"entries\": {}, \"action_collections\": {}, "
             "\"sensory_frames\": {}, \"bare_observations\": {}, \"actions\": {}, "
             "\"observations\": {}, \"uncompressed_bytes\": {}",
             json_string(path), s.entries, s.action_collections, s.sensory_frames,
             s.bare_observations, s.actions, s.observations_in_frames + s.bare_observations,
             s.bytes);
  if (s.first && s.last) {
    fmt::print(", \"time_first\": {:.9f}, \"time_last\": {:.9f}", s.first->to_seconds(),
               s.last->to_seconds());
  }
  fmt::print(", \"observation_kinds\": [");
  bool first = true;
  for (const auto& [kind, n] : s.observation_kinds) {
    fmt::print("{}{{\"class\": {}, \"label\": {}, \"count\": {}}}", first ? "" : ", ",
               json_string(kind.first), json_string(kind.second), n);
    first = false;
  }
  fmt::print("], \"action_kinds\": [");
  first = true;
  for (const auto& [kind, n] : s.action_kinds) {
    fmt::print("{}{{\"class\": {}, \"count\": {}}}", first ? "" : ", ", json_string(kind), n);
    first = false;
  }
  fmt::print("]}}\n");
}

}  // namespace

void add_rawlog_command(CLI::App& app) {
  auto* rawlog = app.add_subcommand("rawlog", "Inspect robot datasets (MRPT rawlogs)");
  rawlog->require_subcommand(1);
  auto options = std::make_shared<RawlogInfoOptions>();
  auto* info = rawlog->add_subcommand(
      "info", "Stream a rawlog once and count its entries per type and sensor label");
  info->add_option("file", options->file, "MRPT rawlog (plain or gzip)")
      ->required()
      ->check(CLI::ExistingFile);
  info->add_flag("--json", options->json, "Print one JSON object instead of text");
  info->add_flag("!--no-progress", options->progress, "Do not report progress on stderr");
  info->callback([options] {
    const RawlogSummary s = summarize(options->file, options->progress);
    if (options->json) {
      print_json(options->file, s);
    } else {
      print_text(options->file, s);
    }
  });
}

}  // namespace rove::cli
