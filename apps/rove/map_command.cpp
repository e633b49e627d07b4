#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>

#include "commands.h"
#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/maps/grid_binary.h"
#include "rove/maps/grid_clearance.h"
#include "rove/maps/grid_entropy.h"
#include "rove/maps/grid_image.h"
#include "rove/maps/metric_map_builder.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/mrpt_gridmap.h"
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

// One line on a grid's entropy and information (grid_entropy.h).
std::string entropy_line(const OccupancyGrid& grid) {
  const GridEntropy e = grid_entropy(grid);
  return fmt::format("    entropy {:.1f} nats, information {:.1f} ({} mapped cells, {:.2f} m2, mean {:.4f})\n",
                     e.entropy, e.information, e.mapped_cells, e.mapped_area, e.mean_information);
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
  auto files = mm.save((std::filesystem::path(a.out_dir) / "map").string());
  // Occupancy grids also as a ROS map_server map (map_saver's trinary PNG + yaml).
  for (std::size_t i = 0; i < mm.size(); ++i) {
    const auto& e = mm.entries()[i];
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
      const RosMapFiles ros = save_ros_map(
          (std::filesystem::path(a.out_dir) / fmt::format("map_{:02}_{}", i, e.map->kind())).string(),
          g->grid());
      files.push_back(ros.image);
      files.push_back(ros.yaml);
    }
  }

  if (a.json) {
    std::string maps;
    for (std::size_t i = 0; i < mm.size(); ++i) {
      const auto& e = mm.entries()[i];
      const auto st = e.map->statistics();
      std::string entropy;
      if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
        const GridEntropy h = grid_entropy(g->grid());
        entropy = fmt::format(", \"entropy\": {:.6f}, \"information\": {:.6f}, \"mapped_cells\": {}, "
                              "\"mapped_area_m2\": {:.6f}",
                              h.entropy, h.information, h.mapped_cells, h.mapped_area);
      }
      maps += fmt::format(
          "{}    {{\"index\": {}, \"kind\": \"{}\", \"section\": \"{}\", \"{}\": {}, "
          "\"total_cells\": {}, \"observations_inserted\": {}, \"insertion_enabled\": {}{}}}",
          i ? ",\n" : "", i, e.map->kind(), json_escape(e.section_prefix), st.unit, st.elements,
          st.total_cells, e.observations_inserted, e.params.enable_insertion, entropy);
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
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
      fmt::print("{}", entropy_line(g->grid()));
    }
  }
  for (const auto& k : report.ignored_keys) {
    fmt::print("  without effect: [{}] {}: {}\n", k.section, k.key, k.reason);
  }
  for (const auto& f : files) fmt::print("  wrote {}\n", f);
  return 0;
}

struct MapConvertArgs {
  std::string input;
  std::string output;
  bool probability = false;
  bool pgm = false;
};

bool ends_with_ci(std::string s, std::string_view suffix) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s.ends_with(suffix);
}

// Reads a grid from a ROS map.yaml, an MRPT .gridmap or a .rovegrid; `from`
// names the kind. `arg` names the command-line argument in errors.
OccupancyGrid load_any_grid(const std::string& path, const std::string& arg, std::string& from) {
  if (ends_with_ci(path, ".yaml") || ends_with_ci(path, ".yml")) {
    RosMap m = load_ros_map(path);
    for (const auto& k : m.yaml.unknown_keys) {
      fmt::print("  without effect: {} key '{}'\n", path, k);
    }
    from = "ROS map";
    return std::move(m.grid);
  }
  if (ends_with_ci(path, ".gridmap") || ends_with_ci(path, ".gridmap.gz")) {
    from = "MRPT gridmap";
    return load_mrpt_gridmap(path).grid;
  }
  if (ends_with_ci(path, ".rovegrid") || ends_with_ci(path, ".rovegrid.gz")) {
    from = "rove grid";
    return load_grid(path);
  }
  throw CLI::ValidationError(arg, fmt::format("{}: unknown input kind (expected .yaml, "
                                              ".gridmap[.gz] or .rovegrid[.gz])", path));
}

int run_map_convert(const MapConvertArgs& a) {
  std::string from;
  const OccupancyGrid grid = load_any_grid(a.input, "IN", from);
  std::vector<std::string> written;
  if (ends_with_ci(a.output, ".yaml")) {
    GridImageOptions o;
    o.mode = a.probability ? RosMapMode::kScale : RosMapMode::kTrinary;
    o.format = a.pgm ? ImageFormat::kPgm : ImageFormat::kPng;
    const auto f = save_ros_map(a.output.substr(0, a.output.size() - 5), grid, o);
    written = {f.image, f.yaml};
  } else if (ends_with_ci(a.output, ".rovegrid") || ends_with_ci(a.output, ".rovegrid.gz")) {
    save_grid(a.output, grid,
              ends_with_ci(a.output, ".gz") ? FileCompression::kGzip : FileCompression::kNone);
    written = {a.output};
  } else {
    throw CLI::ValidationError("OUT", fmt::format("{}: unknown output kind (expected .yaml or "
                                                  ".rovegrid[.gz])", a.output));
  }
  fmt::print("{} {}: {} x {} cells of {} m, x [{}, {}] y [{}, {}] m\n", from, a.input,
             grid.size_x(), grid.size_y(), grid.resolution(), grid.x_min(), grid.x_max(),
             grid.y_min(), grid.y_max());
  fmt::print("{}", entropy_line(grid));
  for (const auto& f : written) fmt::print("  wrote {}\n", f);
  return 0;
}

struct MapVoronoiArgs {
  std::string input;
  std::string output;
  VoronoiOptions options;
};

// The grid as map_saver's gray levels with the diagram drawn in black on
// top: occupied 0, diagram 0 too but only on free cells, so the image
// reads as the map with its skeleton.
int run_map_voronoi(const MapVoronoiArgs& a) {
  if (!ends_with_ci(a.output, ".png") && !ends_with_ci(a.output, ".pgm")) {
    throw CLI::ValidationError("--out", fmt::format("{}: expected a .png or .pgm image", a.output));
  }
  std::string from;
  const OccupancyGrid grid = load_any_grid(a.input, "IN", from);
  const VoronoiDiagram vd = voronoi_diagram(grid, a.options);
  GrayImage img = grid_to_image(grid, GridImageOptions{});
  // Image row 0 is the top of the map (largest y).
  float lo = std::numeric_limits<float>::infinity(), hi = 0;
  for (std::uint32_t cy = 0; cy < vd.size_y; ++cy) {
    for (std::uint32_t cx = 0; cx < vd.size_x; ++cx) {
      const float c = vd.clearance[cx + static_cast<std::size_t>(cy) * vd.size_x];
      if (c <= 0) continue;
      lo = std::min(lo, c);
      hi = std::max(hi, c);
      img.pixels[cx + static_cast<std::size_t>(vd.size_y - 1 - cy) * img.width] = 0;
    }
  }
  write_gray_image(a.output, img, ends_with_ci(a.output, ".pgm") ? ImageFormat::kPgm : ImageFormat::kPng);
  fmt::print("{} {}: {} x {} cells of {} m\n", from, a.input, grid.size_x(), grid.size_y(),
             grid.resolution());
  if (vd.cells > 0) {
    fmt::print("  voronoi diagram: {} cells ({:.2f} m), clearance {:.3f} to {:.3f} m\n", vd.cells,
               static_cast<double>(vd.cells) * grid.resolution(), lo, hi);
  } else {
    fmt::print("  voronoi diagram: no cell\n");
  }
  fmt::print("  wrote {}\n", a.output);
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
  build->add_option("INPUT", args->input,
                    "MRPT simplemap, or a rawlog: MRPT or rove rawlog (plain or gzip), CARMEN log "
                    "(plain or bzip2)")
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

  auto cargs = std::make_shared<MapConvertArgs>();
  auto* convert = map->add_subcommand(
      "convert",
      "Convert an occupancy grid between a ROS map (map.yaml + PNG/PGM), an MRPT .gridmap "
      "(read only) and rove's binary .rovegrid");
  convert->add_option("IN", cargs->input, "map.yaml, .gridmap[.gz] or .rovegrid[.gz]")
      ->required()
      ->check(CLI::ExistingFile);
  convert->add_option("OUT", cargs->output,
                      "NAME.yaml (writes NAME.png + NAME.yaml) or .rovegrid[.gz]")
      ->required();
  convert->add_flag("--probability", cargs->probability,
                    "image of 255·p(free) instead of map_saver's 0/205/254");
  convert->add_flag("--pgm", cargs->pgm, "write the image as PGM (P5) instead of PNG");
  convert->callback([cargs] {
    const int rc = run_map_convert(*cargs);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });

  auto vargs = std::make_shared<MapVoronoiArgs>();
  auto* voronoi = map->add_subcommand(
      "voronoi",
      "Compute the Voronoi diagram of a grid's free space (with clearances) and draw it over "
      "the map as an image");
  voronoi->add_option("IN", vargs->input, "map.yaml, .gridmap[.gz] or .rovegrid[.gz]")
      ->required()
      ->check(CLI::ExistingFile);
  voronoi->add_option("-o,--out", vargs->output, "image to write (.png or .pgm)")->required();
  voronoi->add_option("--robot-size", vargs->options.min_clearance,
                      "leave out cells with at most this clearance, meters (default 0)")
      ->check(CLI::NonNegativeNumber);
  voronoi->add_option("--occupied-below", vargs->options.occupied_threshold,
                      "p(free) below which a cell is an obstacle (default 0.5)")
      ->check(CLI::Range(0.0, 1.0));
  voronoi->add_option("--separation", vargs->options.min_separation,
                      "the two obstacles must be more than this × the clearance apart "
                      "(default 1.75)")
      ->check(CLI::PositiveNumber);
  voronoi->callback([vargs] {
    const int rc = run_map_voronoi(*vargs);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace rove::cli
