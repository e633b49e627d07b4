// Trajectory evaluation as library calls: rove.eval_ate, rove.eval_rpe and
// rove.eval_relations, what `rove eval ate|rpe|relations` run
// (rove/slam/trajectory_eval_run.h, the files read by trajectory_input.h).
// Trajectories come as files (TUM, KITTI, g2o/TORO vertices) or as numpy
// rows; results are types.SimpleNamespace with the figures of the
// command's --json report and the per-pair errors as arrays.

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "rove/slam/trajectory_eval_run.h"
#include "rove/slam/trajectory_input.h"

namespace rove::python {

namespace {

// A path given as str or os.PathLike; nullopt for anything else.
std::optional<Path> path_of(py::handle obj) {
  if (py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__"))
    return Path(py::str(py::module_::import("os").attr("fspath")(obj)).cast<std::string>());
  return std::nullopt;
}

std::string shape_of(const py::array& a) {
  std::string s;
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += fmt::format("{}{}", i ? ", " : "", a.shape(i));
  return a.ndim() == 1 ? s + "," : s;
}

// A trajectory given as a file or as rows.
struct TrajectoryArg {
  std::optional<Path> path;
  LoadedTrajectory rows;  // when given as an array
};

// The poses of (N, 8) rows t x y z qx qy qz qw or (N, 4) rows t x y theta.
TrajectoryArg trajectory_arg(py::handle obj, const char* name) {
  TrajectoryArg out;
  if ((out.path = path_of(obj))) return out;
  const char* expected =
      "a file name or a numpy array of shape (N, 8) (TUM rows t x y z qx qy qz qw) or (N, 4) "
      "(rows t x y theta)";
  if (!py::isinstance<py::array>(obj))
    type_error(fmt::format("argument '{}': expected {}, got {}", name, expected,
                           py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>()));
  const auto a = py::reinterpret_borrow<py::array>(obj);
  if (a.ndim() != 2 || (a.shape(1) != 8 && a.shape(1) != 4))
    value_error(fmt::format("argument '{}': expected shape (N, 8) (TUM rows t x y z qx qy qz qw) "
                            "or (N, 4) (rows t x y theta), got ({})",
                            name, shape_of(a)));
  const Eigen::Index cols = a.shape(1);
  const auto m = matrix_arg(obj, name, cols, true);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    if (cols == 4) {
      const Eigen::Matrix3d R(Eigen::AngleAxisd(m(i, 3), Eigen::Vector3d::UnitZ()));
      out.rows.poses.push_back({m(i, 0), SE3d(R, Eigen::Vector3d(m(i, 1), m(i, 2), 0.0))});
      continue;
    }
    const Eigen::Quaterniond q(m(i, 7), m(i, 4), m(i, 5), m(i, 6));
    if (!(q.norm() > 1e-12))
      value_error(fmt::format("argument '{}': row {}: the quaternion (qx qy qz qw) is zero", name, i));
    out.rows.poses.push_back({m(i, 0), SE3d(q.normalized(), Eigen::Vector3d(m(i, 1), m(i, 2), m(i, 3)))});
  }
  out.rows.format = cols == 8 ? "array (t x y z qx qy qz qw)" : "array (t x y theta)";
  return out;
}

// The trajectory itself (read here when it is a file; the GIL released).
LoadedTrajectory load(TrajectoryArg&& arg, const std::string& format) {
  if (!arg.path) return std::move(arg.rows);
  return load_trajectory(arg.path->string(), format);
}

// Relations given as a Freiburg relations file or as (N, 8) rows
// t1 t2 x y z roll pitch yaw (R = Rz(yaw)·Ry(pitch)·Rx(roll)).
struct RelationsArg {
  std::optional<Path> path;
  std::vector<PoseRelation> rows;
};

RelationsArg relations_arg(py::handle obj) {
  RelationsArg out;
  if ((out.path = path_of(obj))) return out;
  if (!py::isinstance<py::array>(obj))
    type_error(fmt::format("argument 'relations': expected a file name or a numpy array of shape "
                           "(N, 8) (rows t1 t2 x y z roll pitch yaw), got {}",
                           py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>()));
  const auto m = matrix_arg(obj, "relations", 8, true);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const Eigen::Matrix3d R(Eigen::AngleAxisd(m(i, 7), Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(m(i, 6), Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(m(i, 5), Eigen::Vector3d::UnitX()));
    out.rows.push_back({m(i, 0), m(i, 1), SE3d(R, Eigen::Vector3d(m(i, 2), m(i, 3), m(i, 4)))});
  }
  return out;
}

// The statistics as the command's JSON writes them.
py::dict stats(const ErrorStatistics& s) {
  return py::dict(py::arg("count") = s.count, py::arg("rmse") = s.rmse, py::arg("mean") = s.mean,
                  py::arg("median") = s.median, py::arg("std") = s.stddev, py::arg("min") = s.min,
                  py::arg("max") = s.max, py::arg("sse") = s.sse);
}

py::array_t<double> values(const std::vector<double>& v) {
  return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

py::array_t<std::int64_t> index_pairs(const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  py::array_t<std::int64_t> a({static_cast<py::ssize_t>(pairs.size()), py::ssize_t{2}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    r(static_cast<py::ssize_t>(i), 0) = static_cast<std::int64_t>(pairs[i].first);
    r(static_cast<py::ssize_t>(i), 1) = static_cast<std::int64_t>(pairs[i].second);
  }
  return a;
}

void describe(py::dict& d, const char* key, const LoadedTrajectory& t) {
  d[fmt::format("{}_format", key).c_str()] = t.format;
  d[fmt::format("{}_poses", key).c_str()] = t.poses.size();
}

py::object eval_ate(py::handle reference, py::handle estimate, const std::string& format,
                    const std::string& align, double max_dt, double offset) {
  check_trajectory_format(format);
  AteOptions o;
  o.association = {max_dt, offset};
  o.alignment = parse_trajectory_alignment(align);
  TrajectoryArg ref_arg = trajectory_arg(reference, "reference");
  TrajectoryArg est_arg = trajectory_arg(estimate, "estimate");
  LoadedTrajectory ref, est;
  AteEvaluation e;
  {
    py::gil_scoped_release release;
    ref = load(std::move(ref_arg), format);
    est = load(std::move(est_arg), format);
    e = evaluate_ate(ref.poses, est.poses, o);
  }
  const AteResult& r = e.result;
  py::dict d;
  d["metric"] = "ate";
  describe(d, "reference", ref);
  describe(d, "estimate", est);
  d["pairs"] = r.association.pairs.size();
  const Eigen::Vector3d t = r.transform.T_reference_estimate.translation();
  const Eigen::Quaterniond& q = r.transform.T_reference_estimate.quaternion();
  d["alignment"] = py::dict(
      py::arg("method") = std::string(to_string(o.alignment)), py::arg("scale") = r.transform.scale,
      py::arg("translation") = std::vector<double>{t.x(), t.y(), t.z()},
      py::arg("quaternion_xyzw") = std::vector<double>{q.x(), q.y(), q.z(), q.w()},
      py::arg("position_spread_m") = r.position_spread);
  d["T_reference_estimate"] = r.transform.T_reference_estimate;
  d["translation_m"] = stats(r.translation);
  d["rotation_rad"] = stats(r.rotation);
  d["pair_indices"] = index_pairs(r.association.pairs);
  d["times"] = values(r.times);
  d["translation_errors"] = values(r.translation_errors);
  d["rotation_errors"] = values(r.rotation_errors);
  std::vector<StampedPose3> aligned;
  for (std::size_t k = 0; k < r.aligned_estimate.size(); ++k)
    aligned.push_back({est.poses[r.association.pairs[k].second].time, r.aligned_estimate[k]});
  d["aligned_estimate"] = tum_rows(aligned);
  d["issues"] = issue_list(e.issues);
  return namespace_of(d);
}

py::object eval_rpe(py::handle reference, py::handle estimate, const std::string& format,
                    double delta, const std::string& unit, const std::string& align, double max_dt,
                    double offset) {
  check_trajectory_format(format);
  RpeOptions o;
  o.association = {max_dt, offset};
  o.delta = delta;
  o.unit = parse_rpe_unit(unit);
  const TrajectoryAlignment alignment = parse_trajectory_alignment(align);
  TrajectoryArg ref_arg = trajectory_arg(reference, "reference");
  TrajectoryArg est_arg = trajectory_arg(estimate, "estimate");
  LoadedTrajectory ref, est;
  RpeEvaluation e;
  {
    py::gil_scoped_release release;
    ref = load(std::move(ref_arg), format);
    est = load(std::move(est_arg), format);
    e = evaluate_rpe(ref.poses, est.poses, o, alignment);
  }
  const RpeResult& r = e.result;
  py::dict d;
  d["metric"] = "rpe";
  describe(d, "reference", ref);
  describe(d, "estimate", est);
  d["pairs"] = r.association.pairs.size();
  d["delta"] = delta;
  d["unit"] = std::string(to_string(o.unit));
  d["scale"] = e.scale;
  d["intervals"] = r.intervals.size();
  d["translation_m"] = stats(r.translation);
  d["rotation_rad"] = stats(r.rotation);
  d["pair_indices"] = index_pairs(r.association.pairs);
  d["interval_indices"] = index_pairs(r.intervals);
  d["times"] = values(r.times);
  d["translation_errors"] = values(r.translation_errors);
  d["rotation_errors"] = values(r.rotation_errors);
  d["issues"] = issue_list(e.issues);
  return namespace_of(d);
}

py::object eval_relations(py::handle estimate, py::handle relations, const std::string& format,
                          double max_dt, const std::optional<Path>& log) {
  check_trajectory_format(format);
  RelationOptions o;
  o.max_time_difference = max_dt;
  TrajectoryArg est_arg = trajectory_arg(estimate, "estimate");
  RelationsArg rel_arg = relations_arg(relations);
  LoadedTrajectory est;
  RelationEvaluation e;
  {
    py::gil_scoped_release release;
    est = load(std::move(est_arg), format);
    std::vector<PoseRelation> rel =
        rel_arg.path ? read_relations(rel_arg.path->string()) : std::move(rel_arg.rows);
    std::optional<std::vector<ClockPair>> clock;
    if (log) clock = carmen_log_clock(log->string());
    e = evaluate_relations(est.poses, std::move(rel), o, clock);
  }
  const RelationResult& r = e.result;
  py::dict d;
  d["metric"] = "relations";
  describe(d, "estimate", est);
  d["relations"] = r.relations;
  d["used"] = r.used;
  d["translation_m"] = stats(r.translation);
  d["translation_squared_m2"] = stats(r.translation_squared);
  d["rotation_rad"] = stats(r.rotation);
  d["rotation_squared_rad2"] = stats(r.rotation_squared);
  d["translation_errors"] = values(r.translation_errors);
  d["rotation_errors"] = values(r.rotation_errors);
  d["missing_times"] = values(r.missing_times);
  d["issues"] = issue_list(e.issues);
  return namespace_of(d);
}

}  // namespace

void bind_eval(py::module_& m) {
  m.def("eval_ate", &eval_ate, py::arg("reference"), py::arg("estimate"), py::arg("format") = "auto",
        py::arg("align") = "se3", py::arg("max_dt") = 0.01, py::arg("offset") = 0.0,
        "Absolute trajectory error of `estimate` against `reference` after alignment (se3, se2, "
        "sim3, none), as `rove eval ate`. Each trajectory is a file (TUM, KITTI, g2o/TORO "
        "vertices; `format` auto, tum, kitti or graph) or a numpy array of TUM rows (N, 8) or "
        "rows t x y theta (N, 4). max_dt: largest time difference of a pair, s; offset: added "
        "to the estimate's times, s.");
  m.def("eval_rpe", &eval_rpe, py::arg("reference"), py::arg("estimate"), py::arg("format") = "auto",
        py::arg("delta") = 1.0, py::arg("unit") = "frames", py::arg("align") = "none",
        py::arg("max_dt") = 0.01, py::arg("offset") = 0.0,
        "Relative pose error over `delta` frames, m or s (`unit`), as `rove eval rpe`; "
        "align='sim3' scales the estimate by its Sim(3) alignment (monocular). Trajectories as "
        "for eval_ate.");
  m.def("eval_relations", &eval_relations, py::arg("estimate"), py::arg("relations"),
        py::arg("format") = "auto", py::arg("max_dt") = 1e-3, py::arg("log") = py::none(),
        "Relation error (Kümmerle et al. 2009) of `estimate` on Freiburg relations (a file, or "
        "(N, 8) rows t1 t2 x y z roll pitch yaw), as `rove eval relations`; log: the CARMEN log "
        "the estimate was computed from, whose clock takes the relations' times to the "
        "estimate's.");
}

}  // namespace rove::python
