// The filters of the command line as library calls: rove.pf_localization
// (rove/slam/pf_localization_run.h), rove.kf_slam (kf_slam_run.h) and
// rove.rbpf_slam (rbpf_slam_run.h). Configurations are MRPT's INI files
// (with `overrides`), run options keyword arguments, the GIL is released
// during the run and on_step(dict) takes it back per step. Results are
// plain attribute objects (types.SimpleNamespace of numpy arrays, numbers,
// strings and rove objects): they pickle, so batch runs can ship them.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "rove/slam/kf_slam_run.h"
#include "rove/slam/pf_localization_run.h"
#include "rove/slam/rbpf_slam_run.h"

namespace rove::python {

namespace {

Eigen::Vector3d xyphi(const SE2d& T) {
  return {T.translation().x(), T.translation().y(), T.angle()};
}
Eigen::Vector3d xyphi(const Pose2& p) { return {p.x(), p.y(), p.phi()}; }

template <typename T>
py::object optional_value(const std::optional<T>& v) {
  return v ? py::cast(*v) : py::none();
}

py::object pf_localization(const Path& rawlog, const Path& config, py::handle overrides,
                           std::uint64_t seed, int threads, std::optional<std::uint64_t> max_steps,
                           py::object on_step) {
  PfLocalizationConfig cfg = load_pf_localization_config(load_config(config, overrides));
  PfLocalizationRunOptions ro;
  ro.seed = seed;
  ro.num_threads = threads;
  ro.max_steps = max_steps;
  StepHook hook(on_step);
  ro.on_step = [&](const PfLocalizationStep& s) {
    hook([&] {
      return py::object(py::dict(py::arg("index") = s.index, py::arg("pose") = s.estimate.mean,
                                 py::arg("ess") = s.ess, py::arg("converged") = s.converged));
    });
  };
  const PfLocalizationResult r = run_without_gil(
      hook, [&] { return run_pf_localization(std::move(cfg), rawlog.string(), ro); });
  py::dict d;
  d["status"] = std::string(to_string(r.termination));
  d["converged"] = r.ok();
  d["message"] = r.message;
  d["path"] =
      pose2_rows(r.steps, [](const PfLocalizationStep& s) { return xyphi(s.estimate.mean); });
  std::vector<double> ess, std_xy;
  for (const auto& s : r.steps) {
    ess.push_back(s.ess);
    std_xy.push_back(s.estimate.position_std);
  }
  d["ess"] = py::array_t<double>(static_cast<py::ssize_t>(ess.size()), ess.data());
  d["position_std"] = py::array_t<double>(static_cast<py::ssize_t>(std_xy.size()), std_xy.data());
  d["converged_step"] = optional_value(r.converged_step);
  d["first_converged_step"] = optional_value(r.first_converged_step);
  d["ground_truth_rmse"] = optional_value(r.ground_truth_rmse);
  d["peak_particles"] = r.peak_particles;
  if (!r.snapshots.empty()) {
    const auto& last = r.snapshots.back().particles;
    d["particles"] = pose2_rows(last.states, [](const SE2d& T) { return xyphi(T); });
    d["log_weights"] = py::array_t<double>(static_cast<py::ssize_t>(last.log_weights.size()),
                                           last.log_weights.data());
  }
  d["map_kind"] = r.map_info.kind;
  d["filter_seconds"] = r.filter_seconds;
  d["issues"] = issue_list(r.issues);
  return namespace_of(d);
}

py::object kf_slam(const Path& rawlog, const Path& config, py::handle overrides,
                   std::optional<bool> use_landmark_ids, std::optional<std::uint64_t> max_steps,
                   py::object on_step) {
  const KfSlamConfig cfg = load_kf_slam_config(load_config(config, overrides));
  KfSlamRunOptions ro;
  ro.use_landmark_ids = use_landmark_ids;
  ro.max_steps = max_steps;
  StepHook hook(on_step);
  ro.on_step = [&](const KfSlamStep& s) {
    hook([&] {
      return py::object(py::dict(py::arg("index") = s.index, py::arg("pose") = s.pose,
                                 py::arg("landmarks") = s.landmarks, py::arg("nis") = s.nis));
    });
  };
  const KfSlamResult r =
      run_without_gil(hook, [&] { return run_kf_slam(cfg, rawlog.string(), ro); });
  py::dict d;
  d["dim"] = r.dim;
  py::array_t<double> path({static_cast<py::ssize_t>(r.steps.size()), py::ssize_t{3}});
  for (std::size_t i = 0; i < r.steps.size(); ++i)
    for (int c = 0; c < 3; ++c)
      path.mutable_at(static_cast<py::ssize_t>(i), c) = r.steps[i].pose.translation()[c];
  d["path"] = path;
  d["poses"] = [&] {
    std::vector<SE3d> p;
    for (const auto& s : r.steps) p.push_back(s.pose);
    return p;
  }();
  py::array_t<double> lm({static_cast<py::ssize_t>(r.landmarks.size()), py::ssize_t{3}});
  std::vector<std::int64_t> ids;
  for (std::size_t i = 0; i < r.landmarks.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      lm.mutable_at(static_cast<py::ssize_t>(i), c) = r.landmarks[i].mean[c];
    ids.push_back(r.landmarks[i].id);
  }
  d["landmarks"] = lm;
  d["landmark_ids"] = py::array_t<std::int64_t>(static_cast<py::ssize_t>(ids.size()), ids.data());
  d["landmark_rmse"] = optional_value(r.landmark_rmse);
  d["path_rmse"] = optional_value(r.path_rmse);
  d["heading_rmse"] = optional_value(r.heading_rmse);
  d["associations"] = py::dict(
      py::arg("readings") = r.association.readings, py::arg("correct") = r.association.correct,
      py::arg("wrong") = r.association.wrong, py::arg("duplicates") = r.association.duplicates);
  d["final_pose_covariance"] = r.final_pose_covariance;
  d["filter_seconds"] = r.filter_seconds;
  d["issues"] = issue_list(r.issues);
  return namespace_of(d);
}

py::object rbpf_slam(const Path& rawlog, const Path& config, py::handle overrides,
                     std::uint64_t seed, int threads, std::optional<std::uint32_t> particles,
                     std::optional<std::uint64_t> max_steps, py::object on_step) {
  const RbpfSlamConfig cfg = load_rbpf_slam_config(load_config(config, overrides));
  RbpfSlamRunOptions ro;
  ro.seed = seed;
  ro.num_threads = threads;
  ro.particles = particles;
  ro.max_steps = max_steps;
  StepHook hook(on_step);
  ro.on_step = [&](std::uint64_t index) {
    hook([&] { return py::object(py::dict(py::arg("index") = index)); });
  };
  RbpfSlamResult r = run_without_gil(hook, [&] { return run_rbpf_slam(cfg, rawlog.string(), ro); });
  py::dict d;
  d["status"] = std::string(to_string(r.termination));
  d["ok"] = r.ok();
  d["message"] = r.message;
  d["path"] = pose2_rows(r.path, [](const Pose2& p) { return xyphi(p); });
  d["particles"] = pose2_rows(r.particles, [](const SE2d& T) { return xyphi(T); });
  d["best"] = r.best;
  d["updates"] = r.updates;
  d["insertions"] = r.insertions;
  d["scans"] = r.scans;
  d["mapping_seconds"] = r.mapping_seconds;
  d["contradicted_updates"] = r.contradicted_updates;
  d["issues"] = issue_list(r.issues);
  d["map"] = py::cast(std::move(r.map));  // moved, not copied: `cells` is a view of it
  return namespace_of(d);
}

}  // namespace

void bind_filters(py::module_& m) {
  m.def("pf_localization", &pf_localization, py::arg("rawlog"), py::arg("config"),
        py::arg("overrides") = py::none(), py::arg("seed") = 0, py::arg("threads") = 1,
        py::arg("max_steps") = py::none(), py::arg("on_step") = py::none(),
        "Monte-Carlo localization over a rawlog with an MRPT pf-localization config, as "
        "`rove pf-localization`; the result's path is the estimate after every step.");
  m.def("kf_slam", &kf_slam, py::arg("rawlog"), py::arg("config"),
        py::arg("overrides") = py::none(), py::arg("use_landmark_ids") = py::none(),
        py::arg("max_steps") = py::none(), py::arg("on_step") = py::none(),
        "EKF landmark SLAM over a rawlog with an MRPT kf-slam config, as `rove kf-slam`.");
  m.def("rbpf_slam", &rbpf_slam, py::arg("rawlog"), py::arg("config"),
        py::arg("overrides") = py::none(), py::arg("seed") = 0, py::arg("threads") = 1,
        py::arg("particles") = py::none(), py::arg("max_steps") = py::none(),
        py::arg("on_step") = py::none(),
        "RBPF grid mapping over a rawlog with an MRPT rbpf-slam config, as `rove rbpf-slam`.");
}

}  // namespace rove::python
