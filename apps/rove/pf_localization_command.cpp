#include <fmt/compile.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cli_values.h"
#include "commands.h"
#include "data_dir.h"
#include "filter_command.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/parallel.h"
#include "rove/core/progress.h"
#include "rove/core/timer.h"
#include "rove/io/tum_trajectory.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/slam/localization_image.h"
#include "rove/slam/pf_localization_run.h"

namespace rove::cli {
namespace {

namespace fs = std::filesystem;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr const char* kDemoConfig = "mrpt/localization_demo.ini";
constexpr const char* kDemoMap = "mrpt/localization_demo.simplemap.gz";
constexpr const char* kDemoRawlog = "mrpt/localization_demo.rawlog";

struct PfLocalizationCliOptions {
  std::string config;
  std::string rawlog;
  std::string map;
  std::string out_dir = "pf-localization-out";
  bool json = false;
  bool progress = true;
  std::uint64_t seed = 0;
  int threads = 1;
  std::optional<std::uint64_t> max_steps;
  std::optional<std::uint32_t> particles;
  bool global = false;
  std::string init_pose;
  std::string init_std;
  std::string recovery;
  std::uint64_t snapshot_every = 0;
};

// --init-pose x,y,yaw (the command line's pose convention, cli_values.h)
// with --init-std std_xy,std_yaw_deg, on the config's particle count.
ParticleInit init_around_pose(const std::string& pose, const std::string& std,
                              const ParticleInit& base) {
  ParticleInit init = base;
  init.mode = ParticleInitMode::AroundPose;
  const Pose2 p = parse_cli_pose2(pose, "--init-pose");
  init.pose = SE2d(p.x(), p.y(), p.phi());
  if (!std.empty()) {
    const std::vector<double> v = parse_number_list(std, "--init-std");
    if (v.size() != 2 || v[0] < 0.0 || v[1] < 0.0) {
      throw ParseError({"--init-std", std::nullopt, std::nullopt, "--init-std"},
                       "expected std_xy,std_yaw_deg, both >= 0 (m, degrees)");
    }
    init.std_xy = v[0];
    init.std_yaw = v[1] * kDeg;
  }
  return init;
}

RecoveryOptions parse_recovery(const std::string& text) {
  const std::vector<double> v = parse_number_list(text, "--recovery");
  RecoveryOptions r;
  if (v.size() != 2 || !(v[0] > 0.0 && v[0] < v[1] && v[1] < 1.0)) {
    throw ParseError({"--recovery", std::nullopt, std::nullopt, "--recovery"},
                     "expected alpha_slow,alpha_fast with 0 < alpha_slow < alpha_fast < 1 (ROS "
                     "AMCL suggests 0.001,0.1)");
  }
  r.alpha_slow = v[0];
  r.alpha_fast = v[1];
  return r;
}


std::string snapshot_name(const PfLocalizationSnapshot& s) {
  if (!s.step) return "particles_initial.txt";
  return fmt::format("particles_{:05}_{}.txt", *s.step, s.reason);
}

// Appends v with six decimals and a space, as "{:.6f} " but from one
// rounding of v·10⁶ (so a value halfway between two outputs may round the
// other way): integer formatting in a fraction of the time of a float's,
// for particle files of hundreds of thousands of lines.
void append_fixed6(std::string& out, double v) {
  const double scaled = std::round(v * 1e6);
  if (!(std::abs(scaled) < 9e15)) {  // also NaN and infinities
    fmt::format_to(std::back_inserter(out), "{:.6f} ", v);
    return;
  }
  if (std::signbit(scaled)) out += '-';
  const auto q = static_cast<std::uint64_t>(std::abs(scaled));
  char buf[24];
  char* end = std::to_chars(buf, buf + sizeof buf, q / 1000000).ptr;
  out.append(buf, static_cast<std::size_t>(end - buf));
  out += '.';
  end = std::to_chars(buf, buf + sizeof buf, 1000000 + q % 1000000).ptr;  // "1dddddd"
  out.append(buf + 1, static_cast<std::size_t>(end - buf - 1));
  out += ' ';
}

// MRPT's particle files: `% x  y  yaw[rad] log_weight`, one particle a line.
void write_particles(const fs::path& path, const ParticleSet<SE2d>& p) {
  std::string text = "% x  y  yaw[rad] log_weight\n";
  text.reserve(text.size() + p.size() * 48);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const SE2d& s = p.states[i];
    append_fixed6(text, s.translation().x());
    append_fixed6(text, s.translation().y());
    append_fixed6(text, s.angle());
    fmt::format_to(std::back_inserter(text), FMT_COMPILE("{:.6e}\n"), p.log_weights[i]);
  }
  write_text_file_atomically(path, text);
}

// One line per step: the estimate, its (x, y, phi) covariance, the counts.
void write_steps(const fs::path& path, const PfLocalizationResult& res) {
  std::string text =
      "# step time x y phi particles ess converged mass scan_fit range_residual injected "
      "cov_xx cov_xy cov_xphi cov_yy cov_yphi cov_phiphi seconds\n"
      "# (m, rad; time in seconds since the Unix epoch, -1 if unknown; scan_fit and "
      "range_residual -1 when not applicable; mass: share of the weight near the estimate; "
      "covariance of (x, y, phi) in the map frame)\n";
  for (const auto& s : res.steps) {
    const Eigen::Matrix3d C = s.estimate.world_covariance();
    const Eigen::Vector2d& t = s.estimate.mean.translation();
    fmt::format_to(std::back_inserter(text),
                   "{} {:.6f} {:.6f} {:.6f} {:.6f} {} {:.6f} {} {:.4f} {:.4f} {:.4f} {} {:.6e} {:.6e} "
                   "{:.6e} {:.6e} {:.6e} {:.6e} {:.6f}\n",
                   s.index, s.time.valid() ? s.time.to_seconds() : -1.0, t.x(), t.y(),
                   s.estimate.mean.angle(), s.particles, s.ess, s.converged ? 1 : 0, s.mass_near,
                   s.scan_fit.value_or(-1.0), s.range_residual.value_or(-1.0), s.injected, C(0, 0),
                   C(0, 1), C(0, 2), C(1, 1), C(1, 2), C(2, 2), s.seconds);
  }
  write_text_file_atomically(path, text);
}

Pose2 to_pose2(const SE2d& T) {
  return Pose2(T.translation().x(), T.translation().y(), T.angle());
}

const OccupancyGrid* first_grid(const MultiMetricMap& map) {
  for (const auto& e : map.entries()) {
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) return &g->grid();
  }
  return nullptr;
}

PfLocalizationRunOptions run_options(const PfLocalizationCliOptions& o,
                                     const PfLocalizationConfig& cfg) {
  PfLocalizationRunOptions ro;
  ro.seed = o.seed;
  ro.num_threads = resolve_thread_count(o.threads, "--threads");
  ro.max_steps = o.max_steps;
  ro.snapshot_every = o.snapshot_every;
  ParticleInit init = cfg.options.init;
  if (o.particles) init.count = *o.particles;
  if (o.global) init.mode = ParticleInitMode::FreeSpace;
  if (!o.init_std.empty() && o.init_pose.empty()) {
    throw ParseError({"--init-std", std::nullopt, std::nullopt, "--init-std"},
                     "--init-std needs --init-pose");
  }
  if (!o.init_pose.empty()) init = init_around_pose(o.init_pose, o.init_std, init);
  if (o.particles || o.global || !o.init_pose.empty()) ro.init = init;
  if (!o.recovery.empty()) ro.recovery = parse_recovery(o.recovery);
  return ro;
}

struct Written {
  std::vector<std::string> files;
  std::string picture;
};

Written write_outputs(const fs::path& dir, const PfLocalizationResult& res) {
  Written w;
  std::vector<TimedPose2> est, odo;
  std::vector<Pose2> path, truth;
  for (const auto& s : res.steps) {
    est.push_back({s.time, to_pose2(s.estimate.mean)});
    odo.push_back({s.time, s.odometry});
    path.push_back(to_pose2(s.estimate.mean));
    if (s.ground_truth) truth.push_back(*s.ground_truth);
  }
  const auto add = [&](const fs::path& p) { w.files.push_back(p.string()); };
  write_tum_trajectory((dir / "path.tum").string(), est);
  add(dir / "path.tum");
  write_tum_trajectory((dir / "odometry.tum").string(), odo);
  add(dir / "odometry.tum");
  write_steps(dir / "steps.txt", res);
  add(dir / "steps.txt");
  for (const auto& s : res.snapshots) {
    write_particles(dir / snapshot_name(s), s.particles);
    add(dir / snapshot_name(s));
  }
  if (const OccupancyGrid* grid = first_grid(*res.map)) {
    const fs::path png = dir / "map.png";
    render_localization_png(png.string(), *grid, res.snapshots.back().particles.states, path, truth);
    add(png);
    w.picture = png.string();
  }
  return w;
}

std::string summary_json(const PfLocalizationCliOptions& o, const std::string& config,
                         const std::string& rawlog, const PfLocalizationResult& res,
                         const std::vector<Issue>& issues, const Written& w, double total) {
  const std::size_t n = res.steps.size();
  double max_step = 0.0;
  for (const auto& s : res.steps) max_step = std::max(max_step, s.seconds);
  const PfLocalizationStep& last = res.steps.back();
  JsonWriter j;
  j.begin_object();
  j.key("config").value(config);
  j.key("rawlog").value(rawlog);
  j.key("format").value(to_string(res.format));
  j.key("map_kind").value(res.map_info.kind);
  j.key("map_file").value(res.map_info.file);
  j.key("seed").value(o.seed);
  j.key("threads").value(res.options.num_threads);
  j.key("steps").value(n);
  j.key("initial_particles").value(res.snapshots.front().particles.size());
  j.key("peak_particles").value(res.peak_particles);
  j.key("final_particles").value(last.particles);
  j.key("termination").value(to_string(res.termination));
  j.key("converged").value(res.ok());
  j.key("converged_step");
  if (res.converged_step) j.value(*res.converged_step); else j.null();
  j.key("first_converged_step");
  if (res.first_converged_step) j.value(*res.first_converged_step); else j.null();
  j.key("message").value(res.message);
  j.key("final_pose").begin_object();
  j.key("x").value(last.estimate.mean.translation().x());
  j.key("y").value(last.estimate.mean.translation().y());
  j.key("phi").value(last.estimate.mean.angle()).end_object();
  j.key("final_position_std").value(last.estimate.position_std);
  j.key("final_heading_std").value(last.estimate.heading_std);
  j.key("ground_truth_rmse");
  if (res.ground_truth_rmse) j.value(*res.ground_truth_rmse); else j.null();
  j.key("filter_seconds").value(res.filter_seconds);
  j.key("seconds_per_step_mean").value(n ? res.filter_seconds / static_cast<double>(n) : 0.0);
  j.key("seconds_per_step_max").value(max_step);
  j.key("map_seconds").value(res.map_seconds);
  j.key("read_seconds").value(res.read_seconds);
  j.key("total_seconds").value(total);
  j.key("files").value(w.files);
  write_issues(j, issues);
  j.end_object();
  return j.str() + "\n";
}

void print_text(const std::string& config, const std::string& rawlog,
                const PfLocalizationResult& res, const std::vector<Issue>& issues,
                const Written& w, const std::string& out_dir, double total) {
  const std::size_t n = res.steps.size();
  const PfLocalizationStep& last = res.steps.back();
  fmt::print("pf-localization: {} steps from {} ({})\n", n, printable(rawlog), to_string(res.format));
  fmt::print("  config: {}\n", printable(config));
  fmt::print("  map: {} {}{}\n", res.map_info.kind, printable(res.map_info.file),
             res.map_info.grid_size_x
                 ? fmt::format(" (grid {} x {} cells of {:g} m)", res.map_info.grid_size_x,
                               res.map_info.grid_size_y, res.map_info.grid_resolution)
                 : std::string());
  fmt::print("  particles: {} initial, {} peak, {} final\n", res.snapshots.front().particles.size(),
             res.peak_particles, last.particles);
  fmt::print("  result: {}\n", res.message);
  fmt::print("  final pose: {} (position std {:.3f} m, heading std {:.2f} deg)\n",
             to_pose2(last.estimate.mean).as_string(), last.estimate.position_std,
             last.estimate.heading_std / kDeg);
  if (res.ground_truth_rmse) fmt::print("  ground truth: position RMSE {:.3f} m\n", *res.ground_truth_rmse);
  fmt::print("  time: filter {:.3f} s ({:.3f} ms/step), map {:.3f} s, reading {:.3f} s, total "
             "{:.3f} s\n",
             res.filter_seconds, n ? 1e3 * res.filter_seconds / static_cast<double>(n) : 0.0,
             res.map_seconds, res.read_seconds, total);
  fmt::print("  wrote {} files to {}/{}\n", w.files.size(), printable(out_dir),
             w.picture.empty() ? std::string() : fmt::format(" (picture: {})", printable(w.picture)));
  if (issues.empty()) {
    fmt::print("  issues: none\n");
  } else {
    fmt::print("  issues:\n");
    for (const auto& i : issues) fmt::print("    {}: {}\n", i.code, i.message);
  }
}

void run(PfLocalizationCliOptions o) {
  Stopwatch total;
  if (o.config.empty()) {
    const fs::path data = data_dir();
    o.config = (data / kDemoConfig).string();
    if (o.map.empty()) o.map = (data / kDemoMap).string();
    if (o.rawlog.empty()) o.rawlog = (data / kDemoRawlog).string();
  }
  check_regular_input(o.config, "pf-localization config file");
  const IniFile ini = IniFile::load(o.config);
  PfLocalizationConfig cfg = load_pf_localization_config(ini);
  if (!o.map.empty()) cfg.map_file = o.map;
  const std::string rawlog = rawlog_to_read(o.rawlog, o.config, cfg, "LocalizationExperiment");
  check_regular_input(rawlog, "rawlog");
  PfLocalizationRunOptions ro = run_options(o, cfg);

  const fs::path dir = output_folder(o.out_dir);
  std::vector<fs::path> inputs{fs::path(o.config), fs::path(rawlog)};
  if (!cfg.map_file.empty()) inputs.emplace_back(cfg.resolve(cfg.map_file, "map_file"));
  if (!cfg.ground_truth_file.empty()) {
    inputs.emplace_back(cfg.resolve(cfg.ground_truth_file, "ground_truth_path_file"));
  }
  const std::vector<fs::path> fixed{dir / "path.tum", dir / "odometry.tum", dir / "steps.txt",
                                    dir / "map.png", dir / "summary.json"};
  check_outputs_distinct(inputs, fixed);
  const PfLocalizationResult res = run_with_progress(
      o.progress, "pf-localization " + printable(rawlog), o.out_dir,
      [&](const std::function<void()>& step) {
        ro.on_step = [&](const PfLocalizationStep&) { step(); };
        return run_pf_localization(std::move(cfg), rawlog, ro);
      });
  const std::vector<Issue> issues = to_issues(res.issues);
  std::vector<fs::path> outputs = fixed;
  for (const auto& s : res.snapshots) outputs.push_back(dir / snapshot_name(s));
  check_outputs_distinct(inputs, outputs);
  create_output_folder(dir);
  Written w = write_outputs(dir, res);
  publish_summary(
      dir, w.files, o.json, [&] { return summary_json(o, o.config, rawlog, res, issues, w, total.elapsed()); },
      [&] { print_text(o.config, rawlog, res, issues, w, o.out_dir, total.elapsed()); }, issues);
}

}  // namespace

void add_pf_localization_command(CLI::App& app) {
  auto o = std::make_shared<PfLocalizationCliOptions>();
  auto* cmd = app.add_subcommand(
      "pf-localization",
      "Localize a robot in a known map with a particle filter (Monte-Carlo localization), from an "
      "MRPT pf-localization config and a rawlog; without arguments, the bundled demo");
  cmd->add_option("config", o->config,
                  "MRPT pf-localization configuration file (.ini), e.g. localization_demo.ini");
  cmd->add_option("rawlog", o->rawlog, "rawlog (default: the config's rawlog_file)");
  cmd->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  cmd->add_option("--map", o->map,
                  "map file replacing the config's map_file (.simplemap, .gridmap, ROS .yaml)");
  add_seed_and_threads(cmd, o->seed, o->threads);
  cmd->add_option("--particles", o->particles,
                  "initial particle count (default: the config's particles_count)")
      ->check(CLI::Range(1u, 100000000u));
  cmd->add_flag("--global", o->global,
                "global localization: particles uniform over the whole free space of the grid");
  cmd->add_option("--init-pose", o->init_pose,
                  "start the particles around a pose: x,y,yaw (m, degrees; or MRPT's [x y yaw])");
  cmd->add_option("--init-std", o->init_std,
                  "their standard deviations with --init-pose: std_xy,std_yaw_deg")
      ->default_str("0.5,11.46");
  cmd->add_option("--recovery", o->recovery,
                  "augmented MCL for kidnappings: alpha_slow,alpha_fast (e.g. 0.001,0.1; default: "
                  "the config's recovery_alpha_*, off in MRPT's files)");
  cmd->add_option("--max-steps", o->max_steps, "process at most this many steps (default: all)");
  cmd->add_option("--snapshot-every", o->snapshot_every,
                  "also write the particles every N steps (0: initial, converged and final only)")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("!--no-progress", o->progress, "do not report progress on stderr");
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
