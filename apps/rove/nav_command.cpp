// `rove nav plan`: a path on a grid map for a disc robot (`rove nav run`
// in nav_run_command.cpp).
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli_values.h"
#include "commands.h"
#include "grid_input.h"
#include "nav_commands.h"
#include "nav_picture.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/json.h"
#include "rove/core/timer.h"
#include "rove/io/tum_trajectory.h"
#include "rove/nav/grid_planner.h"
#include "rove/nav/navigation_grid.h"

namespace rove::cli {

namespace {

namespace fs = std::filesystem;

struct NavPlanArgs {
  std::string map;
  std::string start, goal;
  std::string method = "value-iteration";
  std::string out;
  std::string picture;
  float occupancy_threshold = 0.5f;
  GridPlannerOptions options;
  bool json = false;
};

SE2d to_se2(const Pose2& p) { return SE2d(p.x(), p.y(), p.phi()); }

void run_nav_plan(NavPlanArgs a) {
  a.options.method = a.method == "astar" ? GridPlannerMethod::AStar : GridPlannerMethod::ValueIteration;
  const SE2d start = to_se2(parse_cli_position_or_pose2(a.start, "--start"));
  const SE2d goal = to_se2(parse_cli_position_or_pose2(a.goal, "--goal"));
  if (a.picture.empty()) a.picture = fs::path(a.out).replace_extension(".png").string();
  if (!ends_with_ci(a.picture, ".png")) {
    throw CLI::ValidationError("--picture", fmt::format("{}: expected a .png name", printable(a.picture)));
  }
  const LoadedGrid in = load_any_grid(a.map, "MAP");
  check_outputs_distinct(in.files, {a.out, a.picture});
  check_outputs_distinct({a.out}, {a.picture});
  Stopwatch watch;
  const NavigationGrid grid = NavigationGrid::from_occupancy(in.grid, a.occupancy_threshold);
  const double prepare_s = watch.lap();
  const GridPlanResult r = plan_path(grid, start, goal, a.options);
  const double plan_s = watch.lap();
  if (!r.ok()) throw Error(fmt::format("{}: {} ({})", printable(a.map), r.message, to_string(r.termination)));

  // The path as TUM: time = distance along the path (1 m/s).
  std::vector<TimedPose2> tum;
  std::vector<Eigen::Vector2d> points;
  double along = 0;
  for (std::size_t i = 0; i < r.path.poses.size(); ++i) {
    const SE2d& p = r.path.poses[i];
    if (i > 0) along += (p.translation() - points.back()).norm();
    points.push_back(p.translation());
    tum.push_back({Timestamp::from_seconds(along), Pose2(p.translation().x(), p.translation().y(), p.angle())});
  }
  write_tum_trajectory(a.out, tum);
  NavPicture picture(grid, a.options.robot_radius);
  picture.polyline(points, kNavPlanned, 3);
  picture.dot(points.front(), 4, kNavStart);
  picture.dot(points.back(), 4, kNavGoal);
  picture.write(a.picture);

  if (a.json) {
    JsonWriter j;
    j.begin_object().key("map").value(a.map).key("map_kind").value(in.kind);
    j.key("method").value(to_string(a.options.method)).key("robot_radius").value(a.options.robot_radius);
    j.key("termination").value(to_string(r.termination)).key("message").value(r.message);
    j.key("length_m").value(r.path.length).key("points").value(static_cast<std::int64_t>(r.path.poses.size()));
    j.key("path_cells").value(static_cast<std::int64_t>(r.path_cells));
    j.key("expanded_cells").value(static_cast<std::int64_t>(r.expanded_cells));
    j.key("min_clearance_m").value(r.path.min_clearance);
    j.key("prepare_seconds").value(prepare_s).key("plan_seconds").value(plan_s);
    j.key("files").value(std::vector<std::string>{a.out, a.picture});
    write_issues(j, {});
    j.end_object();
    fmt::print("{}\n", j.str());
    return;
  }
  fmt::print("{} {}: {} x {} cells of {} m\n", in.kind, printable(a.map), grid.size_x(), grid.size_y(),
             grid.resolution());
  fmt::print("{}\n", r.message);
  fmt::print("  {} grid cells, {} cells searched; clearances {:.3f} s, search {:.3f} s\n", r.path_cells,
             r.expanded_cells, prepare_s, plan_s);
  fmt::print("  wrote {}\n  wrote {}\n", printable(a.out), printable(a.picture));
}

}  // namespace

void add_nav_command(CLI::App& app) {
  auto* nav = app.add_subcommand("nav", "Plan paths on grid maps and drive them in a simulator");
  nav->require_subcommand(1);
  auto a = std::make_shared<NavPlanArgs>();
  auto* plan = nav->add_subcommand(
      "plan",
      "Plan a path for a disc robot on a grid map (MRPT's value-iteration planner or A* with a "
      "clearance cost). Writes the path as a TUM trajectory (time = distance along it at 1 m/s) "
      "and a picture of it on the map, each atomically. Exit status 1 when there is no path");
  plan->add_option("MAP", a->map, "map.yaml, .gridmap[.gz] or .rovegrid[.gz]")->required();
  plan->add_option("--start", a->start, "start x,y or x,y,yaw (meters, degrees)")->required();
  plan->add_option("--goal", a->goal, "goal x,y or x,y,yaw (meters, degrees)")->required();
  plan->add_option("-o,--out", a->out, "path to write (TUM text)")->required();
  plan->add_option("--picture", a->picture, "picture to write (.png; default: OUT with .png)");
  plan->add_option("--method", a->method, "search")
      ->check(CLI::IsMember({"value-iteration", "astar"}))
      ->capture_default_str();
  plan->add_option("--robot-radius", a->options.robot_radius, "robot radius, meters")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  plan->add_option("--occupancy-threshold", a->occupancy_threshold,
                   "cells with p(free) at most this are obstacles")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  plan->add_option("--min-step", a->options.min_step, "keep path points at least this far apart, meters")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  plan->add_option("--max-length", a->options.max_path_length,
                   "give up beyond 1.5 x this path length, meters (<= 0: no limit)")
      ->capture_default_str();
  plan->add_option("--clearance-weight", a->options.clearance_weight, "A*: weight of the clearance cost")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  plan->add_option("--clearance-distance", a->options.clearance_distance,
                   "A*: clearance beyond the radius that costs nothing, meters")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  plan->add_flag("--simplify", a->options.simplify, "replace the path by straight segments in line of sight");
  plan->add_option("--smooth", a->options.smoothing_iterations, "smoothing passes (0: none)")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  plan->add_flag("--json", a->json, "print the summary as JSON");
  plan->callback([a] { run_nav_plan(*a); });
  add_nav_run_command(*nav);
}

}  // namespace rove::cli
