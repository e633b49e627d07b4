#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "commands.h"
#include "grid_input.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/json.h"
#include "rove/core/memory_budget.h"
#include "rove/io/grid_binary.h"
#include "rove/io/grid_image.h"
#include "rove/io/metric_map_files.h"
#include "rove/io/mrpt_gridmap.h"
#include "rove/maps/grid_clearance.h"
#include "rove/maps/grid_entropy.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_octree.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/slam/map_build_outputs.h"
#include "rove/slam/metric_map_builder.h"
#include "rove/slam/scan_consistency.h"
#include "rove/obs/selection_error.h"
#include "rove/io/mrpt_simplemap.h"

namespace rove::cli {

namespace {

namespace fs = std::filesystem;

// One line on a grid's entropy and information (grid_entropy.h).
std::string entropy_line(const OccupancyGrid& grid) {
  const GridEntropy e = grid_entropy(grid);
  return fmt::format("    entropy {:.1f} nats, information {:.1f} ({} mapped cells, {:.2f} m2, mean {:.4f})\n",
                     e.entropy, e.information, e.mapped_cells, e.mapped_area, e.mean_information);
}

void write_entropy(JsonWriter& j, const OccupancyGrid& grid) {
  const GridEntropy h = grid_entropy(grid);
  j.key("entropy").value(h.entropy).key("information").value(h.information);
  j.key("mapped_cells").value(h.mapped_cells).key("mapped_area_m2").value(h.mapped_area);
}

void write_grid_geometry(JsonWriter& j, const OccupancyGrid& grid) {
  j.key("size_x").value(grid.size_x()).key("size_y").value(grid.size_y());
  j.key("resolution").value(grid.resolution());
  j.key("x_min").value(grid.x_min()).key("x_max").value(grid.x_max());
  j.key("y_min").value(grid.y_min()).key("y_max").value(grid.y_max());
}

// ------------------------------------------------------------ map build --

struct MapBuildArgs {
  std::string config;
  std::string input;
  std::string out_dir;
  std::string section;
  bool json = false;
};

void run_map_build(const MapBuildArgs& a) {
  check_map_build_outputs(a.config, a.input, a.out_dir);
  const IniFile ini = IniFile::load(a.config, IniOptions{.strict = false});
  MapBuildConfig cfg = load_map_build_config(ini, a.section);
  MultiMetricMap& mm = cfg.maps;
  const MapBuildResult r = build_map(a.input, mm);
  const std::vector<std::string> files = save_map_build(a.out_dir, mm);
  std::vector<Issue> issues;
  for (const auto& i : map_build_issues(r, mm, a.input)) issues.push_back({i.code, i.message});
  const char* input_kind = r.input == MapInputKind::SimpleMap ? "simplemap" : "rawlog";

  if (a.json) {
    JsonWriter j;
    j.begin_object();
    j.key("config").value(a.config).key("section").value(cfg.section);
    j.key("input").value(a.input).key("input_kind").value(input_kind);
    j.key("keyframes").value(r.keyframes).key("odometry_steps").value(r.odometry_steps);
    j.key("observations").value(r.observations).key("observations_used").value(r.observations_used);
    j.key("seconds").value(r.seconds);
    j.key("maps").begin_array();
    for (std::size_t i = 0; i < mm.size(); ++i) {
      const auto& e = mm.entries()[i];
      const auto st = e.map->statistics();
      j.begin_object().key("index").value(i).key("kind").value(e.map->kind());
      j.key("section").value(e.section_prefix).key(st.unit).value(st.elements);
      j.key("total_cells").value(st.total_cells);
      j.key("observations_inserted").value(e.observations_inserted);
      j.key("insertion_enabled").value(e.params.enable_insertion);
      if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
        write_entropy(j, g->grid());
      }
      j.end_object();
    }
    j.end_array();
    j.key("ignored_keys").begin_array();
    for (const auto& k : cfg.ignored_keys) {
      j.begin_object().key("section").value(k.section).key("key").value(k.key);
      j.key("reason").value(k.reason).end_object();
    }
    j.end_array();
    j.key("files").value(files);
    write_issues(j, issues);
    j.end_object();
    fmt::print("{}\n", j.str());
    finish(issues);
    return;
  }
  fmt::print("config {} [{}]: {} map{}\n", printable(a.config), printable(cfg.section), mm.size(),
             mm.size() == 1 ? "" : "s");
  fmt::print("input {} ({}): {} keyframes, {} odometry steps, {} observations ({} used), {:.3f} s\n",
             printable(a.input), input_kind, r.keyframes, r.odometry_steps, r.observations,
             r.observations_used, r.seconds);
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
  for (const auto& k : cfg.ignored_keys) {
    fmt::print("  without effect: [{}] {}: {}\n", printable(k.section), printable(k.key), k.reason);
  }
  for (const auto& f : files) fmt::print("  wrote {}\n", printable(f));
  if (!issues.empty()) fmt::print("  {} issue{} (below)\n", issues.size(), issues.size() == 1 ? "" : "s");
  finish(issues);
}

// ---------------------------------------------------------- map convert --

struct MapConvertArgs {
  std::string input;
  std::string output;
  std::string mode = "trinary";
  bool probability = false;
  bool pgm = false;
  bool json = false;
};

void run_map_convert(const MapConvertArgs& a) {
  const bool to_yaml = ends_with_ci(a.output, ".yaml");
  const bool to_rovegrid = ends_with_ci(a.output, ".rovegrid") || ends_with_ci(a.output, ".rovegrid.gz");
  if (!to_yaml && !to_rovegrid) {
    throw CLI::ValidationError("OUT", fmt::format("{}: unknown output kind (expected .yaml or "
                                                  ".rovegrid[.gz])",
                                                  printable(a.output)));
  }
  const LoadedGrid in = load_any_grid(a.input, "IN");
  const OccupancyGrid& grid = in.grid;
  std::vector<std::string> written;
  if (to_yaml) {
    GridImageOptions o;
    o.mode = a.probability || a.mode == "scale" ? RosMapMode::Scale : RosMapMode::Trinary;
    o.format = a.pgm ? ImageFormat::Pgm : ImageFormat::Png;
    const std::string prefix = a.output.substr(0, a.output.size() - 5);
    const fs::path image = prefix + (a.pgm ? ".pgm" : ".png");
    check_outputs_distinct(in.files, {image, a.output});
    const auto f = save_ros_map(prefix, grid, o);
    written = {f.image, f.yaml};
  } else {
    check_outputs_distinct(in.files, {a.output});
    save_grid(a.output, grid,
              ends_with_ci(a.output, ".gz") ? FileCompression::Gzip : FileCompression::None);
    written = {a.output};
  }
  if (a.json) {
    JsonWriter j;
    j.begin_object().key("input").value(a.input).key("input_kind").value(in.kind);
    write_grid_geometry(j, grid);
    write_entropy(j, grid);
    j.key("without_effect").value(in.notes);
    j.key("files").value(written);
    write_issues(j, {});
    j.end_object();
    fmt::print("{}\n", j.str());
    return;
  }
  for (const auto& n : in.notes) fmt::print("  without effect: {}\n", n);
  fmt::print("{} {}: {} x {} cells of {} m, x [{}, {}] y [{}, {}] m\n", in.kind, printable(a.input),
             grid.size_x(), grid.size_y(), grid.resolution(), grid.x_min(), grid.x_max(),
             grid.y_min(), grid.y_max());
  fmt::print("{}", entropy_line(grid));
  for (const auto& f : written) fmt::print("  wrote {}\n", printable(f));
}

// ---------------------------------------------------------- map voronoi --

struct MapVoronoiArgs {
  std::string input;
  std::string output;
  VoronoiOptions options;
  bool json = false;
};

// The grid as map_saver's gray levels with the diagram drawn in black on
// top: occupied 0, diagram 0 too but only on free cells, so the image
// reads as the map with its skeleton.
void run_map_voronoi(const MapVoronoiArgs& a) {
  if (!ends_with_ci(a.output, ".png") && !ends_with_ci(a.output, ".pgm")) {
    throw CLI::ValidationError("--out", fmt::format("{}: expected a .png or .pgm image",
                                                    printable(a.output)));
  }
  const LoadedGrid in = load_any_grid(a.input, "IN");
  check_outputs_distinct(in.files, {a.output});
  const OccupancyGrid& grid = in.grid;
  // The diagram and the picture drawn from it, before allocating either.
  check_memory_budget(voronoi_diagram_bytes(grid.size_x(), grid.size_y()) +
                          static_cast<std::uint64_t>(grid.size_x()) * grid.size_y(),
                      fmt::format("{}: {} \u00d7 {} cells (their Voronoi diagram and its picture)",
                                  printable(in.files.back().string()), grid.size_x(),
                                  grid.size_y()));
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
  write_gray_image(a.output, img, ends_with_ci(a.output, ".pgm") ? ImageFormat::Pgm : ImageFormat::Png);
  std::vector<Issue> issues;
  if (vd.cells == 0) {
    issues.push_back({"empty-diagram",
                      fmt::format("no free cell is equidistant to two obstacles with more than "
                                  "{} m of clearance (--robot-size)",
                                  a.options.min_clearance)});
  }
  if (a.json) {
    JsonWriter j;
    j.begin_object().key("input").value(a.input).key("input_kind").value(in.kind);
    write_grid_geometry(j, grid);
    j.key("diagram_cells").value(vd.cells);
    j.key("diagram_length_m").value(static_cast<double>(vd.cells) * grid.resolution());
    j.key("min_clearance_m");
    if (vd.cells > 0) {
      j.value(lo);
    } else {
      j.null();
    }
    j.key("max_clearance_m");
    if (vd.cells > 0) {
      j.value(hi);
    } else {
      j.null();
    }
    j.key("files").value(std::vector<std::string>{a.output});
    write_issues(j, issues);
    j.end_object();
    fmt::print("{}\n", j.str());
    finish(issues);
    return;
  }
  fmt::print("{} {}: {} x {} cells of {} m\n", in.kind, printable(a.input), grid.size_x(),
             grid.size_y(), grid.resolution());
  if (vd.cells > 0) {
    fmt::print("  voronoi diagram: {} cells ({:.2f} m), clearance {:.3f} to {:.3f} m\n", vd.cells,
               static_cast<double>(vd.cells) * grid.resolution(), lo, hi);
  } else {
    fmt::print("  voronoi diagram: no cell\n");
  }
  fmt::print("  wrote {}\n", printable(a.output));
  finish(issues);
}

// ------------------------------------------------------------ map check --

struct MapCheckArgs {
  std::string input;
  double resolution = 0.05;
  bool json = false;
};

// A simple map's 2D scans replayed against each other (scan_consistency.h).
void run_map_check(const MapCheckArgs& a) {
  check_regular_input(a.input, "simplemap");
  const SimpleMap map = load_mrpt_simplemap(a.input);
  SimplemapCheck result;
  try {
    result = check_simplemap(map, static_cast<float>(a.resolution));
  } catch (const SelectionError& e) {
    throw SelectionError(e.option(), fmt::format("{}: {}", printable(a.input), e.what()));
  }
  const ScanConsistency& c = result.consistency;
  const std::vector<SE2d>& poses = result.poses;
  // The scans that saw the most through walls, at most five.
  std::vector<std::size_t> order(poses.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const std::size_t worst_n = std::min<std::size_t>(5, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(worst_n), order.end(),
                    [&](std::size_t x, std::size_t y) { return c.through_walls[x] > c.through_walls[y]; });
  order.resize(worst_n);
  std::vector<Issue> issues;
  for (const ScanCheckIssue& i : result.issues) issues.push_back({i.code, i.message});
  if (a.json) {
    JsonWriter j;
    j.begin_object().key("input").value(a.input);
    j.key("keyframes").value(result.keyframes).key("scans").value(poses.size());
    j.key("resolution").value(c.resolution).key("checked").value(c.checked);
    j.key("contradicted").value(c.contradicted);
    j.key("worst").begin_array();
    for (const std::size_t i : order) {
      const Eigen::Vector2d& t = poses[i].translation();
      j.begin_object().key("scan").value(i).key("through_walls").value(c.through_walls[i]);
      j.key("x").value(t.x()).key("y").value(t.y()).end_object();
    }
    j.end_array();
    write_issues(j, issues);
    j.end_object();
    fmt::print("{}\n", j.str());
    finish(issues);
    return;
  }
  fmt::print("simplemap {}: {} keyframes, {} 2D scans\n", printable(a.input), result.keyframes,
             poses.size());
  if (c.resolution > 0.0) {
    fmt::print("  scans against each other ({:g} m cells): {} of {} with more than {:.0f} % of the rays "
               "through walls\n",
               c.resolution, c.contradicted, c.checked, 100.0 * kContradictedRays);
    for (const std::size_t i : order) {
      const Eigen::Vector2d& t = poses[i].translation();
      fmt::print("  scan {} at ({:.2f}, {:.2f}) m: {:.0f} % of its rays through walls\n", i, t.x(), t.y(),
                 100.0 * c.through_walls[i]);
    }
  }
  finish(issues);
}

}  // namespace

void add_map_command(CLI::App& app) {
  auto* map = app.add_subcommand("map", "Build metric maps from datasets");
  map->require_subcommand(1);
  auto args = std::make_shared<MapBuildArgs>();
  auto* build = map->add_subcommand(
      "build",
      "Build the maps an MRPT config declares from a rawlog (poses from odometry) or a "
      "simplemap (its poses), as MRPT's observations2map. Writes map_* files into the output "
      "folder, each atomically. Exit status: 0 ok, 1 error, 3 written with issues (nothing "
      "inserted, an empty map), 130 Ctrl-C (nothing written)");
  build->add_option("CONFIG", args->config, "MRPT-style config file declaring a multi-metric map")
      ->required();
  build->add_option("INPUT", args->input,
                    "MRPT simplemap, or a rawlog: MRPT or rove rawlog (plain or gzip), CARMEN log "
                    "(plain or bzip2)")
      ->required();
  build->add_option("-o,--out", args->out_dir, "output folder (created)")->required();
  build->add_option("--section", args->section,
                    "config section with the `<kind>_count` keys (default: the first such)");
  build->add_flag("--json", args->json, "print the summary as JSON");
  build->callback([args] { run_map_build(*args); });

  auto cargs = std::make_shared<MapConvertArgs>();
  auto* convert = map->add_subcommand(
      "convert",
      "Convert an occupancy grid between a ROS map (map.yaml + PNG/PGM), an MRPT .gridmap "
      "(read only) and rove's binary .rovegrid. Outputs are written atomically and may not "
      "be any input");
  convert->add_option("IN", cargs->input, "map.yaml, .gridmap[.gz] or .rovegrid[.gz]")->required();
  convert->add_option("OUT", cargs->output,
                      "NAME.yaml (writes NAME.png + NAME.yaml) or .rovegrid[.gz]")
      ->required();
  convert
      ->add_option("--mode", cargs->mode,
                   "ROS map image, stated in the yaml as map_server's mode: trinary "
                   "(map_saver's 0/205/254) or scale (255·p(free))")
      ->check(CLI::IsMember({"trinary", "scale"}))
      ->capture_default_str();
  convert->add_flag("--probability", cargs->probability, "same as --mode scale");
  convert->add_flag("--pgm", cargs->pgm, "write the image as PGM (P5) instead of PNG");
  convert->add_flag("--json", cargs->json, "print the summary as JSON");
  convert->callback([cargs] { run_map_convert(*cargs); });

  auto vargs = std::make_shared<MapVoronoiArgs>();
  auto* voronoi = map->add_subcommand(
      "voronoi",
      "Compute the Voronoi diagram of a grid's free space (with clearances) and draw it over "
      "the map as an image (written atomically; it may not be the map's own image). Exit "
      "status 3 when the diagram is empty");
  voronoi->add_option("IN", vargs->input, "map.yaml, .gridmap[.gz] or .rovegrid[.gz]")->required();
  voronoi->add_option("-o,--out", vargs->output, "image to write (.png or .pgm)")->required();
  voronoi->add_option("--robot-size", vargs->options.min_clearance,
                      "leave out cells with at most this clearance, meters")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  voronoi->add_option("--occupied-below", vargs->options.occupied_threshold,
                      "p(free) below which a cell is an obstacle")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  voronoi->add_option("--separation", vargs->options.min_separation,
                      "the two obstacles must be more than this × the clearance apart")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  voronoi->add_flag("--json", vargs->json, "print the summary as JSON");
  voronoi->callback([vargs] { run_map_voronoi(*vargs); });

  auto kargs = std::make_shared<MapCheckArgs>();
  auto* check = map->add_subcommand(
      "check",
      "Check a simplemap's 2D scans against each other: replayed in keyframe order into an "
      "occupancy grid, each first traced through the grid of those before it; a scan with more "
      "than 20 % of its rays through walls contradicts the map. Exit status 3 when more than 10 % "
      "(at least 3) do: a loop closed wrong, or one not closed");
  check->add_option("SIMPLEMAP", kargs->input, "MRPT .simplemap (plain or gzip)")->required();
  check->add_option("--resolution", kargs->resolution, "cell side of the replay's grid, meters")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  check->add_flag("--json", kargs->json, "print the summary as JSON");
  check->callback([kargs] { run_map_check(*kargs); });
}

}  // namespace rove::cli
