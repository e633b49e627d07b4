// rove.align: rove/registration/align.h, the registration `rove align`
// runs, on numpy arrays or rove.PointCloud objects. float32 (N, 3) arrays
// are read in place (no copy); the GIL is released while it runs.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "rove/registration/align.h"

namespace rove::python {

namespace {

std::optional<std::vector<double>> voxel_arg(py::handle voxel) {
  if (voxel.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(voxel)) {
    if (voxel.cast<std::string>() == "auto") return std::nullopt;
    value_error(
        fmt::format("argument 'voxel': expected 'auto', a size (m) or a list of sizes, got '{}'",
                    voxel.cast<std::string>()));
  }
  if (py::isinstance<py::float_>(voxel) || py::isinstance<py::int_>(voxel))
    return std::vector<double>{voxel.cast<double>()};
  try {
    return voxel.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    type_error("argument 'voxel': expected 'auto', a size (m) or a list of sizes");
  }
}

py::dict result_dict(const AlignResult& r) {
  py::dict d;
  d["T_target_source"] = r.T_target_source.matrix();
  d["termination"] = std::string(to_string(r.termination));
  d["converged"] = r.ok();
  d["message"] = r.message;
  d["iterations"] = r.iterations;
  d["max_iterations"] = r.iteration_cap;
  d["fitness_m2"] = r.fitness;
  d["goodness"] = r.goodness;
  d["source_points"] = r.source_points;
  d["target_points"] = r.target_points;
  d["voxel"] = r.voxel_sizes;
  d["voxel_auto"] = r.voxel_auto;
  d["levels"] = r.level_messages;
  return d;
}

}  // namespace

void bind_registration(py::module_& m) {
  py::class_<AlignResult>(m, "AlignResult", "What rove.align produced.")
      .def_property_readonly(
          "pose", [](const AlignResult& r) { return r.T_target_source; },
          "T_target_source (rove.SE3): source coordinates into the target's frame.")
      .def_property_readonly(
          "T_target_source", [](const AlignResult& r) { return r.T_target_source.matrix(); },
          "The pose as a 4x4 matrix.")
      .def_property_readonly(
          "status", [](const AlignResult& r) { return std::string(to_string(r.termination)); },
          "Termination: Converged, MaxIterations, Degenerate, "
          "TooFewCorrespondences, InvalidInput, Diverged or Stalled.")
      .def_property_readonly("converged", &AlignResult::ok, "True only when it converged.")
      .def_property_readonly("message", [](const AlignResult& r) { return r.message; })
      .def_property_readonly("iterations", [](const AlignResult& r) { return r.iterations; })
      .def_property_readonly("max_iterations", [](const AlignResult& r) { return r.iteration_cap; })
      .def_property_readonly(
          "fitness", [](const AlignResult& r) { return r.fitness; },
          "Mean squared distance of the final pairs, m².")
      .def_property_readonly("goodness", [](const AlignResult& r) { return r.goodness; })
      .def_property_readonly("source_points", [](const AlignResult& r) { return r.source_points; })
      .def_property_readonly("target_points", [](const AlignResult& r) { return r.target_points; })
      .def_property_readonly("voxel_sizes", [](const AlignResult& r) { return r.voxel_sizes; })
      .def_property_readonly("voxel_auto", [](const AlignResult& r) { return r.voxel_auto; })
      .def_property_readonly("level_messages",
                             [](const AlignResult& r) { return r.level_messages; })
      .def("to_dict", &result_dict,
           "The result as plain Python values (the keys of `rove align --json`).")
      .def("__repr__", [](const AlignResult& r) {
        const auto& t = r.T_target_source.translation();
        return fmt::format(
            "rove.AlignResult({}, t=({:.4f}, {:.4f}, {:.4f}), {} iterations, fitness {:.4g})",
            to_string(r.termination), t.x(), t.y(), t.z(), r.iterations, r.fitness);
      });

  m.def(
      "align",
      [](py::handle source, py::handle target, const std::string& method,
         const std::optional<SE3d>& init, py::handle voxel, double max_distance,
         double distance_factor, std::size_t neighbors, double resolution, int max_iterations,
         int threads) {
        const PointsArg src = points_arg(source, "source", true);
        const PointsArg tgt = points_arg(target, "target", true);
        AlignOptions o;
        o.method = parse_align_method(method);
        o.voxel_sizes = voxel_arg(voxel);
        o.max_distance = max_distance;
        o.distance_factor = distance_factor;
        o.neighbors = neighbors;
        o.ndt_resolution = resolution;
        o.max_iterations = max_iterations;
        o.num_threads = threads;
        py::gil_scoped_release release;
        return align_clouds(tgt.points, src.points, init.value_or(SE3d()), o);
      },
      py::arg("source"), py::arg("target"), py::arg("method") = "gicp",
      py::arg("init") = py::none(), py::arg("voxel") = "auto", py::arg("max_distance") = 1.0,
      py::arg("distance_factor") = 3.0, py::arg("neighbors") = 10, py::arg("resolution") = 1.0,
      py::arg("max_iterations") = 0, py::arg("threads") = 1,
      "Registers `source` onto `target` ((N, 3) float32/float64 arrays of finite points, or "
      "rove.PointCloud) as `rove align` does. method: icp | point-to-plane | gicp | ndt; "
      "init: T_target_source guess (rove.SE3); voxel: 'auto', a leaf (m) or a coarse-to-fine "
      "list; max_distance: ICP gate with one voxel size (m); distance_factor: gate per level "
      "as a multiple of its voxel; neighbors: for normals/covariances; resolution: NDT cell "
      "(m); max_iterations: 0 for the method's cap; threads: 0 for all.");

  m.def(
      "_points_address",
      [](py::handle obj) {
        const PointsArg p = points_arg(obj, "points", false);
        return reinterpret_cast<std::uintptr_t>(p.points.data());
      },
      py::arg("points"),
      "Address of the points C++ reads for this argument (tests prove float32 arrays are "
      "used in place).");
}

}  // namespace rove::python
