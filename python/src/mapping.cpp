// Map building as library calls: rove.octomap_build (rove/io/octree_build.h,
// what `rove octomap build` runs) and rove.map_build (build_map of
// rove/slam/metric_map_builder.h with map_build_outputs.h, what `rove map
// build` runs). Results are types.SimpleNamespace with the figures of the
// commands' --json summaries; maps come back as rove objects (grids, point
// clouds), and the files are written only when an output is given.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "rove/core/files.h"
#include "rove/core/parallel.h"
#include "rove/io/octree_build.h"
#include "rove/io/tum_trajectory.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_points.h"
#include "rove/maps/octree_export.h"
#include "rove/slam/map_build_outputs.h"
#include "rove/slam/metric_map_builder.h"
#include "rove/slam/scan_consistency.h"
#include "rove/io/mrpt_simplemap.h"
#include "rove/core/error.h"

namespace rove::python {

namespace {

std::string path_string(py::handle obj, const char* name) {
  if (!py::isinstance<py::str>(obj) && !py::hasattr(obj, "__fspath__"))
    type_error(fmt::format("argument '{}': expected a file name (str or os.PathLike), got {}", name,
                           py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>()));
  return py::str(py::module_::import("os").attr("fspath")(obj)).cast<std::string>();
}

// The clouds: one file name or a sequence of them.
std::vector<std::string> cloud_paths(py::handle clouds) {
  if (py::isinstance<py::str>(clouds) || py::hasattr(clouds, "__fspath__")) return {path_string(clouds, "clouds")};
  if (!py::isinstance<py::sequence>(clouds))
    type_error("argument 'clouds': expected a file name or a sequence of file names (.pcd, .ply)");
  std::vector<std::string> out;
  for (const auto& c : clouds.cast<py::sequence>()) out.push_back(path_string(c, "clouds"));
  if (out.empty()) value_error("argument 'clouds': no cloud given");
  return out;
}

// Poses: a TUM file or (N, 8) TUM rows.
std::vector<StampedPose3> poses_arg(py::handle poses, std::string& source) {
  if (py::isinstance<py::str>(poses) || py::hasattr(poses, "__fspath__")) {
    source = path_string(poses, "poses");
    py::gil_scoped_release release;
    return read_tum_trajectory(source);
  }
  source = "argument 'poses'";
  const auto m = matrix_arg(poses, "poses", 8, true);
  std::vector<StampedPose3> out;
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const Eigen::Quaterniond q(m(i, 7), m(i, 4), m(i, 5), m(i, 6));
    if (!(q.norm() > 1e-12)) value_error(fmt::format("argument 'poses': row {}: the quaternion is zero", i));
    out.push_back({m(i, 0), SE3d(q.normalized(), Eigen::Vector3d(m(i, 1), m(i, 2), m(i, 3)))});
  }
  return out;
}

py::object octomap_build(py::handle clouds, const std::optional<Path>& output, double resolution,
                         std::optional<Eigen::Vector3d> origin, py::handle poses, double max_range,
                         const std::string& mode, const std::string& arithmetic, int threads,
                         const std::string& color, py::object on_cloud) {
  OctreeBuildOptions o;
  o.resolution = resolution;
  o.origin = origin;
  o.insert.max_range = max_range;
  o.insert.mode = parse_octree_update_mode(mode);
  o.insert.arithmetic = parse_octree_ray_arithmetic(arithmetic);
  o.insert.num_threads = resolve_thread_count(threads, "threads");
  o.color = parse_octree_color_rule(color);
  if (!std::isfinite(max_range)) throw InvalidArgument(fmt::format("max_range = {}: not a finite number", max_range));
  const std::vector<std::string> paths = cloud_paths(clouds);
  std::string poses_source = "poses";
  if (!poses.is_none()) o.poses = poses_arg(poses, poses_source);
  if (output) {
    (void)octree_output_format(output->string());
    std::vector<std::filesystem::path> inputs(paths.begin(), paths.end());
    if (!poses.is_none() && poses_source != "argument 'poses'") inputs.emplace_back(poses_source);
    check_outputs_distinct(inputs, {*output});
  }
  StepHook hook(on_cloud);
  o.on_cloud = [&](std::size_t done) { hook([&] { return py::object(py::int_(done)); }); };
  std::vector<OctreeBuildIssue> issues;
  PointCloud occupied;
  const OctreeBuildResult r = run_without_gil(hook, [&] {
    OctreeBuildResult out = build_octree(paths, o, poses_source);
    issues = out.issues;
    if (output)
      for (auto& i : write_built_octree(output->string(), out)) issues.push_back(std::move(i));
    occupied = octree_occupied_cloud(out.tree);
    return out;
  });
  const OccupancyOctree& t = r.tree;
  py::dict d;
  d["resolution"] = t.resolution();
  d["points"] = r.points;
  d["skipped_points"] = r.skipped_points;
  d["nodes"] = t.num_nodes();
  d["leaves"] = r.leaves;
  d["occupied_leaves"] = r.occupied_leaves;
  d["memory_bytes"] = t.memory_usage();
  d["colors"] = r.colors.clouds == 0 ? py::object(py::none())
                                     : py::object(py::dict(py::arg("rule") = color, py::arg("clouds") = r.colors.clouds,
                                                           py::arg("points") = r.colors.points,
                                                           py::arg("mean_leaves") = r.colors.mean_leaves));
  if (t.empty()) {
    d["bounds"] = py::none();
  } else {
    Eigen::Vector3d lo, hi;
    t.metric_bounds(lo, hi);
    d["bounds"] = py::dict(py::arg("min") = std::vector<double>{lo.x(), lo.y(), lo.z()},
                           py::arg("max") = std::vector<double>{hi.x(), hi.y(), hi.z()});
  }
  d["seconds"] = r.seconds;
  d["occupied"] = py::cast(std::move(occupied));
  d["outputs"] = output ? std::vector<std::string>{output->string()} : std::vector<std::string>{};
  d["issues"] = issue_list(issues);
  return namespace_of(d);
}

py::object map_check(const Path& simplemap, double resolution) {
  if (!(std::isfinite(resolution) && resolution > 0.0)) {
    throw InvalidArgument(fmt::format("resolution must be > 0, got {}", resolution));
  }
  check_regular_input(simplemap, "simplemap");
  const SimpleMap map = load_mrpt_simplemap(simplemap.string());
  const SimplemapCheck r = check_simplemap(map, static_cast<float>(resolution));
  const ScanConsistency& c = r.consistency;
  py::dict d;
  d["keyframes"] = r.keyframes;
  d["scans"] = r.poses.size();
  d["resolution"] = c.resolution;
  d["checked"] = c.checked;
  d["contradicted"] = c.contradicted;
  d["through_walls"] = py::array_t<double>(static_cast<py::ssize_t>(c.through_walls.size()), c.through_walls.data());
  std::vector<std::array<double, 3>> poses;
  for (const SE2d& p : r.poses) poses.push_back({p.translation().x(), p.translation().y(), p.angle()});
  d["poses"] = py::array_t<double>({static_cast<py::ssize_t>(poses.size()), py::ssize_t{3}},
                                   reinterpret_cast<const double*>(poses.data()));
  py::list issues;
  for (const ScanCheckIssue& i : r.issues) issues.append(py::make_tuple(i.code, i.message));
  d["issues"] = issues;
  return namespace_of(d);
}

py::object map_build(const Path& config, const Path& input, const std::optional<Path>& out,
                     const std::string& section, py::object on_progress) {
  if (out) {
    check_map_build_outputs(config.string(), input.string(), out->string());
  } else {
    check_regular_input(config, "config file");
    check_regular_input(input, "input");
  }
  const IniFile ini = IniFile::load(config.string(), IniOptions{.strict = false});
  MapBuildConfig cfg = load_map_build_config(ini, section);
  MultiMetricMap& mm = cfg.maps;
  StepHook hook(on_progress);
  MapBuildOptions bo;
  bo.on_progress = [&](std::uint64_t done) { hook([&] { return py::object(py::int_(done)); }); };
  std::vector<std::string> files;
  const MapBuildResult r = run_without_gil(hook, [&] {
    MapBuildResult res = build_map(input.string(), mm, bo);
    if (out) files = save_map_build(out->string(), mm);
    return res;
  });
  py::dict d;
  d["section"] = cfg.section;
  d["input_kind"] = r.input == MapInputKind::SimpleMap ? "simplemap" : "rawlog";
  d["keyframes"] = r.keyframes;
  d["odometry_steps"] = r.odometry_steps;
  d["observations"] = r.observations;
  d["observations_used"] = r.observations_used;
  d["seconds"] = r.seconds;
  py::list maps, grids, point_maps;
  for (std::size_t i = 0; i < mm.size(); ++i) {
    const auto& e = mm.entries()[i];
    const MapStatistics st = e.map->statistics();
    py::dict m;
    m["index"] = i;
    m["kind"] = e.map->kind();
    m["section"] = e.section_prefix;
    m[st.unit.c_str()] = st.elements;
    m["total_cells"] = st.total_cells;
    m["observations_inserted"] = e.observations_inserted;
    m["insertion_enabled"] = e.params.enable_insertion;
    maps.append(m);
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) grids.append(py::cast(g->grid()));
    if (const auto* p = dynamic_cast<const PointsMetricMap*>(e.map.get())) point_maps.append(py::cast(p->points().cloud()));
  }
  d["maps"] = maps;
  d["grids"] = grids;
  d["point_maps"] = point_maps;
  py::list ignored;
  for (const auto& k : cfg.ignored_keys)
    ignored.append(py::dict(py::arg("section") = k.section, py::arg("key") = k.key, py::arg("reason") = k.reason));
  d["ignored_keys"] = ignored;
  d["files"] = files;
  d["issues"] = issue_list(map_build_issues(r, mm, input.string()));
  return namespace_of(d);
}

}  // namespace

void bind_mapping(py::module_& m) {
  m.def("octomap_build", &octomap_build, py::arg("clouds"), py::arg("output") = py::none(),
        py::arg("resolution") = 0.1, py::arg("origin") = py::none(), py::arg("poses") = py::none(),
        py::arg("max_range") = -1.0, py::arg("mode") = "once", py::arg("arithmetic") = "double",
        py::arg("threads") = 1, py::arg("color") = "mean", py::arg("on_cloud") = py::none(),
        "An occupancy octree from point clouds (.pcd, .ply files) and their sensor origins, as `rove "
        "octomap build`: origin (x, y, z) for every cloud, or poses (a TUM file or (N, 8) rows, one per "
        "cloud, the clouds then in the sensor frame); mode once / discretized / every-ray; arithmetic "
        "double / octomap; color mean / average / integrate / set / none. output: the .bt or .ot file "
        "to write. The occupied cells' centres come back as a rove.PointCloud. on_cloud(n) after each "
        "cloud.");
  m.def("map_check", &map_check, py::arg("simplemap"), py::arg("resolution") = 0.05,
        "A simplemap's 2D scans against each other, as `rove map check`: counts, each scan's share of "
        "rays through walls and its pose (x, y, theta) as arrays, issues (map-contradicts-scans, "
        "not-checked).");
  m.def("map_build", &map_build, py::arg("config"), py::arg("input"), py::arg("out") = py::none(),
        py::arg("section") = "", py::arg("on_progress") = py::none(),
        "The maps an MRPT config declares, built from a rawlog (poses from odometry) or a simplemap, as "
        "`rove map build`: counts per map, the occupancy grids and point maps as rove objects; out: the "
        "folder to write the map_* files into. on_progress(n) after each keyframe or rawlog entry.");
}

}  // namespace rove::python
