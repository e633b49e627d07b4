#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "data_dir.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/progress.h"
#include "rove/core/timer.h"
#include "rove/io/grid_image.h"
#include "rove/io/mrpt_simplemap_writer.h"
#include "rove/io/ply.h"
#include "rove/io/tum_trajectory.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_points.h"
#include "rove/slam/icp_slam.h"
#include "rove/slam/icp_slam_run.h"
#include "rove/slam/map_export.h"

namespace rove::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDemoConfig = "mrpt/icp-slam_demo_classic.ini";
constexpr const char* kDemoRawlog = "mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";

struct IcpSlamCliOptions {
  std::string config;
  std::string rawlog;
  std::string out_dir = "icp-slam-out";
  bool json = false;
  bool progress = true;
  std::optional<std::uint64_t> max_steps;
  std::optional<float> max_range;
  std::string arithmetic;  // empty: the config's [ICP] arithmetic (default double)
};

// The rawlog: the command line's, else the config's rawlog_file as given,
// else relative to the config file's folder.
std::string resolve_rawlog(const IcpSlamCliOptions& o, const IcpSlamConfig& cfg) {
  if (!o.rawlog.empty()) return o.rawlog;
  if (cfg.rawlog_file.empty()) {
    throw ConfigError(o.config, "MappingApplication", "rawlog_file",
                      "no rawlog given on the command line and none in the config file");
  }
  if (fs::exists(cfg.rawlog_file)) return cfg.rawlog_file;
  const fs::path beside = fs::path(o.config).parent_path() / cfg.rawlog_file;
  if (fs::exists(beside)) return beside.string();
  throw ConfigError(o.config, "MappingApplication", "rawlog_file",
                    fmt::format("'{}' does not exist (also tried '{}'); give the rawlog on the "
                                "command line",
                                cfg.rawlog_file, beside.string()));
}

// The files a run writes into the output folder, known before it starts (the
// map declarations name them), so that none can be an input.
struct OutputPlan {
  std::vector<fs::path> files;
};

OutputPlan plan_outputs(const fs::path& dir, const MultiMetricMap& map) {
  OutputPlan p;
  for (const char* name : {"path.tum", "odometry.tum", "keyframes.tum", "map.simplemap",
                           "summary.json"}) {
    p.files.push_back(dir / name);
  }
  std::size_t grids = 0, clouds = 0;
  for (const auto& e : map.entries()) {
    if (dynamic_cast<const OccupancyGridMetricMap*>(e.map.get()) != nullptr) {
      const std::string stem = grids == 0 ? "map" : fmt::format("map_{:02}", grids);
      p.files.push_back(dir / (stem + ".png"));
      p.files.push_back(dir / (stem + ".yaml"));
      ++grids;
    } else if (dynamic_cast<const PointsMetricMap*>(e.map.get()) != nullptr) {
      const std::string stem = clouds == 0 ? "points" : fmt::format("points_{:02}", clouds);
      p.files.push_back(dir / (stem + ".ply"));
      p.files.push_back(dir / (stem + ".png"));
      ++clouds;
    }
  }
  return p;
}

// What the text report and summary.json say about a finished run.
struct RunFacts {
  std::string config, rawlog;
  RawlogFormat format = RawlogFormat::Rove;
  float max_range = 0;
  std::string max_range_source = "default";
  Arithmetic arithmetic = Arithmetic::Double;
  std::string arithmetic_source = "default";
  std::size_t steps = 0, scans = 0;
  double mapping_seconds = 0, read_seconds = 0, max_step_seconds = 0;
  std::size_t grids = 0, points = 0;
  std::string picture;
  // The keyframes' 2D scans against each other (scan_consistency.h), and
  // the replay grid's cell side (0: the scans spread too far to check).
  std::size_t keyframes_checked = 0, keyframes_contradicted = 0;
  double consistency_resolution = 0.0;
};

// The maps into dir: each grid as a ROS map pair, each point map as PLY and
// a picture with the path.
void write_maps(const fs::path& dir, const IcpSlam& slam, const std::vector<Pose2>& path,
                std::vector<std::string>& files, RunFacts& facts) {
  std::size_t clouds = 0;
  for (const auto& e : slam.map().entries()) {
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
      const std::string stem = facts.grids == 0 ? "map" : fmt::format("map_{:02}", facts.grids);
      GridImageOptions scale;  // the whole probability, as MRPT's bitmap
      scale.mode = RosMapMode::Scale;
      const RosMapFiles gf = save_ros_map((dir / stem).string(), g->grid(), scale);
      files.push_back(gf.image);
      files.push_back(gf.yaml);
      if (facts.picture.empty()) facts.picture = gf.image;
      ++facts.grids;
    } else if (const auto* p = dynamic_cast<const PointsMetricMap*>(e.map.get())) {
      const std::string stem = clouds == 0 ? "points" : fmt::format("points_{:02}", clouds);
      PlyWriteOptions ascii;
      ascii.format = PlyFormat::Ascii;
      write_ply((dir / (stem + ".ply")).string(), p->points().cloud(), ascii);
      files.push_back((dir / (stem + ".ply")).string());
      render_points_png((dir / (stem + ".png")).string(), p->points().cloud(), path);
      files.push_back((dir / (stem + ".png")).string());
      if (clouds == 0) facts.points = p->points().cloud().size();
      if (facts.picture.empty() && facts.grids == 0) facts.picture = (dir / (stem + ".png")).string();
      ++clouds;
    }
  }
}

// The paths and the keyframes (TUM trajectories, MRPT simplemap) into dir.
void write_trajectories(const fs::path& dir, const IcpSlam& slam, const IcpSlamRunResult& res,
                        std::vector<std::string>& files, std::vector<Issue>& issues) {
  std::vector<TimedPose2> est, odo;
  for (const auto& s : res.steps) {
    est.push_back({s.time, s.pose});
    odo.push_back({s.time, s.odometry});
  }
  write_tum_trajectory((dir / "path.tum").string(), est);
  files.push_back((dir / "path.tum").string());
  write_tum_trajectory((dir / "odometry.tum").string(), odo);
  files.push_back((dir / "odometry.tum").string());
  std::vector<TimedPose2> kf_poses;
  std::vector<SimpleMapEntry2D> kf;
  for (const auto& k : slam.keyframes()) {
    kf_poses.push_back({k.observation->timestamp, k.pose});
    kf.push_back({k.pose, Eigen::Matrix3d::Zero(), k.observation.get()});
  }
  write_tum_trajectory((dir / "keyframes.tum").string(), kf_poses);
  files.push_back((dir / "keyframes.tum").string());
  const SimpleMapWriteReport smr = write_mrpt_simplemap((dir / "map.simplemap").string(), kf);
  files.push_back((dir / "map.simplemap").string());
  if (smr.skipped) {
    issues.push_back({"simplemap-incomplete",
                      fmt::format("{} keyframes not written to map.simplemap (not 2D scans)",
                                  smr.skipped)});
  }
}

double mean_step_seconds(const RunFacts& f) {
  return f.steps ? f.mapping_seconds / static_cast<double>(f.steps) : 0.0;
}

double iterations_per_icp(const IcpSlamStats& st) {
  return st.icp_runs ? static_cast<double>(st.icp_iterations) / static_cast<double>(st.icp_runs)
                     : 0.0;
}

std::string summary_json(const RunFacts& f, const IcpSlam& slam, const std::vector<std::string>& files,
                         const std::vector<Issue>& issues, double total_seconds) {
  const IcpSlamStats& st = slam.stats();
  const Pose2 final_pose = slam.pose();
  JsonWriter j;
  j.begin_object();
  j.key("config").value(f.config);
  j.key("rawlog").value(f.rawlog);
  j.key("format").value(to_string(f.format));
  j.key("arithmetic").value(std::string(to_string(f.arithmetic)));
  j.key("arithmetic_source").value(f.arithmetic_source);
  if (f.format == RawlogFormat::Carmen) {
    j.key("carmen_max_range").value(static_cast<double>(f.max_range));
    j.key("carmen_max_range_source").value(f.max_range_source);
  }
  j.key("steps").value(f.steps);
  j.key("observations").value(st.observations);
  j.key("scans").value(f.scans);
  j.key("odometry_readings").value(st.odometry);
  j.key("icp_runs").value(st.icp_runs);
  j.key("icp_accepted").value(st.icp_accepted);
  j.key("icp_rejected_goodness").value(st.icp_rejected_goodness);
  j.key("icp_rejected_diverged").value(st.icp_rejected_invalid);
  j.key("icp_goodness_max").value(st.icp_goodness_max);
  j.key("min_icp_goodness_to_accept").value(slam.options().min_icp_goodness_to_accept);
  j.key("icp_iterations").value(st.icp_iterations);
  j.key("icp_iterations_per_run").value(iterations_per_icp(st));
  j.key("keyframes").value(st.insertions);
  j.key("keyframes_checked").value(f.keyframes_checked);
  j.key("keyframes_contradicted").value(f.keyframes_contradicted);
  j.key("consistency_resolution").value(f.consistency_resolution);
  j.key("map_points").value(f.points);
  j.key("grid_maps").value(f.grids);
  j.key("final_pose").begin_object();
  j.key("x").value(final_pose.x()).key("y").value(final_pose.y());
  j.key("phi").value(final_pose.phi()).end_object();
  j.key("mapping_seconds").value(f.mapping_seconds);
  j.key("icp_seconds").value(st.icp_seconds);
  j.key("insert_seconds").value(st.insert_seconds);
  j.key("read_seconds").value(f.read_seconds);
  j.key("seconds_per_step_mean").value(mean_step_seconds(f));
  j.key("seconds_per_step_max").value(f.max_step_seconds);
  j.key("total_seconds").value(total_seconds);
  j.key("files").value(files);
  write_issues(j, issues);
  j.end_object();
  return j.str() + "\n";
}

void print_report(const RunFacts& f, const IcpSlam& slam, const std::string& out_dir,
                  const std::vector<std::string>& files, const std::vector<Issue>& issues,
                  double total_seconds) {
  const IcpSlamStats& st = slam.stats();
  fmt::print("icp-slam: {} steps from {} ({})\n", f.steps, printable(f.rawlog), to_string(f.format));
  fmt::print("  config: {}\n", printable(f.config));
  fmt::print("  arithmetic: {} ({}; {})\n", to_string(f.arithmetic), f.arithmetic_source,
             f.arithmetic == Arithmetic::Mrpt ? "MRPT 2.5.8's icp-slam reproduced to the bit"
                                              : "rove's double precision");
  if (f.format == RawlogFormat::Carmen) {
    fmt::print("  CARMEN maximum range: {:g} m ({}; PARAM lines of the log take precedence)\n",
               f.max_range, f.max_range_source);
  }
  fmt::print("  ICP: {} runs, {} accepted, {} rejected (goodness <= {:g}), {} diverged; "
             "{} iterations ({:.1f} per run)\n",
             st.icp_runs, st.icp_accepted, st.icp_rejected_goodness,
             slam.options().min_icp_goodness_to_accept, st.icp_rejected_invalid,
             st.icp_iterations, iterations_per_icp(st));
  fmt::print("  map: {} keyframes, {} points{}\n", st.insertions, f.points,
             f.grids ? fmt::format(", {} grid map(s)", f.grids) : std::string());
  if (f.keyframes_checked > 0) {
    fmt::print("  keyframes against each other: {} of {} with more than {:.0f} % of the rays through walls "
               "({:g} m cells)\n",
               f.keyframes_contradicted, f.keyframes_checked, 100.0 * kContradictedRays,
               f.consistency_resolution);
  } else if (f.consistency_resolution == 0.0 && st.insertions > 1) {
    fmt::print("  keyframes against each other: not checked (their scans span more than {} tiles of "
               "32 cells even at 8x the 5 cm cells)\n",
               kMaxReplayTiles);
  }
  fmt::print("  final pose: {}\n", slam.pose().as_string());
  fmt::print("  time: mapping {:.3f} s ({:.3f} ms/step, max {:.3f} ms), reading {:.3f} s, "
             "total {:.3f} s\n",
             f.mapping_seconds, 1e3 * mean_step_seconds(f), 1e3 * f.max_step_seconds,
             f.read_seconds, total_seconds);
  fmt::print("  wrote {} files to {}/ (map picture: {})\n", files.size(), printable(out_dir),
             printable(f.picture));
  if (issues.empty()) {
    fmt::print("  issues: none\n");
  } else {
    fmt::print("  issues:\n");
    for (const auto& i : issues) fmt::print("    {}: {}\n", i.code, i.message);
  }
}

// Runs ICP-SLAM over the rawlog with a progress line; Ctrl-C says what was
// (not) written and is passed on.
IcpSlamRunResult run_with_progress(IcpSlam& slam, const std::string& rawlog,
                                   IcpSlamRunOptions ro, const IcpSlamCliOptions& o) {
  std::optional<Progress> progress;
  if (o.progress) progress.emplace(std::nullopt, "icp-slam " + printable(rawlog), std::cerr);
  std::uint64_t steps_done = 0;
  ro.on_step = [&](const IcpSlamStep&) {
    ++steps_done;
    if (progress) progress->advance();
  };
  try {
    IcpSlamRunResult res = run_icp_slam(slam, rawlog, ro);
    if (progress) progress->finish();
    return res;
  } catch (const Interrupted&) {
    if (progress) progress->finish();
    fmt::print(stderr, "rove: interrupted after {} steps; nothing written to {}\n", steps_done,
               printable(o.out_dir));
    throw;
  }
}

void run(IcpSlamCliOptions o) {
  Stopwatch total;
  if (o.config.empty()) {  // the demo
    const fs::path data = data_dir();
    o.config = (data / kDemoConfig).string();
    if (o.rawlog.empty()) o.rawlog = (data / kDemoRawlog).string();
  }
  check_regular_input(o.config, "icp-slam config file");
  const IniFile ini = IniFile::load(o.config);
  IcpSlamConfig cfg = load_icp_slam_config(ini);
  RunFacts facts;
  facts.config = o.config;
  if (ini.has("ICP", "arithmetic")) facts.arithmetic_source = "[ICP] arithmetic";
  if (!o.arithmetic.empty()) {
    cfg.options.icp.arithmetic = o.arithmetic == "mrpt" ? Arithmetic::Mrpt : Arithmetic::Double;
    facts.arithmetic_source = "--arithmetic";
  }
  facts.arithmetic = cfg.options.icp.arithmetic;
  facts.rawlog = resolve_rawlog(o, cfg);
  check_regular_input(facts.rawlog, "rawlog");

  const fs::path dir(o.out_dir);
  const OutputPlan plan = plan_outputs(dir, cfg.map);
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw IoError(o.out_dir, "the output folder (-o) exists and is not a folder");
  }
  check_outputs_distinct({fs::path(o.config), fs::path(facts.rawlog)}, plan.files);

  IcpSlam slam(cfg.options, std::move(cfg.map));
  IcpSlamRunOptions ro;
  ro.rawlog_offset = cfg.rawlog_offset;
  ro.max_steps = o.max_steps;
  facts.max_range = ro.reader.carmen.log.flaser_max_range;
  if (cfg.carmen_max_range) {
    facts.max_range = *cfg.carmen_max_range;
    facts.max_range_source = "[CARMEN] maxRange";
  }
  if (o.max_range) {
    facts.max_range = *o.max_range;
    facts.max_range_source = "--max-range";
  }
  ro.reader.carmen.log.flaser_max_range = facts.max_range;
  const IcpSlamRunResult res = run_with_progress(slam, facts.rawlog, ro, o);
  facts.format = res.format;
  facts.steps = res.steps.size();
  facts.scans = res.scans;
  facts.mapping_seconds = res.mapping_seconds;
  facts.keyframes_checked = res.consistency.checked;
  facts.keyframes_contradicted = res.consistency.contradicted;
  facts.consistency_resolution = res.consistency.resolution;
  facts.read_seconds = res.read_seconds;
  for (const auto& s : res.steps) facts.max_step_seconds = std::max(facts.max_step_seconds, s.seconds);

  std::vector<Issue> issues;
  for (const auto& i : res.issues) issues.push_back({i.code, i.message});
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) throw IoError(o.out_dir, "cannot create the output folder: " + ec.message());

  // Outputs, each written under a temporary name and renamed when complete.
  std::vector<std::string> files;
  std::vector<Pose2> path;
  for (const auto& s : res.steps) path.push_back(s.pose);
  try {
    write_trajectories(dir, slam, res, files, issues);
    write_maps(dir, slam, path, files, facts);
    const std::string summary_path = (dir / "summary.json").string();
    files.push_back(summary_path);
    const std::string summary = summary_json(facts, slam, files, issues, total.elapsed());
    write_text_file_atomically(summary_path, summary);
    if (o.json) {
      fmt::print("{}", summary);
    } else {
      print_report(facts, slam, o.out_dir, files, issues, total.elapsed());
    }
  } catch (const Interrupted&) {
    fmt::print(stderr, "rove: interrupted while writing; complete files: {}\n",
               files.empty() ? std::string("none") : printable(fmt::format("{}", fmt::join(files, ", "))));
    throw;
  }
  finish(issues);
}

}  // namespace

void add_icp_slam_command(CLI::App& app) {
  auto o = std::make_shared<IcpSlamCliOptions>();
  auto* cmd = app.add_subcommand(
      "icp-slam",
      "Build a map with ICP-SLAM from an MRPT icp-slam config and a rawlog (MRPT, rove or "
      "CARMEN); without arguments, the bundled demo (Telecom Faculty loop)");
  cmd->add_option("config", o->config, "MRPT icp-slam configuration file (.ini)");
  cmd->add_option("rawlog", o->rawlog, "rawlog (default: the config's rawlog_file)");
  cmd->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("!--no-progress", o->progress, "do not report progress on stderr");
  cmd->add_option("--max-steps", o->max_steps, "process at most this many steps (default: all)");
  cmd->add_option("--max-range", o->max_range,
                  "CARMEN logs: maximum range of FLASER/RLASER scans, meters, when the log has no "
                  "PARAM line stating it; readings at or above it are \"no return\" (default: "
                  "the config's [CARMEN] maxRange, else 81)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--arithmetic", o->arithmetic,
                  "double (rove's double precision) or mrpt (MRPT 2.5.8's arithmetic to the bit: "
                  "reproduces MRPT's icp-slam path and map exactly, given MRPT's config); "
                  "default: the config's [ICP] arithmetic, else double")
      ->check(CLI::IsMember({"double", "mrpt"}));
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
