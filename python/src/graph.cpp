// Pose graphs: rove.PoseGraph2D / PoseGraph3D (rove/graph/pose_graph.h),
// g2o / TORO / rove binary files (graph_io.h), the initial guesses
// (initialization.h) and the optimizer (optimizer.h), as `rove graph-slam`
// runs them. Vertices are kept in an ordered map in C++, so their poses come
// out as new numpy arrays (a copy), rows in the order of vertex_ids.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/initialization.h"
#include "rove/graph/optimizer.h"

namespace rove::python {

namespace {

// (x, y, theta) of an SE2 vertex; (x, y, z, qw, qx, qy, qz) of an SE3 one.
Eigen::VectorXd pose_row(const SE2d& T) {
  return Eigen::Vector3d(T.translation().x(), T.translation().y(), T.angle());
}
Eigen::VectorXd pose_row(const SE3d& T) {
  const auto& q = T.quaternion();
  Eigen::VectorXd r(7);
  r << T.translation(), q.w(), q.x(), q.y(), q.z();
  return r;
}

GraphFileFormat graph_format(const std::string& name) {
  if (name == "auto") return GraphFileFormat::Auto;
  if (name == "toro") return GraphFileFormat::Toro;
  if (name == "g2o") return GraphFileFormat::G2o;
  if (name == "binary") return GraphFileFormat::Binary;
  value_error(fmt::format("argument 'format': '{}' is not auto, toro, g2o or binary", name));
}

LinearSolverType linear_solver(const std::string& name) {
  if (name == "auto") return LinearSolverType::Auto;
  if (name == "eigen") return LinearSolverType::Eigen;
  if (name == "cholmod") return LinearSolverType::Cholmod;
  if (name == "block") return LinearSolverType::Block;
  value_error(
      fmt::format("argument 'linear_solver': '{}' is not auto, block, eigen or cholmod", name));
}

template <class G>
void bind_pose_graph(py::module_& m, const char* name, const char* columns) {
  using Pose = typename G::Pose;
  py::class_<G>(m, name, fmt::format("A pose graph; vertex rows are ({}).", columns).c_str())
      .def(py::init<>())
      .def_property_readonly("num_vertices", &G::num_vertices)
      .def_property_readonly("num_edges", &G::num_edges)
      .def_property_readonly(
          "vertex_ids",
          [](const G& g) {
            py::array_t<std::uint64_t> ids(static_cast<py::ssize_t>(g.num_vertices()));
            py::ssize_t i = 0;
            for (const auto& [id, v] : g.vertices()) ids.mutable_at(i++) = id;
            return ids;
          },
          "(N,) uint64 vertex ids, ascending.")
      .def(
          "vertices",
          [](const G& g) {
            py::array_t<double> a({static_cast<py::ssize_t>(g.num_vertices()),
                                   static_cast<py::ssize_t>(Pose::kDof == 3 ? 3 : 7)});
            auto r = a.mutable_unchecked<2>();
            py::ssize_t i = 0;
            for (const auto& [id, v] : g.vertices()) {
              const Eigen::VectorXd row = pose_row(v.pose);
              for (Eigen::Index c = 0; c < row.size(); ++c) r(i, c) = row[c];
              ++i;
            }
            return a;
          },
          fmt::format("(N, k) float64 rows ({}) in the order of vertex_ids (a copy).", columns)
              .c_str())
      .def("pose", &G::pose, py::arg("id"), "The pose of vertex `id` (ValueError if none).")
      .def("add_vertex", &G::add_vertex, py::arg("id"), py::arg("pose"), py::arg("fixed") = false)
      .def(
          "add_edge",
          [](G& g, VertexId from, VertexId to, const Pose& z,
             const std::optional<typename G::Information>& info) {
            return g.add_edge(from, to, z, info.value_or(G::Information::Identity()));
          },
          py::arg("from_id"), py::arg("to_id"), py::arg("measurement"),
          py::arg("information") = py::none(),
          "Adds an edge (measured T_from_to, information in the right tangent); its index.")
      .def(
          "edges",
          [](const G& g) {
            py::array_t<std::uint64_t> a({static_cast<py::ssize_t>(g.num_edges()), py::ssize_t{2}});
            auto r = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < g.num_edges(); ++i) {
              r(static_cast<py::ssize_t>(i), 0) = g.edges()[i].from;
              r(static_cast<py::ssize_t>(i), 1) = g.edges()[i].to;
            }
            return a;
          },
          "(E, 2) uint64: (from, to) of every edge.")
      .def(
          "chi2", [](const G& g) { return compute_chi2(g); }, "χ² of the graph's edges.")
      .def(
          "initialize",
          [](G& g, const std::string& guess) {
            const InitialGuessChoice c = initialize_best(g, parse_initial_guess(guess));
            return std::string(to_string(c.used));
          },
          py::arg("guess") = "auto",
          "Sets the initial poses: auto | as-is | odometry | spanning-tree | chordal (auto: the "
          "better of as-is and chordal by χ²); returns the guess used.")
      .def(
          "optimize",
          [](G& g, const std::string& solver, int max_iterations, int threads,
             const std::string& linear, double function_tolerance) {
            GraphOptimizerOptions o;
            o.solver = parse_graph_solver(solver);
            o.max_iterations = max_iterations;
            o.num_threads = threads;
            o.linear_solver = linear_solver(linear);
            o.function_tolerance = function_tolerance;
            py::gil_scoped_release release;
            return optimize(g, o);
          },
          py::arg("solver") = "dogleg", py::arg("max_iterations") = 100, py::arg("threads") = 1,
          py::arg("linear_solver") = "auto", py::arg("function_tolerance") = 1e-8,
          "Optimizes the graph in place (GIL released); a rove.GraphResult.")
      .def(
          "write",
          [](const G& g, const Path& path, const std::string& format) {
            write_graph(g, path.string(), graph_format(format));
          },
          py::arg("path"), py::arg("format") = "auto",
          "Writes the graph (auto: by extension, .g2o g2o, .rpg binary, else TORO).")
      .def("__repr__", [name](const G& g) {
        return fmt::format("rove.{}({} vertices, {} edges)", name, g.num_vertices(), g.num_edges());
      });
}

py::object read_graph(const Path& file) {
  const std::string path = file.string();
  const GraphDimension d = detect_graph_dimension(path);
  if (d == GraphDimension::ThreeD) {
    py::gil_scoped_release release;
    PoseGraph3D g = read_graph_3d(path);
    py::gil_scoped_acquire gil;
    return py::cast(std::move(g));
  }
  py::gil_scoped_release release;
  PoseGraph2D g = read_graph_2d(path);
  py::gil_scoped_acquire gil;
  return py::cast(std::move(g));
}

}  // namespace

void bind_graph(py::module_& m) {
  py::class_<GraphOptimizerResult>(m, "GraphResult", "What PoseGraph.optimize did.")
      .def_property_readonly(
          "status",
          [](const GraphOptimizerResult& r) { return std::string(to_string(r.termination)); },
          "converged | max-iterations | no-progress | invalid-input | numerical-failure")
      .def_property_readonly("converged", &GraphOptimizerResult::ok)
      .def_property_readonly("improved", &GraphOptimizerResult::improved)
      .def_readonly("message", &GraphOptimizerResult::message)
      .def_readonly("initial_chi2", &GraphOptimizerResult::initial_chi2)
      .def_readonly("final_chi2", &GraphOptimizerResult::final_chi2)
      .def_readonly("iterations", &GraphOptimizerResult::iterations)
      .def_readonly("accepted_steps", &GraphOptimizerResult::accepted_steps)
      .def_property_readonly("issues",
                             [](const GraphOptimizerResult& r) {
                               std::vector<std::string> l;
                               for (const auto& i : r.issues) l.push_back(i.message);
                               return l;
                             })
      .def("__repr__", [](const GraphOptimizerResult& r) {
        return fmt::format("rove.GraphResult({}, chi2 {:.6g} -> {:.6g}, {} iterations)",
                           to_string(r.termination), r.initial_chi2, r.final_chi2, r.iterations);
      });
  bind_pose_graph<PoseGraph2D>(m, "PoseGraph2D", "x, y, theta");
  bind_pose_graph<PoseGraph3D>(m, "PoseGraph3D", "x, y, z, qw, qx, qy, qz");
  m.def("read_graph", &read_graph, py::arg("path"),
        "Reads a 2D or 3D pose graph (TORO .graph, g2o, rove binary; detected from the file).");
}

}  // namespace rove::python
