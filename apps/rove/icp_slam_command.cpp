#include <fmt/format.h>

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
#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/core/progress.h"
#include "rove/core/timer.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_points.h"
#include "rove/slam/icp_slam.h"
#include "rove/slam/icp_slam_run.h"
#include "rove/slam/map_export.h"
#include "rove/slam/mrpt_simplemap_writer.h"

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
};

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

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

void run(IcpSlamCliOptions o) {
  Stopwatch total;
  const bool demo = o.config.empty();
  if (demo) {
    const fs::path data = data_dir();
    o.config = (data / kDemoConfig).string();
    if (o.rawlog.empty()) o.rawlog = (data / kDemoRawlog).string();
  }
  const IniFile ini = IniFile::load(o.config);
  IcpSlamConfig cfg = load_icp_slam_config(ini);
  const std::string rawlog = resolve_rawlog(o, cfg);

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) throw IoError(o.out_dir, "cannot create the output folder: " + ec.message());

  IcpSlam slam(cfg.options, std::move(cfg.map));
  IcpSlamRunOptions ro;
  ro.rawlog_offset = cfg.rawlog_offset;
  ro.max_steps = o.max_steps;
  std::optional<Progress> progress;
  if (o.progress) progress.emplace(std::nullopt, "icp-slam " + rawlog, std::cerr);
  if (progress) ro.on_step = [&](const IcpSlamStep&) { progress->advance(); };
  const IcpSlamRunResult res = run_icp_slam(slam, rawlog, ro);
  if (progress) progress->finish();

  // Outputs.
  const fs::path dir(o.out_dir);
  std::vector<std::string> files;
  std::vector<TimedPose2> est, odo;
  std::vector<Pose2> path;
  for (const auto& s : res.steps) {
    est.push_back({s.time, s.pose});
    odo.push_back({s.time, s.odometry});
    path.push_back(s.pose);
  }
  write_tum_trajectory((dir / "path.tum").string(), est);
  write_tum_trajectory((dir / "odometry.tum").string(), odo);
  files.push_back((dir / "path.tum").string());
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

  std::size_t grids = 0, clouds = 0, points = 0;
  std::string picture;
  for (const auto& e : slam.map().entries()) {
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
      const std::string stem = grids == 0 ? "map" : fmt::format("map_{:02}", grids);
      const GridMapFiles gf = write_grid_map((dir / stem).string(), g->grid());
      files.push_back(gf.image);
      files.push_back(gf.yaml);
      if (picture.empty()) picture = gf.image;
      ++grids;
    } else if (const auto* p = dynamic_cast<const PointsMetricMap*>(e.map.get())) {
      const std::string stem = clouds == 0 ? "points" : fmt::format("points_{:02}", clouds);
      write_ply((dir / (stem + ".ply")).string(), p->points().cloud());
      render_points_png((dir / (stem + ".png")).string(), p->points().cloud(), path);
      files.push_back((dir / (stem + ".ply")).string());
      files.push_back((dir / (stem + ".png")).string());
      if (clouds == 0) points = p->points().cloud().size();
      if (picture.empty() && grids == 0) picture = (dir / (stem + ".png")).string();
      ++clouds;
    }
  }

  const IcpSlamStats& st = slam.stats();
  const std::size_t n = res.steps.size();
  double max_step = 0.0;
  for (const auto& s : res.steps) max_step = std::max(max_step, s.seconds);
  const double mean_step = n ? res.mapping_seconds / static_cast<double>(n) : 0.0;
  const Pose2 final_pose = slam.pose();
  const double iters_per_icp =
      st.icp_runs ? static_cast<double>(st.icp_iterations) / static_cast<double>(st.icp_runs) : 0.0;

  std::string summary = fmt::format(
      "{{\n  \"config\": {},\n  \"rawlog\": {},\n  \"format\": \"{}\",\n  \"steps\": {},\n"
      "  \"observations\": {},\n  \"odometry_readings\": {},\n  \"icp_runs\": {},\n"
      "  \"icp_accepted\": {},\n  \"icp_iterations\": {},\n  \"icp_iterations_per_run\": {:.2f},\n"
      "  \"keyframes\": {},\n  \"map_points\": {},\n  \"grid_maps\": {},\n"
      "  \"final_pose\": {{\"x\": {:.6f}, \"y\": {:.6f}, \"phi\": {:.6f}}},\n"
      "  \"mapping_seconds\": {:.6f},\n  \"icp_seconds\": {:.6f},\n  \"insert_seconds\": {:.6f},\n"
      "  \"read_seconds\": {:.6f},\n  \"seconds_per_step_mean\": {:.6f},\n"
      "  \"seconds_per_step_max\": {:.6f},\n  \"total_seconds\": {:.6f},\n  \"files\": [",
      json_string(o.config), json_string(rawlog), to_string(res.format), n, st.observations,
      st.odometry, st.icp_runs, st.icp_accepted, st.icp_iterations, iters_per_icp, st.insertions,
      points, grids, final_pose.x(), final_pose.y(), final_pose.phi(), res.mapping_seconds,
      st.icp_seconds, st.insert_seconds, res.read_seconds, mean_step, max_step, total.elapsed());
  for (std::size_t i = 0; i < files.size(); ++i) {
    summary += (i ? ", " : "") + json_string(files[i]);
  }
  summary += "]\n}\n";
  {
    std::ofstream f(dir / "summary.json");
    f << summary;
    if (!f) throw IoError((dir / "summary.json").string(), "write failed");
  }

  if (o.json) {
    fmt::print("{}", summary);
    return;
  }
  fmt::print("icp-slam: {} steps from {} ({})\n", n, rawlog, to_string(res.format));
  fmt::print("  config: {}\n", o.config);
  fmt::print("  ICP: {} runs, {} accepted, {} iterations ({:.1f} per run)\n", st.icp_runs,
             st.icp_accepted, st.icp_iterations, iters_per_icp);
  fmt::print("  map: {} keyframes, {} points{}\n", st.insertions, points,
             grids ? fmt::format(", {} grid map(s)", grids) : std::string());
  if (smr.skipped) fmt::print("  simplemap: {} keyframes not written (not 2D scans)\n", smr.skipped);
  fmt::print("  final pose: {}\n", final_pose.as_string());
  fmt::print("  time: mapping {:.3f} s ({:.3f} ms/step, max {:.3f} ms), reading {:.3f} s, "
             "total {:.3f} s\n",
             res.mapping_seconds, 1e3 * mean_step, 1e3 * max_step, res.read_seconds,
             total.elapsed());
  fmt::print("  wrote {} files to {}/ (map picture: {})\n", files.size() + 1, o.out_dir, picture);
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
  cmd->add_option("-o,--output", o->out_dir, "output folder (default: icp-slam-out)");
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("!--no-progress", o->progress, "do not report progress on stderr");
  cmd->add_option("--max-steps", o->max_steps, "process at most this many steps");
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
