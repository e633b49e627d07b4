// Navigation as library calls: rove.nav_plan (rove/nav/grid_planner.h) and
// rove.nav_run (navigation_run.h with the options of
// navigation_run_config.h), what `rove nav plan` and `rove nav run` run.
// The map is a grid file (map.yaml, .gridmap[.gz], .rovegrid[.gz]) or a
// rove.OccupancyGrid; poses are rove.SE2 or (x, y[, yaw]) in meters and
// radians. Results are types.SimpleNamespace of arrays and numbers; the
// GIL is released during the search and the run.

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "rove/core/files.h"
#include "rove/core/timer.h"
#include "rove/io/any_grid.h"
#include "rove/nav/grid_planner.h"
#include "rove/nav/navigation_grid.h"
#include "rove/nav/navigation_run.h"
#include "rove/nav/navigation_run_config.h"

namespace rove::python {

namespace {

// The grid of `map`: read from a file (the GIL released) or copied from a
// rove.OccupancyGrid. `name` names it in messages.
LoadedGrid map_arg(py::handle map, std::string& name) {
  if (py::isinstance<OccupancyGrid>(map)) {
    name = "<rove.OccupancyGrid>";
    LoadedGrid g;
    g.grid = map.cast<const OccupancyGrid&>();
    g.kind = "rove.OccupancyGrid";
    return g;
  }
  if (!py::isinstance<py::str>(map) && !py::hasattr(map, "__fspath__"))
    type_error(fmt::format("argument 'map': expected a file name (map.yaml, .gridmap[.gz], "
                           ".rovegrid[.gz]) or a rove.OccupancyGrid, got {}",
                           py::str(py::type::handle_of(map).attr("__name__")).cast<std::string>()));
  name = py::str(py::module_::import("os").attr("fspath")(map)).cast<std::string>();
  py::gil_scoped_release release;
  return read_any_grid(name);
}

// A pose from rove.SE2 or a sequence (x, y) or (x, y, yaw); `heading` is
// set to whether a yaw was given.
SE2d pose_arg(py::handle obj, const char* name, bool* heading = nullptr) {
  if (py::isinstance<SE2d>(obj)) {
    if (heading) *heading = true;
    return obj.cast<SE2d>();
  }
  std::vector<double> v;
  try {
    v = obj.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    type_error(fmt::format("argument '{}': expected rove.SE2 or (x, y[, yaw]) numbers (m, rad)", name));
  }
  if (v.size() != 2 && v.size() != 3)
    value_error(fmt::format("argument '{}': expected (x, y) or (x, y, yaw), got {} numbers", name, v.size()));
  for (const double x : v)
    if (!std::isfinite(x)) value_error(fmt::format("argument '{}': {} is not finite", name, x));
  if (heading) *heading = v.size() == 3;
  return SE2d(v[0], v[1], v.size() == 3 ? v[2] : 0.0);
}

Eigen::Vector3d xytheta(const SE2d& T) { return {T.translation().x(), T.translation().y(), T.angle()}; }

// The distance along a path at each of its poses, m.
std::vector<double> distances_along(const std::vector<SE2d>& poses) {
  std::vector<double> d;
  double along = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (i > 0) along += (poses[i].translation() - poses[i - 1].translation()).norm();
    d.push_back(along);
  }
  return d;
}

py::array_t<double> values(const std::vector<double>& v) {
  return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

void check_threshold(float occupancy_threshold) {
  if (!(occupancy_threshold >= 0.0f && occupancy_threshold <= 1.0f))
    throw InvalidArgument(fmt::format("occupancy_threshold = {}: expected a p(free) in [0, 1]", occupancy_threshold));
}

py::object nav_plan(py::handle map, py::handle start, py::handle goal, const std::string& method,
                    double robot_radius, float occupancy_threshold, double min_step, double max_length,
                    double clearance_weight, double clearance_distance, bool simplify, int smooth) {
  GridPlannerOptions o;
  if (method == "astar") {
    o.method = GridPlannerMethod::AStar;
  } else if (method != "value-iteration") {
    throw InvalidArgument(fmt::format("method '{}': expected value-iteration or astar", printable(method)));
  }
  o.robot_radius = robot_radius;
  o.min_step = min_step;
  o.max_path_length = max_length;
  o.clearance_weight = clearance_weight;
  o.clearance_distance = clearance_distance;
  o.simplify = simplify;
  o.smoothing_iterations = smooth;
  o.check();
  check_threshold(occupancy_threshold);
  const SE2d T_start = pose_arg(start, "start");
  const SE2d T_goal = pose_arg(goal, "goal");
  std::string name;
  const LoadedGrid in = map_arg(map, name);
  GridPlanResult r;
  double prepare_s = 0, plan_s = 0;
  std::uint32_t size_x = 0, size_y = 0;
  {
    py::gil_scoped_release release;
    Stopwatch watch;
    const NavigationGrid grid = NavigationGrid::from_occupancy(in.grid, occupancy_threshold);
    prepare_s = watch.lap();
    r = plan_path(grid, T_start, T_goal, o);
    plan_s = watch.lap();
    size_x = grid.size_x();
    size_y = grid.size_y();
  }
  if (!r.ok()) throw Error(fmt::format("{}: {} ({})", printable(name), r.message, to_string(r.termination)));
  py::dict d;
  d["map_kind"] = in.kind;
  d["map_cells"] = py::make_tuple(size_x, size_y);
  d["method"] = std::string(to_string(o.method));
  d["robot_radius"] = o.robot_radius;
  d["termination"] = std::string(to_string(r.termination));
  d["message"] = r.message;
  d["path"] = pose2_rows(r.path.poses, xytheta);
  d["distances"] = values(distances_along(r.path.poses));
  d["clearances"] = values(r.path.clearances);
  d["length_m"] = r.path.length;
  d["points"] = r.path.poses.size();
  d["path_cells"] = r.path_cells;
  d["expanded_cells"] = r.expanded_cells;
  d["min_clearance_m"] = r.path.min_clearance;
  d["prepare_seconds"] = prepare_s;
  d["plan_seconds"] = plan_s;
  d["notes"] = in.notes;
  return namespace_of(d);
}

py::object nav_run(py::handle map, py::handle start, py::handle goal, const std::string& planner,
                   const std::optional<Path>& config, double robot_radius, double max_v, double max_w_deg,
                   double max_time, float occupancy_threshold, std::uint64_t seed,
                   const std::optional<Path>& rawlog, py::object on_frame) {
  NavigationRobot robot;
  if (planner == "reactive") {
    robot.planner = LocalPlannerKind::Reactive;
  } else if (planner != "teb") {
    throw InvalidArgument(fmt::format("planner '{}': expected teb or reactive", printable(planner)));
  }
  for (const auto& [what, v] : {std::pair{"robot_radius", robot_radius}, {"max_v", max_v}, {"max_w_deg", max_w_deg}})
    if (!(v > 0 && std::isfinite(v))) throw InvalidArgument(fmt::format("{} = {}: expected a positive number", what, v));
  if (!(max_time >= 0 && std::isfinite(max_time)))
    throw InvalidArgument(fmt::format("max_time = {}: expected ≥ 0 s (0: from the path length)", max_time));
  check_threshold(occupancy_threshold);
  robot.radius = robot_radius;
  robot.max_v = max_v;
  robot.max_omega = max_w_deg * std::numbers::pi / 180;
  const SE2d T_start = pose_arg(start, "start");
  bool goal_heading = false;
  const SE2d T_goal = pose_arg(goal, "goal", &goal_heading);
  std::optional<IniFile> ini;
  if (config) ini = IniFile::load(config->string());
  NavigationRunConfig c = navigation_run_config(robot, ini ? &*ini : nullptr, config ? config->string() : "");
  NavigationRunOptions& o = c.options;
  o.simulator.seed = seed;
  o.max_time = max_time;
  o.goal_heading = goal_heading;
  std::string name;
  const LoadedGrid in = map_arg(map, name);
  if (rawlog) check_outputs_distinct(in.files, {*rawlog});
  StepHook hook(on_frame);
  const auto frame = [&](const NavigationFrame& f) {
    hook([&] {
      return py::object(py::dict(py::arg("time") = f.time, py::arg("pose") = f.T_map_robot,
                                 py::arg("v") = f.command.vx, py::arg("omega") = f.command.omega,
                                 py::arg("obstacles") = f.obstacles.size()));
    });
  };
  std::vector<double> clearances;
  const NavigationRunResult r = run_without_gil(hook, [&] {
    const NavigationGrid world = NavigationGrid::from_occupancy(in.grid, occupancy_threshold);
    NavigationRunResult out;
    const auto no_path = [&] {
      if (out.termination == NavigationTermination::NoPath)
        throw Error(fmt::format("{}: {} (no-path)", printable(name), out.message));
    };
    if (rawlog) {
      write_file_atomically(*rawlog, [&](const std::filesystem::path& tmp) {
        RoveRawlogWriterOptions lo;
        lo.metadata = {{"tool", "rove.nav_run"}, {"map", name}};
        RoveRawlogWriter log(tmp.string(), lo);
        out = run_navigation(world, T_start, T_goal, o, &log, frame);
        no_path();
        log.close();
      });
    } else {
      out = run_navigation(world, T_start, T_goal, o, nullptr, frame);
      no_path();
    }
    clearances = driven_clearances(out, world, o.simulator.robot_radius);
    return out;
  });
  py::dict d;
  d["planner"] = std::string(to_string(o.planner));
  d["termination"] = std::string(to_string(r.termination));
  d["message"] = r.message;
  d["ok"] = r.ok();
  d["planned"] = pose2_rows(r.global.path.poses, xytheta);
  d["planned_length_m"] = r.global.path.length;
  d["driven"] = pose2_rows(r.driven, xytheta);
  std::vector<double> times;
  for (std::size_t i = 0; i < r.driven.size(); ++i) times.push_back(static_cast<double>(i) * o.simulator.dt);
  d["times"] = values(times);
  d["clearances"] = values(clearances);
  d["driven_length_m"] = r.length;
  d["time_s"] = r.time;
  d["min_clearance_m"] = r.min_clearance;
  d["cycles"] = r.cycles;
  d["replans"] = r.replans;
  d["infeasible_cycles"] = r.infeasible_cycles;
  d["cycle_seconds"] = values(r.cycle_seconds);
  d["notes"] = c.notes;
  py::list issues;
  if (!r.ok()) issues.append(py::make_tuple(std::string(to_string(r.termination)), r.message));
  d["issues"] = issues;
  return namespace_of(d);
}

}  // namespace

void bind_nav(py::module_& m) {
  const GridPlannerOptions p;
  m.def("nav_plan", &nav_plan, py::arg("map"), py::arg("start"), py::arg("goal"),
        py::arg("method") = "value-iteration", py::arg("robot_radius") = p.robot_radius,
        py::arg("occupancy_threshold") = 0.5f, py::arg("min_step") = p.min_step,
        py::arg("max_length") = p.max_path_length, py::arg("clearance_weight") = p.clearance_weight,
        py::arg("clearance_distance") = p.clearance_distance, py::arg("simplify") = p.simplify,
        py::arg("smooth") = p.smoothing_iterations,
        "A path for a disc robot on a grid map (a map file or a rove.OccupancyGrid), as `rove nav "
        "plan` (without its files): method 'value-iteration' (MRPT's planner) or 'astar'; start and "
        "goal as rove.SE2 or (x, y[, yaw]) in m and rad. The path is (N, 3) x y theta with the "
        "distance along it at every pose. Raises rove.Error when there is no path.");
  m.def("nav_run", &nav_run, py::arg("map"), py::arg("start"), py::arg("goal"), py::arg("planner") = "teb",
        py::arg("config") = py::none(), py::arg("robot_radius") = 0.3, py::arg("max_v") = 0.8,
        py::arg("max_w_deg") = 60.0, py::arg("max_time") = 0.0, py::arg("occupancy_threshold") = 0.5f,
        py::arg("seed") = 1, py::arg("rawlog") = py::none(), py::arg("on_frame") = py::none(),
        "A global path, then the local planner ('teb' or 'reactive', options from `config` as "
        "`rove nav run --config`) driving it in the simulator, as `rove nav run`: the planned and "
        "driven paths (N, 3), times, clearances, counts. A goal with a yaw must be reached with "
        "it. rawlog: where to write the run's log (odometry and scans). on_frame(dict) is called "
        "every control cycle. Raises rove.Error when there is no path.");
}

}  // namespace rove::python
