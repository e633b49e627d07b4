// The SLAM pipelines of the command line as library calls: rove.icp_slam
// (rove/slam/icp_slam_run.h) and rove.lidar_slam (lidar_slam_run.h). The
// configuration is MRPT's INI file, with `overrides` for single keys; run
// options are keyword arguments; the GIL is released during the run and a
// per-step callback (on_step / on_scan) takes it back. Results keep the
// maps in C++: grids and point maps are handed out as rove objects whose
// arrays are views (no copy) that keep the result alive.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>

#include "bindings.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_points.h"
#include "rove/poses/lie_conversion.h"
#include "rove/slam/icp_slam.h"
#include "rove/slam/icp_slam_run.h"
#include "rove/slam/lidar_slam_options.h"
#include "rove/slam/lidar_slam_run.h"

namespace rove::python {

IniFile load_config(const std::optional<Path>& config, py::handle overrides) {
  IniFile ini = config ? IniFile::load(config->string()) : IniFile::parse("", "<overrides>");
  if (overrides.is_none()) return ini;
  if (!py::isinstance<py::dict>(overrides))
    type_error("argument 'overrides': expected {section: {key: value}}");
  for (const auto& [section, keys] : overrides.cast<py::dict>()) {
    if (!py::isinstance<py::str>(section) || !py::isinstance<py::dict>(keys))
      type_error("argument 'overrides': expected {section: {key: value}} with str sections");
    for (const auto& [key, value] : keys.cast<py::dict>()) {
      std::string text;
      if (py::isinstance<py::bool_>(value)) {
        text = value.cast<bool>() ? "true" : "false";
      } else {
        text = py::str(value).cast<std::string>();
      }
      ini.set(section.cast<std::string>(), py::str(key).cast<std::string>(), text);
    }
  }
  return ini;
}

double seconds_of(Timestamp t) {
  return t.valid() ? t.to_seconds() : std::numeric_limits<double>::quiet_NaN();
}

namespace {

/// An ICP-SLAM run: the mapper (its maps and keyframes) and the run's record.
struct IcpSlamRun {
  explicit IcpSlamRun(IcpSlam s) : slam(std::move(s)) {}
  IcpSlam slam;
  IcpSlamRunResult result;
};

template <typename MapType>
std::vector<const MapType*> maps_of(const MultiMetricMap& map) {
  std::vector<const MapType*> out;
  for (const auto& e : map.entries())
    if (const auto* m = dynamic_cast<const MapType*>(e.map.get())) out.push_back(m);
  return out;
}

py::dict icp_slam_summary(const IcpSlamRun& r) {
  const IcpSlamStats& st = r.slam.stats();
  py::dict d;
  d["format"] = std::string(to_string(r.result.format));
  d["steps"] = r.result.steps.size();
  d["scans"] = r.result.scans;
  d["observations"] = st.observations;
  d["icp_runs"] = st.icp_runs;
  d["icp_accepted"] = st.icp_accepted;
  d["icp_rejected_goodness"] = st.icp_rejected_goodness;
  d["icp_rejected_diverged"] = st.icp_rejected_invalid;
  d["icp_iterations"] = st.icp_iterations;
  d["keyframes"] = st.insertions;
  d["keyframes_checked"] = r.result.consistency.checked;
  d["keyframes_contradicted"] = r.result.consistency.contradicted;
  d["consistency_resolution"] = r.result.consistency.resolution;
  const Pose2 p = r.slam.pose();
  d["final_pose"] = py::dict(py::arg("x") = p.x(), py::arg("y") = p.y(), py::arg("phi") = p.phi());
  d["mapping_seconds"] = r.result.mapping_seconds;
  d["read_seconds"] = r.result.read_seconds;
  d["issues"] = issue_list(r.result.issues);
  return d;
}

std::shared_ptr<IcpSlamRun> icp_slam(const Path& rawlog, const std::optional<Path>& config,
                                     py::handle overrides, std::optional<std::uint64_t> max_steps,
                                     std::optional<float> max_range, py::object on_step) {
  const IniFile ini = load_config(config, overrides);
  IcpSlamConfig cfg = load_icp_slam_config(ini);
  auto run = std::make_shared<IcpSlamRun>(IcpSlam(cfg.options, std::move(cfg.map)));
  IcpSlamRunOptions ro;
  ro.rawlog_offset = cfg.rawlog_offset;
  ro.max_steps = max_steps;
  if (cfg.carmen_max_range) ro.reader.carmen.log.flaser_max_range = *cfg.carmen_max_range;
  if (max_range) ro.reader.carmen.log.flaser_max_range = *max_range;
  StepHook hook(on_step);
  ro.on_step = [&](const IcpSlamStep& s) {
    hook([&] {
      return py::object(py::dict(py::arg("index") = s.index, py::arg("time") = seconds_of(s.time),
                                 py::arg("pose") = to_se2(s.pose),
                                 py::arg("icp_accepted") = s.icp_accepted,
                                 py::arg("icp_goodness") = s.icp_goodness));
    });
  };
  run->result = run_without_gil(hook, [&] { return run_icp_slam(run->slam, rawlog.string(), ro); });
  return run;
}

void bind_icp_slam(py::module_& m) {
  py::class_<IcpSlamRun, std::shared_ptr<IcpSlamRun>>(
      m, "IcpSlamResult", "A finished ICP-SLAM run: its path, keyframes, maps and counters.")
      .def_property_readonly(
          "path",
          [](const IcpSlamRun& r) {
            return pose2_rows(r.result.steps, [](const IcpSlamStep& s) {
              return Eigen::Vector3d(s.pose.x(), s.pose.y(), s.pose.phi());
            });
          },
          "(N, 3) float64: T_map_robot (x, y, phi) after every step.")
      .def_property_readonly(
          "odometry",
          [](const IcpSlamRun& r) {
            return pose2_rows(r.result.steps, [](const IcpSlamStep& s) {
              return Eigen::Vector3d(s.odometry.x(), s.odometry.y(), s.odometry.phi());
            });
          },
          "(N, 3) float64: the cumulative odometry (x, y, phi) after every step.")
      .def_property_readonly(
          "times",
          [](const IcpSlamRun& r) {
            std::vector<double> t;
            for (const auto& s : r.result.steps) t.push_back(seconds_of(s.time));
            return py::array_t<double>(static_cast<py::ssize_t>(t.size()), t.data());
          },
          "(N,) seconds of every step (NaN when unknown).")
      .def_property_readonly(
          "keyframes",
          [](const IcpSlamRun& r) {
            return pose2_rows(r.slam.keyframes(), [](const IcpSlamKeyframe& k) {
              return Eigen::Vector3d(k.pose.x(), k.pose.y(), k.pose.phi());
            });
          },
          "(K, 3) float64: poses at which observations were inserted into the map.")
      .def_property_readonly("final_pose",
                             [](const IcpSlamRun& r) { return to_se2(r.slam.pose()); })
      .def_property_readonly(
          "grids",
          [](py::object self) {
            py::list l;
            for (const auto* g :
                 maps_of<OccupancyGridMetricMap>(self.cast<IcpSlamRun&>().slam.map()))
              l.append(py::cast(&g->grid(), py::return_value_policy::reference_internal, self));
            return l;
          },
          "The occupancy grids of the map (views into the result, no copy).")
      .def_property_readonly(
          "point_maps",
          [](py::object self) {
            py::list l;
            for (const auto* p : maps_of<PointsMetricMap>(self.cast<IcpSlamRun&>().slam.map()))
              l.append(py::cast(&p->points().cloud(), py::return_value_policy::reference_internal,
                                self));
            return l;
          },
          "The point maps of the map as rove.PointCloud (views into the result, no copy).")
      .def_property_readonly("issues",
                             [](const IcpSlamRun& r) { return issue_list(r.result.issues); })
      .def("summary", &icp_slam_summary,
           "Counters and figures as plain values (the keys of icp-slam's summary.json).")
      .def("__repr__", [](const IcpSlamRun& r) {
        return fmt::format("rove.IcpSlamResult({} steps, {} keyframes, final pose {})",
                           r.result.steps.size(), r.slam.keyframes().size(),
                           r.slam.pose().as_string());
      });
  m.def("icp_slam", &icp_slam, py::arg("rawlog"), py::arg("config") = py::none(),
        py::arg("overrides") = py::none(), py::arg("max_steps") = py::none(),
        py::arg("max_range") = py::none(), py::arg("on_step") = py::none(),
        "ICP-SLAM over a rawlog (rove, MRPT or CARMEN) with an MRPT icp-slam config (file, "
        "and/or overrides {section: {key: value}}), as `rove icp-slam`. on_step(dict) is "
        "called after every step; an exception it raises (or Ctrl-C) stops the run.");
}

/// A lidar SLAM run: the mapper, its record and the rebuilt map.
struct LidarSlamRun {
  explicit LidarSlamRun(LidarSlam s) : slam(std::move(s)) {}
  LidarSlam slam;
  LidarSlamRunResult result;
  OccupancyGrid map;
};

py::dict lidar_slam_summary(const LidarSlamRun& r) {
  const LidarSlamStats& st = r.slam.stats();
  py::dict d;
  d["format"] = std::string(to_string(r.result.format));
  d["sensor_label"] = r.result.sensor_label;
  d["scans"] = st.scans;
  d["nodes"] = r.slam.nodes().size();
  d["nodes_checked"] = r.result.consistency.checked;
  d["nodes_contradicted"] = r.result.consistency.contradicted;
  d["consistency_resolution"] = r.result.consistency.resolution;
  d["submaps"] = r.slam.submaps().size();
  std::size_t accepted = 0;
  for (const auto& lc : r.slam.loop_closures())
    accepted += lc.outcome == LoopClosureOutcome::Accepted;
  d["loop_closures_accepted"] = accepted;
  d["poor_matches"] = r.result.poor_matches;
  d["window_edges"] = st.window_edges;
  d["window_failed"] = st.window_failed;
  if (r.result.final_optimization) {
    d["final_chi2"] = r.result.final_optimization->final_chi2;
    d["optimization"] = std::string(to_string(r.result.final_optimization->termination));
  }
  d["mapping_seconds"] = r.result.mapping_seconds;
  d["read_seconds"] = r.result.read_seconds;
  d["issues"] = issue_list(r.result.issues);
  return d;
}

std::shared_ptr<LidarSlamRun> lidar_slam(const Path& rawlog, const std::optional<Path>& config,
                                         py::handle overrides,
                                         std::optional<std::uint64_t> max_scans,
                                         const std::string& sensor_label, py::object on_scan) {
  const IniFile ini = load_config(config, overrides);
  const LidarMapOptions map_options = LidarMapOptions::from_config(ConfigSection(ini, "map"));
  auto run = std::make_shared<LidarSlamRun>(LidarSlam(load_lidar_slam_options(ini)));
  LidarSlamRunOptions ro;
  ro.max_scans = max_scans;
  ro.sensor_label = sensor_label;
  StepHook hook(on_scan);
  ro.on_scan = [&](const LidarSlamScanUpdate& u) {
    hook([&] {
      return py::object(py::dict(
          py::arg("matched") = u.matched, py::arg("match_score") = u.match_score,
          py::arg("node_added") = u.node_added, py::arg("loops_accepted") = u.loops_accepted,
          py::arg("T_local_robot") = u.T_local_robot));
    });
  };
  run_without_gil(hook, [&] {
    run->result = run_lidar_slam(run->slam, rawlog.string(), ro);
    run->map = build_lidar_slam_map(run->slam, map_options);
    return 0;
  });
  return run;
}

void bind_lidar_slam(py::module_& m) {
  py::class_<LidarSlamRun, std::shared_ptr<LidarSlamRun>>(
      m, "LidarSlamResult", "A finished lidar SLAM run: poses, graph, loop closures and the map.")
      .def_property_readonly(
          "path",
          [](const LidarSlamRun& r) {
            std::vector<SE2d> poses;
            for (std::size_t i = 0; i < r.slam.num_scans(); ++i)
              poses.push_back(r.slam.scan_pose(i));
            return pose2_rows(poses, [](const SE2d& T) {
              return Eigen::Vector3d(T.translation().x(), T.translation().y(), T.angle());
            });
          },
          "(N, 3) float64: T_world_robot (x, y, theta) of every scan.")
      .def_property_readonly(
          "nodes",
          [](const LidarSlamRun& r) {
            return pose2_rows(r.slam.nodes(), [](const LidarSlamNode& n) {
              return Eigen::Vector3d(n.T_world_robot.translation().x(),
                                     n.T_world_robot.translation().y(), n.T_world_robot.angle());
            });
          },
          "(K, 3) float64: the graph's nodes T_world_robot (x, y, theta).")
      .def_property_readonly(
          "map",
          [](py::object self) -> py::object {
            return py::cast(&self.cast<LidarSlamRun&>().map,
                            py::return_value_policy::reference_internal, self);
          },
          "The rebuilt occupancy grid (a view into the result).")
      .def_property_readonly(
          "graph", [](const LidarSlamRun& r) { return r.slam.graph(); }, "The pose graph (a copy).")
      .def_property_readonly("issues",
                             [](const LidarSlamRun& r) { return issue_list(r.result.issues); })
      .def("summary", &lidar_slam_summary, "Counters and figures as plain values.")
      .def("__repr__", [](const LidarSlamRun& r) {
        return fmt::format("rove.LidarSlamResult({} scans, {} nodes)", r.slam.num_scans(),
                           r.slam.nodes().size());
      });
  m.def("lidar_slam", &lidar_slam, py::arg("rawlog"), py::arg("config") = py::none(),
        py::arg("overrides") = py::none(), py::arg("max_scans") = py::none(),
        py::arg("sensor_label") = "", py::arg("on_scan") = py::none(),
        "Lidar SLAM (submaps, loop closure, pose graph) over the 2D scans of a rawlog, as "
        "`rove lidar-slam`; config: its INI file (None: defaults) and/or overrides.");
}

}  // namespace

void bind_slam(py::module_& m) {
  bind_icp_slam(m);
  bind_lidar_slam(m);
}

}  // namespace rove::python
