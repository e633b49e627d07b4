// rove.PointCloud (rove/maps/point_cloud.h). The cloud's storage is C++'s;
// `points`, `normals`, `colors` and `intensities` are numpy views of it (no
// copy) whose base is the Python cloud, so a view keeps the cloud alive. The
// number of points is fixed once built (no call changes it), so a view never
// dangles. Building a cloud from numpy copies into C++-owned storage;
// functions that only read points (rove.align, ...) take numpy arrays in
// place instead (bindings.h, points_arg).

#include <fmt/format.h>
#include <pybind11/eigen.h>

#include "bindings.h"
#include "rove/maps/point_cloud.h"
#include "rove/maps/voxel_grid.h"
#include "rove/math/se3.h"

namespace rove::python {

namespace {

// Copies an optional (N, cols) array into `dst` (N entries of `cols`
// values of T), after checking its shape against the cloud's size.
template <typename T, typename Dst>
void fill_channel(py::handle src, const char* name, std::size_t n, int cols, Dst dst) {
  if (src.is_none()) return;
  const auto m = matrix_arg(src, name, cols, std::is_floating_point_v<T>);
  if (static_cast<std::size_t>(m.rows()) != n)
    value_error(fmt::format("argument '{}': {} rows for {} points", name, m.rows(), n));
  for (std::size_t i = 0; i < n; ++i) dst(i, m.row(static_cast<Eigen::Index>(i)));
}

PointCloud make_cloud(py::handle points, py::handle normals, py::handle colors,
                      py::handle intensities) {
  const PointsArg p = points_arg(points, "points", false);
  PointCloud c(std::vector<Eigen::Vector3f>(p.points.begin(), p.points.end()));
  const std::size_t n = c.size();
  PointChannels ch = PointChannels::None;
  if (!normals.is_none()) ch = ch | PointChannels::Normal;
  if (!colors.is_none()) ch = ch | PointChannels::Color;
  if (!intensities.is_none()) ch = ch | PointChannels::Intensity;
  c.set_channels(ch);
  fill_channel<float>(normals, "normals", n, 3, [&](std::size_t i, const auto& r) {
    c.normals_mut()[i] = r.transpose().template cast<float>();
  });
  fill_channel<std::uint8_t>(colors, "colors", n, 3, [&](std::size_t i, const auto& r) {
    for (int k = 0; k < 3; ++k)
      if (!(r[k] >= 0 && r[k] <= 255))
        value_error(fmt::format("argument 'colors': row {} has {} outside 0..255", i, r[k]));
    c.colors_mut()[i] = {static_cast<std::uint8_t>(r[0]), static_cast<std::uint8_t>(r[1]),
                         static_cast<std::uint8_t>(r[2])};
  });
  if (!intensities.is_none()) {
    // A 1-D array of N values: viewed as (N, 1) for the common checks.
    py::array a = py::isinstance<py::array>(intensities)
                      ? py::reinterpret_borrow<py::array>(intensities)
                      : py::array();
    if (a && a.ndim() == 1) a = a.attr("reshape")(-1, 1);
    fill_channel<float>(
        a ? py::handle(a) : intensities, "intensities", n, 1,
        [&](std::size_t i, const auto& r) { c.intensities_mut()[i] = static_cast<float>(r[0]); });
  }
  return c;
}

}  // namespace

void bind_clouds(py::module_& m) {
  py::class_<PointCloud>(m, "PointCloud",
                         "3D points (float32, meters) with optional normals, colors and "
                         "intensities. Arrays returned are views of the cloud (no copy).")
      .def(py::init(&make_cloud), py::arg("points"), py::arg("normals") = py::none(),
           py::arg("colors") = py::none(), py::arg("intensities") = py::none(),
           "A cloud from an (N, 3) array (copied; float32 or float64), with optional (N, 3) "
           "normals, (N, 3) colors 0..255 and (N,) intensities.")
      .def("__len__", &PointCloud::size)
      .def_property_readonly(
          "points",
          [](py::object self) {
            auto& c = self.cast<PointCloud&>();
            return view_array<float>(c.points_mut().data()->data(), c.size(), 3, self, true);
          },
          "(N, 3) float32 view of the coordinates (writable; no copy).")
      .def_property_readonly(
          "normals",
          [](py::object self) -> py::object {
            auto& c = self.cast<PointCloud&>();
            if (!c.has_normals()) return py::none();
            return view_array<float>(c.normals_mut().data()->data(), c.size(), 3, self, true);
          },
          "(N, 3) float32 view of the normals, or None.")
      .def_property_readonly(
          "colors",
          [](py::object self) -> py::object {
            auto& c = self.cast<PointCloud&>();
            if (!c.has_colors()) return py::none();
            static_assert(sizeof(Rgb8) == 3);
            return view_array<std::uint8_t>(&c.colors_mut().data()->r, c.size(), 3, self, true);
          },
          "(N, 3) uint8 view of the colors (r, g, b), or None.")
      .def_property_readonly(
          "intensities",
          [](py::object self) -> py::object {
            auto& c = self.cast<PointCloud&>();
            if (!c.has_intensity()) return py::none();
            return view_array<float>(c.intensities_mut().data(), c.size(), 0, self, true);
          },
          "(N,) float32 view of the intensities, or None.")
      .def(
          "bounding_box",
          [](const PointCloud& c) {
            const BoundingBox3 b = c.bounding_box();
            return py::make_tuple(b.min.cast<double>(), b.max.cast<double>());
          },
          "(min, max) corners of the finite points; min > max when there is none.")
      .def("count_finite", &PointCloud::count_finite, "Points whose coordinates are all finite.")
      .def(
          "voxel_downsample",
          [](const PointCloud& c, double leaf) {
            if (!(leaf > 0) || !std::isfinite(leaf))
              value_error(
                  fmt::format("argument 'leaf': expected a finite size > 0 m, got {}", leaf));
            py::gil_scoped_release release;
            return voxel_downsample(c, static_cast<float>(leaf));
          },
          py::arg("leaf"), "A new cloud: one point per occupied voxel of side `leaf` (m).")
      .def(
          "transformed",
          [](const PointCloud& c, const SE3d& T) {
            PointCloud out = c;
            const Eigen::Matrix3f R = T.rotation_matrix().cast<float>();
            const Eigen::Vector3f t = T.translation().cast<float>();
            for (auto& p : out.points_mut()) p = R * p + t;
            if (out.has_normals())
              for (auto& nrm : out.normals_mut()) nrm = R * nrm;
            return out;
          },
          py::arg("T"), "A new cloud with points (and normals) moved by T.")
      .def(
          "copy", [](const PointCloud& c) { return PointCloud(c); }, "An independent copy.")
      .def(py::pickle(
          [](py::object self) {  // copies of the arrays: the state must not share memory
            const auto copy = [&](const char* name) -> py::object {
              py::object a = self.attr(name);
              return a.is_none() ? a : a.attr("copy")();
            };
            return py::make_tuple(copy("points"), copy("normals"), copy("colors"),
                                  copy("intensities"));
          },
          [](const py::tuple& t) {
            if (t.size() != 4) value_error("PointCloud: pickled state of the wrong size");
            return make_cloud(t[0], t[1], t[2], t[3]);
          }))
      .def(
          "_points_address",
          [](PointCloud& c) { return reinterpret_cast<std::uintptr_t>(c.points_mut().data()); },
          "Address of the C++ coordinate buffer (tests prove the views share it).")
      .def("__repr__", [](const PointCloud& c) {
        return fmt::format("rove.PointCloud({} points{}{}{})", c.size(),
                           c.has_normals() ? ", normals" : "", c.has_colors() ? ", colors" : "",
                           c.has_intensity() ? ", intensities" : "");
      });
}

}  // namespace rove::python
