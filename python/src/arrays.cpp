// Conversions from Python arguments to rove's containers, and the step hook
// of the long runs (see bindings.h).

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "bindings.h"
#include "rove/maps/point_cloud.h"

namespace rove::python {

namespace {

std::string type_name(py::handle obj) {
  return py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>();
}

// The array `obj` checked for type, rank, columns and layout; dtype checked
// by the caller.
py::array checked_array(py::handle obj, const char* name, py::ssize_t cols, const char* expected) {
  if (!py::isinstance<py::array>(obj))
    type_error(fmt::format("argument '{}': expected {}, got {}", name, expected, type_name(obj)));
  py::array a = py::reinterpret_borrow<py::array>(obj);
  if (a.ndim() != 2 || a.shape(1) != cols) {
    std::string shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i)
      shape += fmt::format("{}{}", i ? ", " : "", a.shape(i));
    value_error(fmt::format("argument '{}': expected shape (N, {}), got ({}{})", name, cols, shape,
                            a.ndim() == 1 ? "," : ""));
  }
  if (!(a.flags() & py::array::c_style))
    value_error(
        fmt::format("argument '{}': the array is not C-contiguous (use "
                    "numpy.ascontiguousarray)",
                    name));
  return a;
}

[[noreturn]] void non_finite(const char* name, py::ssize_t row, const double* v, int cols) {
  std::string values;
  for (int c = 0; c < cols; ++c) values += fmt::format("{}{}", c ? ", " : "", v[c]);
  value_error(fmt::format("argument '{}': row {} is not finite ({})", name, row, values));
}

// True for a native-byte-order floating-point dtype of `bytes` bytes (by
// value: equal dtypes need not be the same object, e.g. after unpickling).
bool is_native_float(const py::dtype& d, py::ssize_t bytes) {
  return d.kind() == 'f' && d.itemsize() == bytes && d.attr("isnative").cast<bool>();
}

}  // namespace

PointsArg points_arg(py::handle obj, const char* name, bool require_finite) {
  PointsArg out;
  out.keep = py::reinterpret_borrow<py::object>(obj);
  if (py::isinstance<PointCloud>(obj)) {
    out.points = obj.cast<const PointCloud&>().points();
    return out;
  }
  const py::array a = checked_array(obj, name, 3,
                                    "a numpy array of shape (N, 3) (float32 or float64) or a "
                                    "rove.PointCloud");
  const auto n = static_cast<std::size_t>(a.shape(0));
  if (is_native_float(a.dtype(), 4) &&
      reinterpret_cast<std::uintptr_t>(a.data()) % alignof(float) == 0) {
    out.points = {static_cast<const Eigen::Vector3f*>(a.data()), n};
  } else if (is_native_float(a.dtype(), 8)) {
    const auto* d = static_cast<const double*>(a.data());
    out.converted.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      out.converted[i] = Eigen::Vector3d(d[3 * i], d[3 * i + 1], d[3 * i + 2]).cast<float>();
    out.points = out.converted;
  } else {
    type_error(
        fmt::format("argument '{}': expected dtype float32 or float64 (native byte "
                    "order), got {}",
                    name, py::str(a.dtype()).cast<std::string>()));
  }
  if (require_finite) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!out.points[i].allFinite()) {
        const Eigen::Vector3d v = out.points[i].cast<double>();
        non_finite(name, static_cast<py::ssize_t>(i), v.data(), 3);
      }
    }
  }
  return out;
}

Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> matrix_arg(
    py::handle obj, const char* name, Eigen::Index cols, bool require_finite) {
  const py::array a =
      checked_array(obj, name, cols, fmt::format("a numpy array of shape (N, {})", cols).c_str());
  if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    type_error(fmt::format("argument '{}': expected a numeric dtype, got {}", name,
                           py::str(a.dtype()).cast<std::string>()));
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  const Eigen::Index n = a.shape(0);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(n, cols);
  std::copy(d.data(), d.data() + n * cols, m.data());
  if (require_finite)
    for (Eigen::Index i = 0; i < n; ++i)
      if (!m.row(i).allFinite()) non_finite(name, i, m.row(i).data(), static_cast<int>(cols));
  return m;
}

py::object namespace_of(const py::dict& d) {
  return py::module_::import("types").attr("SimpleNamespace")(**d);
}

py::array_t<double> tum_rows(const std::vector<StampedPose3>& poses) {
  py::array_t<double> a({static_cast<py::ssize_t>(poses.size()), py::ssize_t{8}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto k = static_cast<py::ssize_t>(i);
    const Eigen::Vector3d& t = poses[i].pose.translation();
    const Eigen::Quaterniond q(poses[i].pose.rotation().matrix());
    const double row[8] = {poses[i].time, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int c = 0; c < 8; ++c) r(k, c) = row[c];
  }
  return a;
}

void StepHook::operator()(const std::function<py::object()>& make) {
  if (error_) throw CallbackFailed();
  py::gil_scoped_acquire gil;
  try {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (callback_ && !callback_.is_none()) callback_(make());
  } catch (py::error_already_set& e) {
    error_.emplace(std::move(e));
  }
  if (error_) throw CallbackFailed();
}

void StepHook::rethrow_if_failed() {
  if (!error_) return;
  py::error_already_set e = std::move(*error_);
  error_.reset();
  throw e;
}

}  // namespace rove::python
