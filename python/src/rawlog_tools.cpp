// Rawlog conversion as a library call: rove.rawlog_convert, what `rove
// rawlog convert` runs (convert_rawlog of rove/io/rawlog_tools.h; to a ROS
// bag, write_bag of rove/ros/bag_writer.h when rove was built with the ROS
// adapter, which also makes every reader of the extension read bags).

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "rove/core/files.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/rawlog_tools.h"
#ifndef ROVE_PYTHON_ROS
#define ROVE_PYTHON_ROS 0
#endif
#if ROVE_PYTHON_ROS
#include "rove/ros/bag_reader.h"
#include "rove/ros/bag_writer.h"
#endif

namespace rove::python {

namespace {

bool is_bag_path(const std::string& path) { return path.size() >= 4 && path.compare(path.size() - 4, 4, ".bag") == 0; }

py::object rawlog_convert(const Path& input, const Path& output, std::optional<int> layout, bool gzip,
                          std::optional<float> max_range, const std::vector<std::string>& topics,
                          const std::string& compression, py::object on_progress) {
  AnyRawlogOptions read;
  if (max_range) {
    if (!(*max_range > 0)) throw InvalidArgument(fmt::format("max_range = {}: expected a positive range, m", *max_range));
    read.carmen.log.flaser_max_range = *max_range;
  }
  read.bag.topics = topics;
  if (layout && *layout != 1 && *layout != 2)
    throw InvalidArgument(fmt::format("layout = {}: expected 1 (actions + sensory frames) or 2 (observations)", *layout));
  if (compression != "none" && compression != "bz2" && compression != "lz4")
    throw InvalidArgument(fmt::format("compression '{}': expected none, bz2 or lz4", printable(compression)));
  check_regular_input(input, "input");
  StepHook hook(on_progress);
  const RawlogProgressFn progress = [&](const AnyRawlogReader& reader) {
    hook([&] { return py::object(py::dict(py::arg("position") = reader.position())); });
  };
  py::dict d;
  if (is_bag_path(output.string())) {
#if ROVE_PYTHON_ROS
    BagWriteOptions o;
    o.compression = compression == "none" ? BagCompression::None
                    : compression == "bz2" ? BagCompression::Bz2
                                            : BagCompression::Lz4;
    o.read = read;
    const BagWriteResult w =
        run_without_gil(hook, [&] { return write_bag(input.string(), output.string(), o, progress); });
    std::uint64_t written = 0;
    std::map<std::string, std::uint64_t> kept;
    for (const auto& [topic, n] : w.messages_by_topic) {
      kept["messages on " + topic] = n;
      written += n;
    }
    d["input_format"] = std::string(to_string(w.input_format));
    d["entries_in"] = w.entries_in;
    d["entries_out"] = written;
    d["kept"] = kept;
    d["messages_by_topic"] = w.messages_by_topic;
    d["dropped"] = w.dropped;
    d["reader_skipped"] = std::vector<std::string>{};
    return namespace_of(d);
#else
    throw Error(fmt::format("{}: writing ROS bags needs the rove::ros adapter, which this build lacks",
                            printable(output.string())));
#endif
  }
  ConvertOptions o;
  if (layout == 1) o.layout = RawlogLayout::ActionsSensoryFrames;
  if (layout == 2) o.layout = RawlogLayout::Observations;
  o.read = read;
  o.write.gzip = gzip;
  const RawlogJobResult r =
      run_without_gil(hook, [&] { return convert_rawlog(input.string(), output.string(), o, progress); });
  d["input_format"] = std::string(to_string(r.input_format));
  d["entries_in"] = r.entries_in;
  d["entries_out"] = r.entries_out;
  d["kept"] = r.kept;
  d["dropped"] = r.dropped;
  d["reader_skipped"] = r.reader_skipped;
  return namespace_of(d);
}

}  // namespace

void bind_rawlog_tools(py::module_& m) {
#if ROVE_PYTHON_ROS
  register_bag_reader();  // every reader of the extension (read_rawlog, the pipelines) reads ROS bags
#endif
  m.def("_has_ros", [] { return ROVE_PYTHON_ROS != 0; }, "Whether rove was built with the ROS adapter.");
  m.def("rawlog_convert", &rawlog_convert, py::arg("input"), py::arg("output"), py::arg("layout") = py::none(),
        py::arg("gzip") = true, py::arg("max_range") = py::none(), py::arg("topics") = std::vector<std::string>{},
        py::arg("compression") = "lz4", py::arg("on_progress") = py::none(),
        "Converts a rove or MRPT rawlog, a CARMEN log or a ROS bag to a rove rawlog (gzip unless "
        "gzip=False; layout 1 or 2, default the input's), or to a ROS bag when `output` ends in .bag "
        "(chunk compression none, bz2, lz4), as `rove rawlog convert`: what was kept and dropped per "
        "class. max_range: CARMEN logs' laser range when the log states none, m; topics: the bag "
        "topics to read. on_progress(dict) after each entry (position: bytes read).");
}

}  // namespace rove::python
