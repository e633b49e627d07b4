// `rove nav run`: a global path, then the local planner driving it in the
// simulator; the log, the paths, the clearances and pictures.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli_values.h"
#include "grid_input.h"
#include "nav_commands.h"
#include "nav_picture.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/json.h"
#include "rove/io/rove_rawlog.h"
#include "rove/io/tum_trajectory.h"
#include "rove/nav/navigation_run.h"
#include "rove/nav/navigation_run_config.h"

namespace rove::cli {

namespace {

namespace fs = std::filesystem;

struct NavRunArgs {
  std::string map, start, goal, config, out_dir;
  std::string planner = "teb";
  double robot_radius = 0.3;
  double max_v = 0.8;
  double max_w_deg = 60;
  double max_time = 0;
  float occupancy_threshold = 0.5f;
  std::uint64_t seed = 1;
  int frames = 8;
  bool json = false;
};

SE2d to_se2(const Pose2& p) { return SE2d(p.x(), p.y(), p.phi()); }

// Items of a position or pose: separated by commas, or by spaces in MRPT's
// bracketed form.
int item_count(const std::string& text) {
  int items = 0;
  bool in_item = false;
  for (const char c : text) {
    const bool separator = c == ',' || c == ' ' || c == '[' || c == ']';
    if (!separator && !in_item) ++items;
    in_item = !separator;
  }
  return items;
}

// The run's options from the command line, then the config's sections.
NavigationRunOptions run_options(const NavRunArgs& a, std::vector<std::string>& notes) {
  NavigationRobot robot;
  robot.planner = a.planner == "reactive" ? LocalPlannerKind::Reactive : LocalPlannerKind::Teb;
  robot.radius = a.robot_radius;
  robot.max_v = a.max_v;
  robot.max_omega = a.max_w_deg * std::numbers::pi / 180;
  std::optional<IniFile> ini;
  if (!a.config.empty()) ini = IniFile::load(a.config);
  NavigationRunConfig c = navigation_run_config(robot, ini ? &*ini : nullptr, a.config);
  c.options.simulator.seed = a.seed;
  c.options.max_time = a.max_time;
  notes = std::move(c.notes);
  return c.options;
}

void write_driven(const std::string& path, const NavigationRunResult& r, double dt) {
  std::vector<TimedPose2> tum;
  for (std::size_t i = 0; i < r.driven.size(); ++i) {
    const SE2d& p = r.driven[i];
    tum.push_back({Timestamp::from_seconds(static_cast<double>(i) * dt),
                   Pose2(p.translation().x(), p.translation().y(), p.angle())});
  }
  write_tum_trajectory(path, tum);
}

void write_planned(const std::string& path, const GridPath& g) {
  std::vector<TimedPose2> tum;
  double along = 0;
  for (std::size_t i = 0; i < g.poses.size(); ++i) {
    if (i > 0) along += (g.poses[i].translation() - g.poses[i - 1].translation()).norm();
    const SE2d& p = g.poses[i];
    tum.push_back({Timestamp::from_seconds(along), Pose2(p.translation().x(), p.translation().y(), p.angle())});
  }
  write_tum_trajectory(path, tum);
}

// Per cycle: time, pose, clearance (robot edge to the nearest obstacle).
void write_clearances(const std::string& path, const NavigationRunResult& r, const NavigationGrid& world,
                      double radius, double dt) {
  const std::vector<double> clearances = driven_clearances(r, world, radius);
  std::string text = "# t x y yaw clearance (s, m, m, rad, m)\n";
  for (std::size_t i = 0; i < r.driven.size(); ++i) {
    const SE2d& p = r.driven[i];
    text += fmt::format("{:.3f} {:.4f} {:.4f} {:.5f} {:.4f}\n", static_cast<double>(i) * dt, p.translation().x(),
                        p.translation().y(), p.angle(), clearances[i]);
  }
  write_text_file_atomically(path, text);
}

std::vector<Eigen::Vector2d> positions(const std::vector<SE2d>& poses) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : poses) out.push_back(p.translation());
  return out;
}

// The route on the map: the window around both paths, 5 m of margin.
void write_route_picture(const std::string& path, const NavigationGrid& world, const NavigationRunResult& r,
                         double radius) {
  std::vector<Eigen::Vector2d> all = positions(r.global.path.poses);
  for (const auto& p : r.driven) all.push_back(p.translation());
  Eigen::Vector2d lo = all.front(), hi = all.front();
  for (const auto& p : all) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  NavPicture pic(world, radius, lo.x() - 5, lo.y() - 5, hi.x() + 5, hi.y() + 5, 4096, 2.0);
  pic.polyline(positions(r.global.path.poses), kNavPlanned, 2);
  pic.polyline(positions(r.driven), kNavDriven, 2);
  pic.dot(r.driven.front().translation(), 5, kNavStart);
  pic.dot(r.global.path.poses.back().translation(), 5, kNavGoal);
  if (r.termination == NavigationTermination::Collision) pic.dot(r.driven.back().translation(), 6, kNavCollision);
  pic.write(path);
}

void run_nav_run(const NavRunArgs& a) {
  const SE2d start = to_se2(parse_cli_pose2(a.start, "--start"));
  const SE2d goal = to_se2(parse_cli_position_or_pose2(a.goal, "--goal"));
  std::vector<std::string> notes;
  NavigationRunOptions o = run_options(a, notes);
  // A heading given with the goal ("x,y,yaw" or "[x y yaw]") must be reached too.
  o.goal_heading = item_count(a.goal) == 3;
  const LoadedGrid in = load_any_grid(a.map, "MAP");
  std::vector<fs::path> inputs = in.files;
  if (!a.config.empty()) inputs.push_back(a.config);
  const fs::path dir(a.out_dir);
  const std::vector<std::string> names = {"run.rawlog", "driven.tum", "planned.tum", "clearance.txt", "route.png",
                                          "frames.png"};
  std::vector<fs::path> outputs;
  for (const auto& n : names) outputs.push_back(dir / n);
  check_outputs_distinct(inputs, outputs);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(printable(a.out_dir), "cannot create the output folder: " + ec.message());
  const NavigationGrid world = NavigationGrid::from_occupancy(in.grid, a.occupancy_threshold);

  // The log is written as the run goes, under a temporary name renamed
  // when it is complete; every fifth cycle is kept for the frame strip.
  std::vector<NavigationFrame> frames;
  NavigationRunResult r;
  write_file_atomically(outputs[0], [&](const fs::path& tmp) {
    RoveRawlogWriterOptions lo;
    lo.metadata = {{"tool", "rove nav run"}, {"map", a.map}};
    RoveRawlogWriter log(tmp.string(), lo);
    int cycle = 0;
    r = run_navigation(world, start, goal, o, &log, [&](const NavigationFrame& f) {
      if (cycle++ % 5 == 0) frames.push_back(f);
    });
    if (r.termination == NavigationTermination::NoPath) {
      throw Error(fmt::format("{}: {} (no-path)", printable(a.map), r.message));
    }
    log.close();
  });
  const double dt = o.simulator.dt;
  write_driven(outputs[1].string(), r, dt);
  write_planned(outputs[2].string(), r.global.path);
  write_clearances(outputs[3].string(), r, world, o.simulator.robot_radius, dt);
  write_route_picture(outputs[4].string(), world, r, o.simulator.robot_radius);
  // The animation strip: `frames` snapshots evenly spaced in time, 8 m around the robot.
  std::vector<NavPicture> strip;
  const int count = std::min<int>(a.frames, static_cast<int>(frames.size()));
  for (int k = 0; k < count; ++k) {
    const auto& f = frames[static_cast<std::size_t>(count == 1 ? 0 : k * (static_cast<int>(frames.size()) - 1) / (count - 1))];
    const Eigen::Vector2d c = f.T_map_robot.translation();
    NavPicture pic(world, o.simulator.robot_radius, c.x() - 4, c.y() - 4, c.x() + 4, c.y() + 4, 800, 3.0);
    pic.polyline(positions(r.global.path.poses), kNavPlanned, 1);
    for (const auto& p : f.obstacles) pic.dot(p, 1, kNavScan);
    pic.polyline(positions(f.local_plan), kNavLocal, 2);
    pic.robot(c, f.T_map_robot.angle(), o.simulator.robot_radius, kNavRobot);
    strip.push_back(std::move(pic));
  }
  if (!strip.empty()) NavPicture::write_strip(strip, outputs[5].string());

  std::vector<double> sorted = r.cycle_seconds;
  std::sort(sorted.begin(), sorted.end());
  const auto pct = [&](double q) {
    return sorted.empty() ? 0.0 : sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * sorted.size()))];
  };
  std::vector<Issue> issues;
  if (!r.ok()) issues.push_back({std::string(to_string(r.termination)), r.message});
  std::vector<std::string> written;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (i == 5 && strip.empty()) continue;
    written.push_back(outputs[i].string());
  }
  if (a.json) {
    JsonWriter j;
    j.begin_object().key("map").value(a.map).key("planner").value(a.planner);
    j.key("termination").value(to_string(r.termination)).key("message").value(r.message);
    j.key("planned_length_m").value(r.global.path.length).key("driven_length_m").value(r.length);
    j.key("time_s").value(r.time).key("min_clearance_m").value(r.min_clearance);
    j.key("cycles").value(r.cycles).key("replans").value(r.replans).key("infeasible_cycles").value(r.infeasible_cycles);
    j.key("cycle_ms_median").value(1e3 * pct(0.5)).key("cycle_ms_p99").value(1e3 * pct(0.99));
    j.key("notes").value(notes).key("files").value(written);
    write_issues(j, issues);
    j.end_object();
    fmt::print("{}\n", j.str());
    finish(issues);
    return;
  }
  for (const auto& n : notes) fmt::print("  note: {}\n", n);
  fmt::print("planned: {}\n", r.global.message);
  fmt::print("{} ({}): {}\n", a.planner, to_string(r.termination), r.message);
  if (o.planner == LocalPlannerKind::Reactive) fmt::print("  holonomic method: {}\n", to_string(o.reactive.holonomic));
  fmt::print("  {:.1f} s, driven {:.2f} m, minimum clearance {:.3f} m, {} cycles ({} replans, {} without a command)\n",
             r.time, r.length, r.min_clearance, r.cycles, r.replans, r.infeasible_cycles);
  fmt::print("  local planner CPU time per cycle: median {:.2f} ms, 99th percentile {:.2f} ms\n", 1e3 * pct(0.5), 1e3 * pct(0.99));
  for (const auto& f : written) fmt::print("  wrote {}\n", printable(f));
  finish(issues);
}

}  // namespace

void add_nav_run_command(CLI::App& nav) {
  auto a = std::make_shared<NavRunArgs>();
  auto* run = nav.add_subcommand(
      "run",
      "Plan a path on a grid map, then drive it with a local planner in the simulator (a disc robot, "
      "differential drive, a 360-degree lidar ray-cast in the map); the local planner sees the true pose "
      "and the scan. Writes into the output folder the "
      "log (run.rawlog: odometry and scans), the driven and planned paths (TUM), the clearances, the "
      "route on the map (route.png) and a strip of frames (frames.png). Exit status 0 when the goal "
      "is reached, 3 when the run ended otherwise (collision, stuck, timeout; outputs written), 1 "
      "when there is no path");
  run->add_option("MAP", a->map, "map.yaml, .gridmap[.gz] or .rovegrid[.gz]")->required();
  run->add_option("--start", a->start, "start pose x,y,yaw (meters, degrees)")->required();
  run->add_option("--goal", a->goal, "goal x,y (or x,y,yaw to reach that heading too)")->required();
  run->add_option("-o,--out", a->out_dir, "output folder (created)")->required();
  run->add_option("--planner", a->planner, "local planner: teb (timed elastic band) or reactive (PTGs)")
      ->check(CLI::IsMember({"teb", "reactive"}))
      ->capture_default_str();
  run->add_option("--config", a->config,
                  "INI file: for teb, a [TEB] section with teb_local_planner's parameter names; for reactive, "
                  "MRPT's reactive-navigation file (navigation-ptgs/reactive2d_config.ini)");
  run->add_option("--robot-radius", a->robot_radius, "robot radius, meters")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  run->add_option("--max-v", a->max_v, "top speed, m/s")->check(CLI::PositiveNumber)->capture_default_str();
  run->add_option("--max-w", a->max_w_deg, "top turn rate, deg/s")->check(CLI::PositiveNumber)->capture_default_str();
  run->add_option("--max-time", a->max_time, "give up after this long, s (0: from the path length)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  run->add_option("--occupancy-threshold", a->occupancy_threshold, "cells with p(free) at most this are obstacles")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  run->add_option("--seed", a->seed, "seed of the sensor and odometry noise")->capture_default_str();
  run->add_option("--frames", a->frames, "frames in frames.png")->check(CLI::Range(1, 64))->capture_default_str();
  run->add_flag("--json", a->json, "print the summary as JSON");
  run->callback([a] { run_nav_run(*a); });
}

}  // namespace rove::cli
