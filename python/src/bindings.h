#pragma once
// Shared pieces of the Python bindings (the extension rove._rove): the
// registration functions of each part and the conversions between numpy
// arrays and rove's containers.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/io/trajectory_files.h"
#include "rove/obs/timestamp.h"

namespace rove::python {

namespace py = pybind11;

/// File arguments: str or os.PathLike (pathlib.Path).
using Path = std::filesystem::path;

void bind_errors(py::module_& m);
void bind_geometry(py::module_& m);
void bind_clouds(py::module_& m);
void bind_grids(py::module_& m);
void bind_io(py::module_& m);
void bind_registration(py::module_& m);
void bind_graph(py::module_& m);
void bind_slam(py::module_& m);
void bind_filters(py::module_& m);
void bind_eval(py::module_& m);
void bind_nav(py::module_& m);
void bind_mapping(py::module_& m);
void bind_rawlog_tools(py::module_& m);
/// rove.rgbd_slam, when rove was built with rove::vision (else nothing).
void bind_rgbd(py::module_& m);

/// A numpy array that views `count` rows of `cols` values of type T at
/// `data` (C order; cols == 0: a 1-D array) without copying. `owner` is the
/// array's base: it keeps the memory alive as long as the array lives.
template <typename T>
py::array_t<T> view_array(const T* data, std::size_t count, std::size_t cols, py::handle owner,
                          bool writable) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(count)};
  std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(sizeof(T) * (cols ? cols : 1))};
  if (cols) {
    shape.push_back(static_cast<py::ssize_t>(cols));
    strides.push_back(sizeof(T));
  }
  py::array_t<T> a(shape, strides, data, owner);
  if (!writable)
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// Points taken from a Python argument: a rove.PointCloud (its points, in
/// place) or a C-contiguous numpy array of shape (N, 3) and dtype float32
/// (used in place: no copy) or float64 (converted to float32, the type of
/// rove's clouds). Anything else raises TypeError (not an array, another
/// dtype) or ValueError (shape, layout, a non-finite coordinate when
/// `require_finite`) naming the argument.
struct PointsArg {
  std::span<const Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> converted;  // float64 input, converted
  py::object keep;                         // the Python object viewed
};
PointsArg points_arg(py::handle obj, const char* name, bool require_finite);

/// A copy of the (N, cols) float64-convertible array `obj` (TypeError /
/// ValueError naming `name` for anything else; non-finite values refused
/// when `require_finite`).
Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> matrix_arg(
    py::handle obj, const char* name, Eigen::Index cols, bool require_finite);

/// A types.SimpleNamespace with the items of `d` as attributes (the results
/// of the pipelines: plain values that pickle).
py::object namespace_of(const py::dict& d);

/// An (N, 8) float64 array of TUM rows t x y z qx qy qz qw (seconds,
/// meters, the unit quaternion of T_world_body's rotation).
py::array_t<double> tum_rows(const std::vector<StampedPose3>& poses);

/// Raises TypeError with the message (for use where pybind11 would not).
[[noreturn]] void type_error(const std::string& message);
/// Raises ValueError with the message.
[[noreturn]] void value_error(const std::string& message);

/// An MRPT-style configuration: the file at `config` (None: empty) with
/// `overrides` ({section: {key: value}}; bools as true/false, numbers by
/// their shortest text) set over it. ValueError for an override that is not
/// a dict of dicts.
IniFile load_config(const std::optional<Path>& config, py::handle overrides);

/// The rove issues of a result as a list of (code, message) tuples.
template <typename Issues>
py::list issue_list(const Issues& issues) {
  py::list l;
  for (const auto& i : issues) l.append(py::make_tuple(i.code, i.message));
  return l;
}

/// Seconds of a timestamp, NaN when unknown.
double seconds_of(Timestamp t);

/// A per-step hook for the long runs, called from C++ with the GIL
/// released: takes the GIL, lets Python signal handlers run (Ctrl-C raises
/// KeyboardInterrupt), calls `callback` (if any) with the object `make`
/// builds, and releases the GIL again. An exception raised in Python is
/// kept and the run unwound; rethrow_if_failed() raises it again once the
/// run is left.
class StepHook {
 public:
  explicit StepHook(py::object callback) : callback_(std::move(callback)) {}
  /// Called per step; `make` is only called when there is a callback.
  void operator()(const std::function<py::object()>& make);
  /// Re-raises a Python exception kept by operator() (GIL held).
  void rethrow_if_failed();
  /// True when the run must be given up (a Python exception was kept).
  bool failed() const noexcept { return error_.has_value(); }

 private:
  py::object callback_;
  std::optional<py::error_already_set> error_;
};

/// Thrown through the C++ run when a StepHook kept a Python exception (a
/// rove::Error, so that the trace frames added on the way keep its type).
class CallbackFailed : public Error {
 public:
  CallbackFailed() : Error("a Python callback raised an exception") {}
};

/// Runs `run` with the GIL released and `hook` collecting Python errors;
/// re-raises the Python exception of a callback instead of CallbackFailed.
template <typename F>
auto run_without_gil(StepHook& hook, F&& run) {
  try {
    py::gil_scoped_release release;
    return run();
  } catch (const CallbackFailed&) {
    hook.rethrow_if_failed();
    throw;
  }
}

/// An (N, 3) float64 array of (x, y, phi) from poses with x(), y(), phi() or
/// SE2d values (translation and angle).
template <typename Range, typename Get>
py::array_t<double> pose2_rows(const Range& items, Get get) {
  py::array_t<double> a({static_cast<py::ssize_t>(items.size()), py::ssize_t{3}});
  auto r = a.mutable_unchecked<2>();
  py::ssize_t i = 0;
  for (const auto& item : items) {
    const Eigen::Vector3d v = get(item);
    for (int c = 0; c < 3; ++c) r(i, c) = v[c];
    ++i;
  }
  return a;
}

}  // namespace rove::python
