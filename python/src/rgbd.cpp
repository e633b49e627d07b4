// RGB-D SLAM as a library call: rove.rgbd_slam (rove/slam/rgbd_slam_run.h),
// what `rove rgbd-slam` runs. Present when rove was built with rove::vision
// (OpenCV). The options come as the command line's: a config file's
// [rgbd-slam] section (or the keys outside any section, the RGB-D SLAM
// tutorial's parameters.txt) with `overrides`, and a preset. The result is a
// types.SimpleNamespace of numpy arrays, numbers and strings.

#include "bindings.h"

#if ROVE_PYTHON_RGBD

#include <pybind11/stl.h>

#include "rove/core/config_section.h"
#include "rove/core/ini.h"
#include "rove/slam/rgbd_sequence.h"
#include "rove/slam/rgbd_slam_run.h"

namespace rove::python {

namespace {

RgbdSlamOptions rgbd_options(const std::optional<Path>& config, py::handle overrides, const std::string& preset) {
  if (preset != "default" && preset != "tutorial") {
    value_error("preset must be 'default' or 'tutorial', got '" + preset + "'");
  }
  const IniFile ini = load_config(config, overrides);
  const std::string section = ini.has_section("rgbd-slam") ? "rgbd-slam" : "";
  IniFile merged = ini;
  if (!merged.has(section, "preset")) merged.set(section, "preset", preset);
  const ConfigSection s(merged, section);
  RgbdSlamOptions o = RgbdSlamOptions::from_config(s);
  s.check_all_read();
  return o;
}

py::object rgbd_slam(const Path& input, const std::optional<Path>& config, py::handle overrides,
                     const std::string& preset, const std::string& camera, std::optional<double> depth_scale,
                     std::optional<std::size_t> max_frames, py::object on_frame) {
  RgbdSequenceOptions so;
  so.camera = camera;
  so.depth_scale = depth_scale;
  const RgbdSequence seq = read_rgbd_sequence(input.string(), so);
  const RgbdSlamOptions opt = rgbd_options(config, overrides, preset);
  RgbdSlam slam(seq.camera, for_sequence(opt, seq));
  RgbdSlamRunOptions ro;
  ro.max_frames = max_frames;
  StepHook hook(on_frame);
  ro.on_frame = [&](const RgbdFrameUpdate& u) {
    hook([&] {
      return py::object(py::dict(py::arg("index") = u.index, py::arg("status") = std::string(to_string(u.status)),
                                 py::arg("features") = u.features, py::arg("inliers") = u.inliers,
                                 py::arg("loops_accepted") = u.loops_accepted));
    });
  };
  const RgbdSlamRunResult r = run_without_gil(hook, [&] { return run_rgbd_slam(slam, seq, ro); });
  const RgbdSlamStats& st = slam.stats();
  py::dict d;
  d["trajectory"] = tum_rows(rgbd_trajectory(slam));
  std::vector<StampedPose3> kf;
  std::vector<std::size_t> kf_frames;
  for (const RgbdKeyframe& k : slam.keyframes()) {
    kf.push_back({k.time, k.T_world_camera});
    kf_frames.push_back(k.frame);
  }
  d["keyframes"] = tum_rows(kf);
  d["keyframe_frames"] = py::array_t<std::size_t>(static_cast<py::ssize_t>(kf_frames.size()), kf_frames.data());
  std::vector<std::string> status;
  for (std::size_t i = 0; i < slam.num_frames(); ++i) status.emplace_back(to_string(slam.frame_status(i)));
  d["frame_status"] = status;
  d["stats"] = py::dict(
      py::arg("frames") = st.frames, py::arg("tracked") = st.tracked, py::arg("lost") = st.lost,
      py::arg("no_features") = st.no_features, py::arg("keyframes") = st.keyframes,
      py::arg("loop_checks") = st.loop_checks, py::arg("loops_accepted") = st.loops_accepted,
      py::arg("optimizations") = st.optimizations, py::arg("icp_edges") = st.icp_edges,
      py::arg("icp_refused") = st.icp_refused, py::arg("ba_points") = st.ba_points,
      py::arg("ba_observations") = st.ba_observations, py::arg("ba_outliers") = st.ba_outliers);
  d["ate_rmse"] = r.ate ? py::cast(r.ate->translation.rmse) : py::none();
  d["ate_max"] = r.ate ? py::cast(r.ate->translation.max) : py::none();
  d["camera"] = seq.camera_source;
  d["read_seconds"] = r.read_seconds;
  d["processing_seconds"] = r.processing_seconds;
  d["issues"] = issue_list(r.issues);
  return py::module_::import("types").attr("SimpleNamespace")(**d);
}

}  // namespace

void bind_rgbd(py::module_& m) {
  m.def("rgbd_slam", &rgbd_slam, py::arg("input"), py::arg("config") = py::none(),
        py::arg("overrides") = py::none(), py::arg("preset") = "default", py::arg("camera") = "",
        py::arg("depth_scale") = py::none(), py::arg("max_frames") = py::none(),
        py::arg("on_frame") = py::none(),
        "RGB-D SLAM over a TUM / ICL-NUIM / numbered-frame folder or a rawlog of 3D range scans, as "
        "`rove rgbd-slam` (without its output files): trajectory and keyframes as (N, 8) TUM rows, "
        "per-frame status, counts, the ATE against the folder's reference when it has one.");
}

}  // namespace rove::python

#else

namespace rove::python {
void bind_rgbd(py::module_&) {}  // built without rove::vision: no rove.rgbd_slam
}  // namespace rove::python

#endif
