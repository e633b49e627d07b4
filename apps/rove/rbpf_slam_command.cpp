#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "filter_command.h"
#include "rbpf_slam_cli.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/parallel.h"
#include "rove/core/progress.h"
#include "rove/core/timer.h"
#include "rove/io/grid_image.h"
#include "rove/io/tum_trajectory.h"
#include "rove/maps/grid_agreement.h"
#include "rove/slam/localization_image.h"
#include "rove/slam/rbpf_slam_run.h"

namespace rove::cli {
namespace {

namespace fs = std::filesystem;

// The map's agreement with a reference map of the same data (--reference).
struct Reference {
  std::string file;
  GridAgreement agreement;
};


// One line per filter update: the effective sample size before resampling
// and what the update did.
void write_ess(const fs::path& path, const RbpfSlamResult& res) {
  std::string text =
      "step,time,ess,effective_particles,resampled,inserted,fallbacks,distinct_tiles,fit,through_walls,"
      "seconds\n";
  const double n = static_cast<double>(res.options.particles);
  for (const auto& s : res.steps) {
    if (!s.updated) continue;
    fmt::format_to(std::back_inserter(text), "{},{:.6f},{:.6f},{:.3f},{},{},{},{},{:.4f},{:.4f},{:.6f}\n",
                   s.index, s.time.valid() ? s.time.to_seconds() : -1.0, s.update.ess,
                   s.update.ess * n, s.update.resampled ? 1 : 0, s.inserted ? 1 : 0,
                   s.update.fallbacks, s.update.distinct_tiles, s.update.fit, s.update.through_walls,
                   s.seconds);
  }
  write_text_file_atomically(path, text);
}

struct Written {
  std::vector<std::string> files;
  std::string picture;
};

Written write_outputs(const fs::path& dir, const RbpfSlamResult& res) {
  Written w;
  const auto add = [&](const fs::path& p) { w.files.push_back(p.string()); };
  write_rbpf_paths(dir, res.steps, res.path, w.files);
  write_ess(dir / "ess.csv", res);
  add(dir / "ess.csv");
  GridImageOptions scale;  // the whole probability, as MRPT's bitmap
  scale.mode = RosMapMode::Scale;
  scale.fast_png = true;  // the default filter search was 3 % of a Telecom run's instructions
  // The picture is drawn on a second thread when the run has one (the two
  // images were 4 % of a Telecom run's instructions, after the filter).
  const fs::path picture = dir / "picture.png";
  const auto draw = [&] { render_localization_png(picture.string(), res.map, res.particles, res.path); };
  std::future<void> drawn;
  if (res.options.num_threads > 1) drawn = std::async(std::launch::async, draw);
  const RosMapFiles gf = save_ros_map((dir / "map").string(), res.map, scale);
  if (drawn.valid()) {
    drawn.get();
  } else {
    draw();
  }
  w.files.push_back(gf.image);
  w.files.push_back(gf.yaml);
  add(picture);
  w.picture = picture.string();
  return w;
}

std::string summary_json(const RbpfSlamCliOptions& o, const std::string& config,
                         const std::string& rawlog, const RbpfSlamConfig& cfg,
                         const RbpfSlamResult& res, const std::optional<Reference>& ref,
                         const std::vector<Issue>& issues, const Written& w, double total) {
  double max_step = 0.0;
  for (const auto& s : res.steps) max_step = std::max(max_step, s.seconds);
  const Pose2& last = res.path.back();
  JsonWriter j;
  j.begin_object();
  j.key("config").value(config);
  j.key("rawlog").value(rawlog);
  j.key("format").value(to_string(res.format));
  j.key("seed").value(o.seed);
  j.key("threads").value(res.options.num_threads);
  j.key("proposal").value(std::string(mrpt_name(res.options.proposal)));
  j.key("particles").value(res.options.particles);
  j.key("resolution").value(static_cast<double>(res.options.resolution));
  j.key("scans").value(res.scans);
  write_rbpf_counts(j, res);
  j.key("final_pose").begin_object();
  j.key("x").value(last.x()).key("y").value(last.y()).key("phi").value(last.phi()).end_object();
  j.key("map_cells").begin_object();
  j.key("x").value(res.map.size_x()).key("y").value(res.map.size_y()).end_object();
  j.key("peak_distinct_tiles").value(res.peak_tiles);
  j.key("peak_tile_bytes").value(res.peak_tile_bytes);
  j.key("unshared_tiles").value(res.unshared_tiles);
  j.key("contradicted_updates").value(res.contradicted_updates);
  j.key("mapping_seconds").value(res.mapping_seconds);
  j.key("seconds_per_scan").value(res.scans ? res.mapping_seconds / static_cast<double>(res.scans) : 0.0);
  j.key("seconds_per_step_max").value(max_step);
  j.key("read_seconds").value(res.read_seconds);
  j.key("total_seconds").value(total);
  j.key("reference");
  if (ref) {
    j.begin_object().key("file").value(ref->file);
    j.key("compared_cells").value(ref->agreement.compared);
    j.key("agreement").value(ref->agreement.agreement());
    j.key("occupied_cells").value(ref->agreement.occupied);
    j.key("wall_agreement").value(ref->agreement.wall_agreement());
    j.key("occupied_known_cells").value(ref->agreement.occupied_known);
    j.key("known_wall_agreement").value(ref->agreement.known_wall_agreement()).end_object();
  } else {
    j.null();
  }
  write_ignored_keys(j, cfg);
  j.key("files").value(w.files);
  write_issues(j, issues);
  j.end_object();
  return j.str() + "\n";
}

void print_text(const std::string& config, const std::string& rawlog, const RbpfSlamConfig& cfg,
                const RbpfSlamResult& res, const std::optional<Reference>& ref,
                const std::vector<Issue>& issues, const Written& w, const std::string& out_dir,
                double total) {
  fmt::print("rbpf-slam: {} steps ({} scans) from {} ({})\n", res.steps.size(), res.scans,
             printable(rawlog), to_string(res.format));
  fmt::print("  config: {}\n", printable(config));
  fmt::print("  filter: {} particles, {} proposal, {} updates, {} insertions\n",
             res.options.particles, mrpt_name(res.options.proposal), res.updates, res.insertions);
  fmt::print("  result: {}\n", res.message);
  fmt::print("  final pose: {}\n", res.path.back().as_string());
  fmt::print("  scans against the map: {} of {} updates with more than {:.0f} % of the rays through walls\n",
             res.contradicted_updates, res.updates, 100.0 * kContradictedRays);
  fmt::print("  map: {} x {} cells of {:g} m; tiles: {} distinct at peak ({:.1f} MB), {} unshared\n",
             res.map.size_x(), res.map.size_y(), res.map.resolution(), res.peak_tiles,
             static_cast<double>(res.peak_tile_bytes) / 1e6, res.unshared_tiles);
  fmt::print("  time: mapping {:.3f} s ({:.2f} ms/scan), reading {:.3f} s, total {:.3f} s\n",
             res.mapping_seconds,
             res.scans ? 1e3 * res.mapping_seconds / static_cast<double>(res.scans) : 0.0,
             res.read_seconds, total);
  if (ref) {
    fmt::print("  reference {}: {:.2f} % of {} cells known in both agree; {:.2f} % of {} occupied "
               "cells have a reference wall within 1 cell ({:.2f} % of the {} the reference saw)\n",
               printable(ref->file), 100.0 * ref->agreement.agreement(), ref->agreement.compared,
               100.0 * ref->agreement.wall_agreement(), ref->agreement.occupied,
               100.0 * ref->agreement.known_wall_agreement(), ref->agreement.occupied_known);
  }
  if (!cfg.ignored_keys.empty()) {
    fmt::print("  config keys without effect: {}\n", cfg.ignored_keys.size());
  }
  fmt::print("  wrote {} files to {}/ (picture: {})\n", w.files.size(), printable(out_dir),
             printable(w.picture));
  if (issues.empty()) {
    fmt::print("  issues: none\n");
  } else {
    fmt::print("  issues:\n");
    for (const auto& i : issues) fmt::print("    {}: {}\n", i.code, i.message);
  }
}

void run(const RbpfSlamCliOptions& o) {
  Stopwatch total;
  check_regular_input(o.config, "rbpf-slam config file");
  const IniFile ini = IniFile::load(o.config);
  const RbpfSlamConfig cfg = load_rbpf_slam_config(ini);
  const std::string rawlog = rawlog_to_read(o.rawlog, o.config, cfg, "MappingApplication");
  check_regular_input(rawlog, "rawlog");
  RbpfSlamRunOptions ro;
  ro.seed = o.seed;
  ro.num_threads = resolve_thread_count(o.threads, "--threads");
  ro.max_steps = o.max_steps;
  ro.particles = o.particles;
  if (cfg.map == RbpfMapKind::Beacons) {
    if (!o.reference.empty()) {
      throw InvalidArgument("--reference compares occupancy grids; " + printable(o.config) +
                            " maps beacons (use --ground-truth)");
    }
    run_ro_slam_command(o, cfg, rawlog, std::move(ro), total);
    return;
  }
  if (!o.truth.empty()) {
    throw InvalidArgument("--ground-truth takes beacon positions; " + printable(o.config) +
                          " maps an occupancy grid (use --reference)");
  }
  const fs::path dir = output_folder(o.out_dir);
  std::vector<fs::path> inputs{fs::path(o.config), fs::path(rawlog)};
  if (!o.reference.empty()) {
    check_regular_input(o.reference, "reference map");
    inputs.emplace_back(o.reference);
  }
  const std::vector<fs::path> outputs{dir / "path.tum",    dir / "odometry.tum", dir / "ess.csv",
                                      dir / "map.png",     dir / "map.yaml",     dir / "picture.png",
                                      dir / "summary.json"};
  check_outputs_distinct(inputs, outputs);
  const RbpfSlamResult res = run_with_progress(
      o.progress, "rbpf-slam " + printable(rawlog), o.out_dir, [&](const std::function<void()>& step) {
        ro.on_step = [&](std::uint64_t) { step(); };
        return run_rbpf_slam(cfg, rawlog, ro);
      });
  const std::vector<Issue> issues = to_issues(res.issues);
  std::optional<Reference> ref;
  if (!o.reference.empty()) ref = Reference{o.reference, grid_agreement(res.map, load_ros_map(o.reference).grid)};
  create_output_folder(dir);
  Written w = write_outputs(dir, res);
  publish_summary(
      dir, w.files, o.json,
      [&] { return summary_json(o, o.config, rawlog, cfg, res, ref, issues, w, total.elapsed()); },
      [&] { print_text(o.config, rawlog, cfg, res, ref, issues, w, o.out_dir, total.elapsed()); },
      issues);
}

}  // namespace

void write_ignored_keys(JsonWriter& j, const RbpfSlamConfig& cfg) {
  j.key("ignored_keys").begin_array();
  for (const auto& k : cfg.ignored_keys) {
    j.begin_object().key("section").value(k.section).key("key").value(k.key);
    j.key("reason").value(k.reason).end_object();
  }
  j.end_array();
}

void add_rbpf_slam_command(CLI::App& app) {
  auto o = std::make_shared<RbpfSlamCliOptions>();
  auto* cmd = app.add_subcommand(
      "rbpf-slam",
      "Build an occupancy grid (or a map of range-only beacons) and the robot's path with a "
      "Rao-Blackwellized particle filter (MRPT's rbpf-slam), from an MRPT rbpf-slam config and a "
      "rawlog");
  cmd->add_option("config", o->config,
                  "MRPT rbpf-slam configuration file (.ini), e.g. gridmapping_optimal_sampling.ini "
                  "or RO-SLAM_simulatedData_MC.ini")
      ->required();
  cmd->add_option("rawlog", o->rawlog, "rawlog or CARMEN log (default: the config's rawlog_file)");
  cmd->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  add_seed_and_threads(cmd, o->seed, o->threads);
  cmd->add_option("--particles", o->particles, "particle count (default: the config's sampleSize)")
      ->check(CLI::Range(1u, 1000000u));
  cmd->add_option("--max-steps", o->max_steps, "process at most this many steps (default: all)");
  cmd->add_option("--reference", o->reference,
                  "a ROS map.yaml of the same data (e.g. rove icp-slam's map.yaml): report the cell "
                  "agreement of the map with it");
  cmd->add_option("--ground-truth", o->truth,
                  "with a beacon map: MRPT's beacon ground-truth file (ID X Y Z per line, e.g. "
                  "RO-SLAM_demo_ground_truth.txt): report each beacon's error and their RMSE");
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("!--no-progress", o->progress, "do not report progress on stderr");
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
