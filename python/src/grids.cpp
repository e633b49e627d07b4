// rove.OccupancyGrid (rove/maps/occupancy_grid.h, 8-bit log-odds cells as
// MRPT). `cells` is a numpy view of the C++ cells (rows = y, columns = x;
// no copy) whose base is the Python grid; the grid's size cannot change
// from Python, so the view never dangles.

#include <fmt/format.h>
#include <pybind11/eigen.h>

#include "bindings.h"
#include "rove/maps/occupancy_grid.h"

namespace rove::python {

namespace {

py::array_t<float> probability_image(const OccupancyGrid& g, bool occupancy) {
  py::array_t<float> a(
      {static_cast<py::ssize_t>(g.size_y()), static_cast<py::ssize_t>(g.size_x())});
  auto r = a.mutable_unchecked<2>();
  for (std::uint32_t y = 0; y < g.size_y(); ++y)
    for (std::uint32_t x = 0; x < g.size_x(); ++x) {
      const float p = g.free_probability(static_cast<int>(x), static_cast<int>(y));
      r(y, x) = occupancy ? 1.0f - p : p;
    }
  return a;
}

OccupancyGrid from_probabilities(py::handle prob, double x_min, double y_min, double resolution) {
  if (!py::isinstance<py::array>(prob))
    type_error("argument 'free_probability': expected a 2-D numpy array (rows = y)");
  const py::array a = py::reinterpret_borrow<py::array>(prob);
  if (a.ndim() != 2 || a.shape(0) == 0 || a.shape(1) == 0)
    value_error(
        "argument 'free_probability': expected a non-empty 2-D array (rows = y, columns = x)");
  const auto m = matrix_arg(prob, "free_probability", a.shape(1), true);
  if (!(resolution > 0) || !std::isfinite(resolution) || !std::isfinite(x_min) ||
      !std::isfinite(y_min))
    value_error(fmt::format("expected finite x_min, y_min and resolution > 0, got {}, {}, {}",
                            x_min, y_min, resolution));
  const auto nx = static_cast<std::uint32_t>(m.cols()), ny = static_cast<std::uint32_t>(m.rows());
  const auto res = static_cast<float>(resolution);
  OccupancyGrid g;
  g.assign(static_cast<float>(x_min), static_cast<float>(x_min) + res * static_cast<float>(nx),
           static_cast<float>(y_min), static_cast<float>(y_min) + res * static_cast<float>(ny), res,
           nx, ny, std::vector<std::int8_t>(std::size_t{nx} * ny, 0));
  for (std::uint32_t y = 0; y < ny; ++y)
    for (std::uint32_t x = 0; x < nx; ++x) {
      const double p = m(y, x);
      if (!(p >= 0 && p <= 1))
        value_error(fmt::format("argument 'free_probability': cell ({}, {}) = {} is not in [0, 1]",
                                y, x, p));
      g.set_free_probability(static_cast<int>(x), static_cast<int>(y), static_cast<float>(p));
    }
  g.set_empty(false);
  return g;
}

}  // namespace

void bind_grids(py::module_& m) {
  py::class_<OccupancyGrid>(m, "OccupancyGrid",
                            "A 2D occupancy grid (MRPT's cells: int8 log-odds of being free). "
                            "Cell (row y, column x) covers [x_min + x·res, x_min + (x+1)·res) × "
                            "[y_min + y·res, ...).")
      .def(py::init<>(), "MRPT's default grid: [-20, 20] x [-20, 20] m, 5 cm cells, all unknown.")
      .def(py::init<float, float, float, float, float, float>(), py::arg("x_min"), py::arg("x_max"),
           py::arg("y_min"), py::arg("y_max"), py::arg("resolution"), py::arg("p_free") = 0.5f,
           "A grid over [x_min, x_max] × [y_min, y_max] (m) of square cells, all at p_free.")
      .def_static("from_free_probability", &from_probabilities, py::arg("free_probability"),
                  py::arg("x_min"), py::arg("y_min"), py::arg("resolution"),
                  "A grid whose cells hold the probabilities of a 2-D array (rows = y), values "
                  "in [0, 1], lower-left corner at (x_min, y_min).")
      .def_property_readonly("size_x", &OccupancyGrid::size_x, "Cells along x (columns).")
      .def_property_readonly("size_y", &OccupancyGrid::size_y, "Cells along y (rows).")
      .def_property_readonly("x_min", &OccupancyGrid::x_min)
      .def_property_readonly("x_max", &OccupancyGrid::x_max)
      .def_property_readonly("y_min", &OccupancyGrid::y_min)
      .def_property_readonly("y_max", &OccupancyGrid::y_max)
      .def_property_readonly("resolution", &OccupancyGrid::resolution, "Cell side, m.")
      .def_property_readonly(
          "shape", [](const OccupancyGrid& g) { return py::make_tuple(g.size_y(), g.size_x()); })
      .def_property_readonly(
          "cells",
          [](py::object self) {
            auto& g = self.cast<OccupancyGrid&>();
            const std::span<std::int8_t> c = g.mutable_cells();
            return py::array_t<std::int8_t>(
                {static_cast<py::ssize_t>(g.size_y()), static_cast<py::ssize_t>(g.size_x())},
                c.data(), self);
          },
          "(size_y, size_x) int8 view of the log-odds cells (writable; no copy).")
      .def(
          "free_probability", [](const OccupancyGrid& g) { return probability_image(g, false); },
          "(size_y, size_x) float32 array of p(free) (computed).")
      .def(
          "occupancy", [](const OccupancyGrid& g) { return probability_image(g, true); },
          "(size_y, size_x) float32 array of p(occupied) (computed).")
      .def("free_probability_at", &OccupancyGrid::free_probability_at, py::arg("x"), py::arg("y"),
           "p(free) of the cell holding world point (x, y); 0.5 outside.")
      .def(
          "cell_of",
          [](const OccupancyGrid& g, double x, double y) {
            return py::make_tuple(g.y_to_idx(y), g.x_to_idx(x));
          },
          py::arg("x"), py::arg("y"), "(row, column) of world point (x, y) (may be outside).")
      .def(py::pickle(
          [](const OccupancyGrid& g) {
            const auto c = g.cells();
            return py::make_tuple(g.x_min(), g.x_max(), g.y_min(), g.y_max(), g.resolution(),
                                  g.size_x(), g.size_y(),
                                  py::bytes(reinterpret_cast<const char*>(c.data()), c.size()));
          },
          [](const py::tuple& t) {
            if (t.size() != 8) value_error("OccupancyGrid: pickled state of the wrong size");
            const std::string cells = t[7].cast<std::string>();
            OccupancyGrid g;
            g.assign(t[0].cast<float>(), t[1].cast<float>(), t[2].cast<float>(), t[3].cast<float>(),
                     t[4].cast<float>(), t[5].cast<std::uint32_t>(), t[6].cast<std::uint32_t>(),
                     std::vector<std::int8_t>(cells.begin(), cells.end()));
            g.set_empty(false);
            return g;
          }))
      .def(
          "_cells_address",
          [](OccupancyGrid& g) { return reinterpret_cast<std::uintptr_t>(g.cells().data()); },
          "Address of the C++ cell buffer (tests prove the view shares it).")
      .def("__repr__", [](const OccupancyGrid& g) {
        return fmt::format(
            "rove.OccupancyGrid({} x {} cells of {:g} m, x [{:g}, {:g}], y [{:g}, {:g}])",
            g.size_x(), g.size_y(), g.resolution(), g.x_min(), g.x_max(), g.y_min(), g.y_max());
      });
}

}  // namespace rove::python
