// `rove lidar-slam [CONFIG.ini] LOG [-o DIR] [--json]`: 2D lidar SLAM with
// loop closure (rove/slam/lidar_slam.h) over an MRPT rawlog, a rove rawlog
// or a CARMEN log.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "lidar_slam_plot.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/parallel.h"
#include "rove/core/progress.h"
#include "rove/core/timer.h"
#include "rove/graph/graph_io.h"
#include "rove/io/grid_image.h"
#include "rove/io/tum_trajectory.h"
#include "rove/poses/lie_conversion.h"
#include "rove/slam/lidar_slam.h"
#include "rove/slam/lidar_slam_run.h"

namespace rove::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kOutputs[] = {"path.tum",     "nodes.tum",         "odometry.tum",
                                    "map.png",      "map.yaml",          "graph.g2o",
                                    "loop_closures.csv", "lidar_slam.png", "summary.json"};

struct LidarSlamCliOptions {
  std::vector<std::string> inputs;  // [CONFIG.ini] LOG
  std::string out_dir = "lidar-slam-out";
  bool json = false;
  bool progress = true;
  std::optional<std::uint64_t> max_scans;
  std::optional<float> max_range;
  std::string sensor;
  std::optional<int> threads;  // overrides [backend] num_threads
};

struct Config {
  std::string path;  // empty: defaults
  LidarSlamOptions slam;
  LidarMapOptions map;
  std::optional<float> carmen_max_range;
};

// The lidar SLAM sections, [map], and [CARMEN] maxRange (as icp-slam's).
Config load_config(const std::string& path) {
  Config c;
  c.path = path;
  if (path.empty()) return c;
  check_regular_input(path, "lidar-slam config file");
  const IniFile ini = IniFile::load(path);
  c.slam = load_lidar_slam_options(ini);
  c.map = LidarMapOptions::from_config(ConfigSection(ini, "map"));
  if (ini.has_section("CARMEN")) {
    const ConfigSection carmen(ini, "CARMEN");
    if (carmen.has("maxRange")) {
      c.carmen_max_range = static_cast<float>(carmen.get_in_range("maxRange", 81.0, 1e-3, 1e6));
    }
    carmen.check_all_read();
  }
  for (const std::string& s : ini.sections()) {
    const bool known = s == "map" || s == "CARMEN" ||
                       std::find(std::begin(kLidarSlamSections), std::end(kLidarSlamSections), s) !=
                           std::end(kLidarSlamSections);
    if (!known) {
      throw ConfigError(path, s, "",
                        "unknown section; lidar-slam reads [frontend], [submaps], [loop_closure], "
                        "[backend], [map] and [CARMEN]");
    }
  }
  return c;
}

struct Written {
  std::vector<std::string> files;
  std::size_t map_cells_x = 0, map_cells_y = 0;
};

void write_trajectories(const fs::path& dir, const LidarSlam& slam, const LidarSlamRunResult& res,
                        Written& w) {
  std::vector<TimedPose2> path, nodes, odo;
  for (std::size_t i = 0; i < slam.num_scans(); ++i) {
    path.push_back({slam.scan_time(i), to_pose2(slam.scan_pose(i))});
    if (!res.odometry.empty()) odo.push_back({slam.scan_time(i), to_pose2(res.odometry[i])});
  }
  for (const auto& n : slam.nodes()) nodes.push_back({n.time, to_pose2(n.T_world_robot)});
  write_tum_trajectory((dir / "path.tum").string(), path);
  w.files.push_back((dir / "path.tum").string());
  write_tum_trajectory((dir / "nodes.tum").string(), nodes);
  w.files.push_back((dir / "nodes.tum").string());
  if (!odo.empty()) {
    write_tum_trajectory((dir / "odometry.tum").string(), odo);
    w.files.push_back((dir / "odometry.tum").string());
  }
}

void write_loop_closures(const fs::path& dir, const LidarSlam& slam, Written& w) {
  std::string csv =
      "node,submap,node_time,outcome,score,refined_score,second_score,icp_goodness,correction_m,"
      "correction_deg,"
      "x,y,theta\n";
  for (const auto& lc : slam.loop_closures()) {
    const Timestamp t = slam.nodes()[lc.node].time;
    csv += fmt::format("{},{},{:.6f},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.3f},{:.6f},{:.6f},{:.6f}\n",
                       lc.node, lc.submap, t.valid() ? t.to_seconds() : 0.0, to_string(lc.outcome),
                       lc.score, lc.refined_score, lc.second_score, lc.icp_goodness,
                       lc.correction_translation,
                       lc.correction_rotation * 180.0 / 3.14159265358979323846,
                       lc.T_submap_robot.translation().x(), lc.T_submap_robot.translation().y(),
                       lc.T_submap_robot.angle());
  }
  const std::string p = (dir / "loop_closures.csv").string();
  write_text_file_atomically(p, csv);
  w.files.push_back(p);
}

void write_maps(const fs::path& dir, const LidarSlam& slam, const LidarMapOptions& map, Written& w) {
  const OccupancyGrid grid = build_lidar_slam_map(slam, map);
  w.map_cells_x = grid.size_x();
  w.map_cells_y = grid.size_y();
  GridImageOptions scale;
  scale.mode = RosMapMode::Scale;
  const RosMapFiles f = save_ros_map((dir / "map").string(), grid, scale);
  w.files.push_back(f.image);
  w.files.push_back(f.yaml);
  write_graph(slam.graph(), (dir / "graph.g2o").string(), GraphFileFormat::G2o);
  w.files.push_back((dir / "graph.g2o").string());
  SlamPlotContent content;
  for (std::size_t i = 0; i < slam.num_scans(); ++i) content.path.push_back(slam.scan_pose(i).translation());
  for (const auto& s : slam.submaps()) content.submap_origins.push_back(s.T_world_submap.translation());
  for (const auto& lc : slam.loop_closures()) {
    if (lc.outcome != LoopClosureOutcome::Accepted) continue;
    content.loop_edges.emplace_back(
        slam.submaps()[static_cast<std::size_t>(lc.submap)].T_world_submap.translation(),
        slam.nodes()[lc.node].T_world_robot.translation());
  }
  const std::string plot = (dir / "lidar_slam.png").string();
  write_slam_plot(grid, content, plot);
  w.files.push_back(plot);
}

double real_time_factor(const LidarSlamRunResult& res, double seconds) {
  const double duration = res.last_time - res.first_time;
  return seconds > 0.0 && duration > 0.0 ? duration / seconds : 0.0;
}

std::string summary_json(const Config& cfg, const std::string& log, const LidarSlam& slam,
                         const LidarSlamRunResult& res, const Written& w,
                         const std::vector<Issue>& issues, double total_seconds) {
  const LidarSlamStats& st = slam.stats();
  JsonWriter j;
  j.begin_object();
  j.key("config").value(cfg.path);
  j.key("log").value(log);
  j.key("format").value(to_string(res.format));
  j.key("sensor_label").value(res.sensor_label);
  j.key("scans").value(st.scans);
  j.key("other_sensor_scans").value(res.other_scans);
  j.key("scans_without_points").value(st.scans_without_points);
  j.key("odometry").value(!res.odometry.empty());
  j.key("matched").value(st.matched);
  j.key("match_score_mean").value(st.matched ? st.match_score_sum / static_cast<double>(st.matched) : 0.0);
  j.key("poor_matches").value(res.poor_matches);
  j.key("match_not_converged").value(st.match_not_converged);
  j.key("nodes").value(st.nodes);
  j.key("nodes_checked").value(res.consistency.checked);
  j.key("nodes_contradicted").value(res.consistency.contradicted);
  j.key("consistency_resolution").value(res.consistency.resolution);
  j.key("submaps").value(st.submaps);
  j.key("loop_searches").value(st.loop_searches);
  j.key("loops_accepted").value(st.loops_accepted);
  j.key("loops_low_score").value(st.loops_low_score);
  j.key("loops_icp_rejected").value(st.loops_icp_rejected);
  j.key("loops_inconsistent").value(st.loops_inconsistent);
  j.key("loops_ambiguous").value(st.loops_ambiguous);
  j.key("optimizations").value(st.optimizations);
  if (const auto& o = slam.last_optimization()) {
    j.key("last_optimization").begin_object();
    j.key("termination").value(std::string(to_string(o->termination)));
    j.key("message").value(o->message);
    j.key("initial_chi2").value(o->initial_chi2).key("final_chi2").value(o->final_chi2);
    j.key("iterations").value(o->iterations);
    j.end_object();
  }
  const LidarBackEndOptions& b = slam.options().backend;
  j.key("refinement").begin_object();
  j.key("scan_window").value(b.scan_window);
  j.key("window_edges").value(st.window_edges);
  j.key("window_failed").value(st.window_failed);
  j.key("threads").value(resolve_thread_count(b.num_threads));
  j.key("seconds").value(st.refinement_seconds);
  j.end_object();
  j.key("graph_vertices").value(slam.graph().num_vertices());
  j.key("graph_edges").value(slam.graph().num_edges());
  j.key("map_cells").begin_array().value(w.map_cells_x).value(w.map_cells_y).end_array();
  j.key("log_duration_seconds").value(res.last_time - res.first_time);
  j.key("mapping_seconds").value(res.mapping_seconds);
  j.key("frontend_seconds").value(st.frontend_seconds);
  j.key("insertion_seconds").value(st.insertion_seconds);
  j.key("loop_closure_seconds").value(st.loop_seconds);
  j.key("optimization_seconds").value(st.optimization_seconds);
  j.key("read_seconds").value(res.read_seconds);
  j.key("seconds_per_scan").value(st.scans ? res.mapping_seconds / static_cast<double>(st.scans) : 0.0);
  j.key("real_time_factor").value(real_time_factor(res, res.mapping_seconds + res.read_seconds));
  j.key("total_seconds").value(total_seconds);
  j.key("files").value(w.files);
  write_issues(j, issues);
  j.end_object();
  return j.str() + "\n";
}

void print_report(const Config& cfg, const std::string& log, const std::string& out_dir,
                  const LidarSlam& slam, const LidarSlamRunResult& res, const Written& w,
                  const std::vector<Issue>& issues, double total_seconds) {
  const LidarSlamStats& st = slam.stats();
  fmt::print("lidar-slam: {} scans of '{}' from {} ({})\n", st.scans, printable(res.sensor_label),
             printable(log), to_string(res.format));
  fmt::print("  config: {}\n", cfg.path.empty() ? std::string("defaults") : printable(cfg.path));
  fmt::print("  front-end: {} matched (mean score {:.3f}, {} poor), {} nodes, {} submaps{}\n",
             st.matched, st.matched ? st.match_score_sum / static_cast<double>(st.matched) : 0.0,
             res.poor_matches, st.nodes, st.submaps,
             res.odometry.empty() ? ", no odometry" : "");
  fmt::print("  loop closure: {} searches, {} accepted, {} below min_score, {} ambiguous, {} not "
             "confirmed by ICP, {} without an agreeing candidate\n",
             st.loop_searches, st.loops_accepted, st.loops_low_score, st.loops_ambiguous,
             st.loops_icp_rejected, st.loops_inconsistent);
  if (res.consistency.resolution > 0.0) {
    fmt::print("  nodes against each other: {} of {} with more than {:.0f} % of the rays through walls ({:g} m "
               "cells)\n",
               res.consistency.contradicted, res.consistency.checked, 100.0 * kContradictedRays,
               res.consistency.resolution);
  } else {
    fmt::print("  nodes against each other: not checked (their scans span more than {} tiles of 32 cells "
               "even at 8x the 5 cm cells)\n",
               kMaxReplayTiles);
  }
  if (const auto& o = slam.last_optimization()) {
    fmt::print("  pose graph: {} vertices, {} edges; {} optimizations, the last {} (chi2 {:.4g} -> {:.4g})\n",
               slam.graph().num_vertices(), slam.graph().num_edges(), st.optimizations,
               to_string(o->termination), o->initial_chi2, o->final_chi2);
  } else {
    fmt::print("  pose graph: {} vertices, {} edges; not optimized (no loop closure)\n",
               slam.graph().num_vertices(), slam.graph().num_edges());
  }
  const LidarBackEndOptions& b = slam.options().backend;
  if (b.scan_window > 0 && st.window_edges + st.window_failed > 0) {
    fmt::print("  refinement: every scan aligned with the next {}: {} pairs aligned, {} not; {:.3f} s "
               "on {} thread{}\n",
               b.scan_window, st.window_edges, st.window_failed, st.refinement_seconds,
               resolve_thread_count(b.num_threads), resolve_thread_count(b.num_threads) == 1 ? "" : "s");
  } else {
    fmt::print("  refinement: off ({})\n",
               b.scan_window == 0 ? "[backend] scan_window = 0" : "no scan pair to align");
  }
  const double per_scan = st.scans ? res.mapping_seconds / static_cast<double>(st.scans) : 0.0;
  fmt::print("  time: mapping {:.3f} s ({:.3f} ms/scan; front-end {:.3f} s, insertion {:.3f} s, "
             "loops {:.3f} s, optimization {:.3f} s), reading {:.3f} s, total {:.3f} s\n",
             res.mapping_seconds, 1e3 * per_scan, st.frontend_seconds, st.insertion_seconds,
             st.loop_seconds, st.optimization_seconds, res.read_seconds, total_seconds);
  fmt::print("  log: {:.1f} s of data, {:.1f}x real time (mapping and reading)\n",
             res.last_time - res.first_time,
             real_time_factor(res, res.mapping_seconds + res.read_seconds));
  fmt::print("  wrote {} files to {}/ (map {} x {} cells)\n", w.files.size(), printable(out_dir),
             w.map_cells_x, w.map_cells_y);
  if (issues.empty()) {
    fmt::print("  issues: none\n");
  } else {
    fmt::print("  issues:\n");
    for (const auto& i : issues) fmt::print("    {}: {}\n", i.code, i.message);
  }
}

LidarSlamRunResult run_with_progress(LidarSlam& slam, const std::string& log, LidarSlamRunOptions ro,
                                     const LidarSlamCliOptions& o) {
  std::optional<Progress> progress;
  if (o.progress) progress.emplace(std::nullopt, "lidar-slam " + printable(log), std::cerr);
  std::uint64_t done = 0;
  ro.on_scan = [&](const LidarSlamScanUpdate&) {
    ++done;
    if (progress) progress->advance();
  };
  try {
    LidarSlamRunResult res = run_lidar_slam(slam, log, ro);
    if (progress) progress->finish();
    return res;
  } catch (const Interrupted&) {
    if (progress) progress->finish();
    fmt::print(stderr, "rove: interrupted after {} scans; nothing written to {}\n", done,
               printable(o.out_dir));
    throw;
  }
}

void run(const LidarSlamCliOptions& o) {
  Stopwatch total;
  const std::string config_path = o.inputs.size() == 2 ? o.inputs[0] : std::string();
  const std::string log = o.inputs.back();
  const Config cfg = load_config(config_path);
  check_regular_input(log, "log");
  const fs::path dir(o.out_dir);
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw IoError(o.out_dir, "the output folder (-o) exists and is not a folder");
  }
  std::vector<fs::path> planned;
  for (const char* f : kOutputs) planned.push_back(dir / f);
  std::vector<fs::path> inputs{fs::path(log)};
  if (!config_path.empty()) inputs.emplace_back(config_path);
  check_outputs_distinct(inputs, planned);

  LidarSlamOptions slam_options = cfg.slam;
  if (o.threads) slam_options.backend.num_threads = resolve_thread_count(*o.threads, "--threads");
  LidarSlam slam(slam_options);
  LidarSlamRunOptions ro;
  ro.max_scans = o.max_scans;
  ro.sensor_label = o.sensor;
  if (cfg.carmen_max_range) ro.reader.carmen.log.flaser_max_range = *cfg.carmen_max_range;
  if (o.max_range) ro.reader.carmen.log.flaser_max_range = *o.max_range;
  const LidarSlamRunResult res = run_with_progress(slam, log, ro, o);

  std::vector<Issue> issues;
  for (const auto& i : res.issues) issues.push_back({i.code, i.message});
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(o.out_dir, "cannot create the output folder: " + ec.message());
  Written w;
  try {
    write_trajectories(dir, slam, res, w);
    write_loop_closures(dir, slam, w);
    write_maps(dir, slam, cfg.map, w);
    const std::string summary_path = (dir / "summary.json").string();
    w.files.push_back(summary_path);
    const std::string summary = summary_json(cfg, log, slam, res, w, issues, total.elapsed());
    write_text_file_atomically(summary_path, summary);
    if (o.json) {
      fmt::print("{}", summary);
    } else {
      print_report(cfg, log, o.out_dir, slam, res, w, issues, total.elapsed());
    }
  } catch (const Interrupted&) {
    std::string done;
    for (const auto& f : w.files) done += (done.empty() ? "" : ", ") + f;
    fmt::print(stderr, "rove: interrupted while writing; complete files: {}\n",
               done.empty() ? std::string("none") : printable(done));
    throw;
  }
  finish(issues);
}

}  // namespace

void add_lidar_slam_command(CLI::App& app) {
  auto o = std::make_shared<LidarSlamCliOptions>();
  auto* cmd = app.add_subcommand(
      "lidar-slam",
      "2D lidar SLAM with loop closure (submaps, branch-and-bound loop closure, pose graph) over "
      "an MRPT rawlog, a rove rawlog or a CARMEN log");
  cmd->add_option("inputs", o->inputs,
                  "[CONFIG.ini] LOG: an optional lidar-slam config (docs/lidar-slam.md), then the "
                  "log")
      ->required()
      ->expected(1, 2);
  cmd->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("!--no-progress", o->progress, "do not report progress on stderr");
  cmd->add_option("--max-scans", o->max_scans, "process at most this many scans (default: all)");
  cmd->add_option("--sensor", o->sensor,
                  "use the 2D scans of this sensor label (default: the first scan's)");
  cmd->add_option("--max-range", o->max_range,
                  "CARMEN logs: maximum range of FLASER/RLASER scans, meters, when the log has no "
                  "PARAM line stating it (default: the config's [CARMEN] maxRange, else 81)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--threads", o->threads,
                  fmt::format("threads of the final refinement's alignments, 1 to {}, 0 for all "
                              "hardware threads (default: the config's [backend] num_threads, "
                              "else 1; results do not depend on it)",
                              kMaxThreads));
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
