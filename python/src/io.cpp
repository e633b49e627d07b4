// File formats from Python: PCD, PLY (rove/io/pcd.h, ply.h), ROS map.yaml
// (rove/io/grid_image.h) and rawlogs of every kind rove reads
// (rove/io/any_rawlog.h). Errors are rove's (ParseError naming the file and
// offset or line, IoError naming the path).

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <memory>

#include "bindings.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/grid_image.h"
#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/lie_conversion.h"

namespace rove::python {

namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.rfind('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

PcdFormat pcd_format(const std::string& name) {
  if (name == "ascii") return PcdFormat::Ascii;
  if (name == "binary") return PcdFormat::Binary;
  if (name == "binary_compressed") return PcdFormat::BinaryCompressed;
  value_error(
      fmt::format("argument 'format': '{}' is not ascii, binary or binary_compressed", name));
}

PlyFormat ply_format(const std::string& name) {
  if (name == "ascii") return PlyFormat::Ascii;
  if (name == "binary_little_endian") return PlyFormat::BinaryLittleEndian;
  if (name == "binary_big_endian") return PlyFormat::BinaryBigEndian;
  value_error(fmt::format(
      "argument 'format': '{}' is not ascii, binary_little_endian or binary_big_endian", name));
}

PointCloud read_cloud(const Path& file) {
  const std::string path = file.string();
  const std::string e = lower_extension(path);
  py::gil_scoped_release release;
  if (e == "pcd") return read_pcd(path);
  if (e == "ply") return read_ply(path);
  throw IoError(path, "unknown point cloud format (expected .pcd or .ply)");
}

/// A whole log in memory (entries shared with the Python objects built from
/// them).
struct PyRawlog {
  AnyRawlog log;
  std::string path;
};

// Every observation of the log, in file order (sensory frames flattened).
std::vector<std::shared_ptr<Observation>> observations_of(const PyRawlog& r) {
  std::vector<std::shared_ptr<Observation>> out;
  const auto add = [&](const std::shared_ptr<const Observation>& o) {
    out.push_back(std::const_pointer_cast<Observation>(o));
  };
  for (const RawlogEntry& e : r.log.entries) {
    if (const auto* f = std::get_if<std::shared_ptr<const SensoryFrame>>(&e)) {
      for (const auto& o : (*f)->observations) add(o);
    } else if (const auto* o = std::get_if<std::shared_ptr<const Observation>>(&e)) {
      add(*o);
    }
  }
  return out;
}

std::string layout_name(RawlogLayout l) {
  switch (l) {
    case RawlogLayout::Empty:
      return "empty";
    case RawlogLayout::ActionsSensoryFrames:
      return "actions-and-frames";
    case RawlogLayout::Observations:
      return "observations";
    case RawlogLayout::Mixed:
      return "mixed";
  }
  return "mixed";
}

void bind_rawlog(py::module_& m) {
  py::class_<Observation, std::shared_ptr<Observation>>(
      m, "Observation", "One sensor reading of a rawlog (its concrete class is a subclass).")
      .def_property_readonly("kind",
                             [](const Observation& o) { return std::string(o.class_name()); })
      .def_property_readonly("sensor_label", [](const Observation& o) { return o.sensor_label; })
      .def_property_readonly(
          "time",
          [](const Observation& o) -> py::object {
            if (!o.timestamp.valid()) return py::none();
            return py::float_(o.timestamp.to_seconds());
          },
          "Seconds since the Unix epoch, or None when unknown.")
      .def_property_readonly("T_robot_sensor",
                             [](const Observation& o) { return to_se3(o.T_robot_sensor); });
  py::class_<RangeScan2D, Observation, std::shared_ptr<RangeScan2D>>(m, "RangeScan2D",
                                                                     "A planar laser scan.")
      .def_property_readonly(
          "ranges",
          [](py::object self) {
            const auto& s = self.cast<const RangeScan2D&>();
            return view_array<float>(s.ranges.data(), s.ranges.size(), 0, self, false);
          },
          "(N,) float32 read-only view of the ranges, m (no copy).")
      .def_property_readonly(
          "valid",
          [](const RangeScan2D& s) {
            py::array_t<bool> a(static_cast<py::ssize_t>(s.valid.size()));
            for (std::size_t i = 0; i < s.valid.size(); ++i)
              a.mutable_at(static_cast<py::ssize_t>(i)) = s.valid[i];
            return a;
          },
          "(N,) bool: the rays that returned.")
      .def_property_readonly("aperture", [](const RangeScan2D& s) { return s.aperture; })
      .def_property_readonly("max_range", [](const RangeScan2D& s) { return s.max_range; })
      .def("angles", &RangeScan2D::ray_angles, "Angle of every ray, sensor frame, rad.")
      .def(
          "points",
          [](const RangeScan2D& s, bool sensor_frame) {
            const auto pts = s.points_2d(sensor_frame ? ScanFrame::Sensor : ScanFrame::Robot);
            py::array_t<double> a({static_cast<py::ssize_t>(pts.size()), py::ssize_t{2}});
            auto r = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < pts.size(); ++i) {
              r(static_cast<py::ssize_t>(i), 0) = pts[i].x();
              r(static_cast<py::ssize_t>(i), 1) = pts[i].y();
            }
            return a;
          },
          py::arg("sensor_frame") = false,
          "(M, 2) points of the rays that returned (robot frame unless sensor_frame).");

  py::class_<PyRawlog, std::shared_ptr<PyRawlog>>(
      m, "Rawlog", "A whole rawlog in memory (rove, MRPT or CARMEN).")
      .def("__len__", [](const PyRawlog& r) { return r.log.entries.size(); })
      .def_property_readonly("format",
                             [](const PyRawlog& r) { return std::string(to_string(r.log.format)); })
      .def_property_readonly("layout", [](const PyRawlog& r) { return layout_name(r.log.layout); })
      .def_property_readonly("path", [](const PyRawlog& r) { return r.path; })
      .def("observations", &observations_of,
           "Every observation in file order (sensory frames flattened).")
      .def("__repr__", [](const PyRawlog& r) {
        return fmt::format("rove.Rawlog('{}', {} entries, {})", r.path, r.log.entries.size(),
                           to_string(r.log.format));
      });
  m.def(
      "read_rawlog",
      [](const Path& path) {
        auto r = std::make_shared<PyRawlog>();
        r->path = path.string();
        py::gil_scoped_release release;
        r->log = load_any_rawlog(r->path);
        return r;
      },
      py::arg("path"), "Reads a whole rove rawlog, MRPT rawlog or CARMEN log.");
}

}  // namespace

void bind_io(py::module_& m) {
  m.def(
      "read_pcd",
      [](const Path& p) {
        py::gil_scoped_release r;
        return read_pcd(p.string());
      },
      py::arg("path"), "Reads a PCD file (ascii, binary, binary_compressed).");
  m.def(
      "read_ply",
      [](const Path& p) {
        py::gil_scoped_release r;
        return read_ply(p.string());
      },
      py::arg("path"), "Reads a PLY file (ascii or binary).");
  m.def("read_cloud", &read_cloud, py::arg("path"), "Reads a .pcd or .ply file (by extension).");
  m.def(
      "write_pcd",
      [](const Path& path, const PointCloud& cloud, const std::string& format) {
        PcdWriteOptions o;
        o.format = pcd_format(format);
        py::gil_scoped_release release;
        write_pcd(path.string(), cloud, o);
      },
      py::arg("path"), py::arg("cloud"), py::arg("format") = "binary_compressed",
      "Writes a PCD file (every channel the cloud has).");
  m.def(
      "write_ply",
      [](const Path& path, const PointCloud& cloud, const std::string& format) {
        PlyWriteOptions o;
        o.format = ply_format(format);
        py::gil_scoped_release release;
        write_ply(path.string(), cloud, o);
      },
      py::arg("path"), py::arg("cloud"), py::arg("format") = "binary_little_endian",
      "Writes a PLY file (every channel the cloud has).");
  m.def(
      "load_ros_map",
      [](const Path& yaml_path) {
        py::gil_scoped_release release;
        return load_ros_map(yaml_path.string()).grid;
      },
      py::arg("yaml_path"), "Reads a ROS map_server map.yaml and its image into a grid.");
  m.def(
      "save_ros_map",
      [](const Path& prefix, const OccupancyGrid& grid, const std::string& mode) {
        GridImageOptions o;
        if (mode == "trinary") {
          o.mode = RosMapMode::Trinary;
        } else if (mode == "scale") {
          o.mode = RosMapMode::Scale;
        } else {
          value_error(fmt::format("argument 'mode': '{}' is not trinary or scale", mode));
        }
        py::gil_scoped_release release;
        const RosMapFiles f = save_ros_map(prefix.string(), grid, o);
        return std::make_pair(f.yaml, f.image);
      },
      py::arg("prefix"), py::arg("grid"), py::arg("mode") = "trinary",
      "Writes <prefix>.png and <prefix>.yaml; returns (yaml path, image path).");
  bind_rawlog(m);
}

}  // namespace rove::python
