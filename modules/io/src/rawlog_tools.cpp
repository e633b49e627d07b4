#include "rove/io/rawlog_tools.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <deque>
#include <memory>
#include <type_traits>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/selection_error.h"
#include "rove/obs/sensory_frame.h"

namespace rove {
namespace {

using ObsPtr = std::shared_ptr<const Observation>;
using FramePtr = std::shared_ptr<const SensoryFrame>;
using ActionsPtr = std::shared_ptr<const ActionCollection>;

const char* kToolName = "rove rawlog";

RoveRawlogWriterOptions with_metadata(RoveRawlogWriterOptions w, const std::string& in,
                                      RawlogFormat format, RawlogLayout layout) {
  w.layout = layout;
  w.metadata.emplace("source", in);
  w.metadata.emplace("source_format", std::string(to_string(format)));
  w.metadata.emplace("tool", kToolName);
  return w;
}

RawlogLayout input_layout(const AnyRawlogReader& reader) {
  // MRPT files declare none: mixed admits whatever they hold.
  return reader.declared_layout().value_or(RawlogLayout::Mixed);
}

void count_entry(std::map<std::string, std::uint64_t>& counts, const RawlogEntry& e) {
  std::visit(
      [&counts](const auto& p) {
        using T = std::remove_const_t<typename std::decay_t<decltype(p)>::element_type>;
        if constexpr (std::is_same_v<T, ActionCollection>) {
          for (const auto& a : p->actions) ++counts[std::string(a->class_name())];
        } else if constexpr (std::is_same_v<T, SensoryFrame>) {
          for (const auto& o : p->observations) ++counts[std::string(o->class_name())];
        } else {
          ++counts[std::string(p->class_name())];
        }
      },
      e);
}

std::optional<Timestamp> entry_time(const RawlogEntry& e) {
  std::optional<Timestamp> t;
  auto add = [&t](Timestamp x) {
    if (x.valid() && (!t || x < *t)) t = x;
  };
  std::visit(
      [&add](const auto& p) {
        using T = std::remove_const_t<typename std::decay_t<decltype(p)>::element_type>;
        if constexpr (std::is_same_v<T, ActionCollection>) {
          for (const auto& a : p->actions) add(a->timestamp);
        } else if constexpr (std::is_same_v<T, SensoryFrame>) {
          for (const auto& o : p->observations) add(o->timestamp);
        } else {
          add(p->timestamp);
        }
      },
      e);
  return t;
}

void finish(RawlogJobResult& r, RoveRawlogWriter& writer) {
  writer.close();
  r.entries_out = writer.entries_written();
}

// Refuses an output that is the input (it would be destroyed before it is
// read).
void check_in_out(const std::string& in, const std::string& out) {
  check_outputs_distinct({std::filesystem::path(in)}, {std::filesystem::path(out)});
}

std::string format_seconds(double s) { return fmt::format("{:.6f}", s); }

// What a log holds, for the message of a selection that found nothing.
struct LogExtent {
  std::uint64_t entries = 0;
  std::optional<double> first_time, last_time;
  void add(const RawlogEntry& e) {
    ++entries;
    if (const auto t = entry_time(e)) {
      const double s = t->to_seconds();
      if (!first_time || s < *first_time) first_time = s;
      if (!last_time || s > *last_time) last_time = s;
    }
  }
  std::string describe(const std::string& in) const {
    std::string d = fmt::format("{} has {} entries", in, entries);
    if (entries > 0) d += fmt::format(" (indices 0..{})", entries - 1);
    if (first_time) {
      d += fmt::format(", times {} .. {} s", format_seconds(*first_time), format_seconds(*last_time));
    } else {
      d += ", none timestamped";
    }
    return d;
  }
};

// A label list for messages: "'LASER' (224), 'LASER_REAR' (12)".
std::string describe_labels(const std::map<std::string, std::uint64_t>& labels) {
  std::string d;
  for (const auto& [label, n] : labels) {
    if (!d.empty()) d += ", ";
    d += fmt::format("'{}' ({})", label, n);
  }
  return d;
}

// Composes consecutive RobotMovement2D actions into one (decimation and
// layout conversion).
struct MovementAccumulator {
  std::optional<RobotMovement2D> total;
  bool any_estimate = false;
  Pose2Gaussian estimate;

  void add(const RobotMovement2D& m) {
    if (!total) {
      total = m;
      any_estimate = m.estimated_pose_change.has_value();
      estimate = m.gaussian();
      return;
    }
    total->odometry_increment = total->odometry_increment + m.odometry_increment;
    // Composition of independent Gaussians (first order), as the poses
    // module propagates covariance.
    estimate = estimate + m.gaussian();
    any_estimate = any_estimate || m.estimated_pose_change.has_value();
    if (m.timestamp.valid()) total->timestamp = m.timestamp;
    if (total->encoder_ticks && m.encoder_ticks) {
      total->encoder_ticks->left += m.encoder_ticks->left;
      total->encoder_ticks->right += m.encoder_ticks->right;
    } else {
      total->encoder_ticks.reset();
    }
    total->velocity = m.velocity;
  }
  std::optional<RobotMovement2D> take() {
    if (total && any_estimate) total->estimated_pose_change = estimate;
    std::optional<RobotMovement2D> out = std::move(total);
    total.reset();
    any_estimate = false;
    return out;
  }
};

// Text output files keyed by sensor label, named as rawlog-edit names them
// (`<out stem>_<label>.txt`; `out` itself when the job ends with a single
// label). Rows go to temporary files beside `out` as they come (constant
// memory); finish() renames them to their names, so an error or Ctrl-C
// leaves no partial file and no older file half-overwritten.
class LabelFiles {
 public:
  LabelFiles(std::string in, std::string out, RawlogJobResult& result)
      : in_(std::move(in)), out_(std::move(out)), result_(result) {
    check_in_out(in_, out_);
  }
  ~LabelFiles() {
    for (auto& f : files_) {
      if (f.file != nullptr) std::fclose(f.file);
      if (!f.committed) {
        std::error_code ec;
        std::filesystem::remove(f.tmp, ec);
      }
    }
  }
  LabelFiles(const LabelFiles&) = delete;
  LabelFiles& operator=(const LabelFiles&) = delete;

  void add_row(const std::string& label, const std::string& header, const std::string& row) {
    Label* l = nullptr;
    for (auto& f : files_) {
      if (f.label == label) l = &f;
    }
    if (l == nullptr) {
      const std::string path = split_name(label);
      for (const auto& f : files_) {
        if (f.path == path) {
          throw IoError(path, fmt::format("sensor labels '{}' and '{}' give the same file name",
                                          f.label, label));
        }
      }
      check_in_out(in_, path);
      const std::filesystem::path tmp = temporary_sibling(out_);
      std::FILE* file = std::fopen(tmp.c_str(), "wx");
      if (file == nullptr) {
        throw IoError(path, fmt::format("cannot create a temporary file beside it: {}",
                                        std::strerror(errno)));
      }
      files_.push_back(Label{label, path, tmp, file, 0, false});
      l = &files_.back();
      std::fprintf(file, "%% %16s %s\n", "Time", header.c_str());
    }
    if (std::fputs(row.c_str(), l->file) < 0) throw IoError(l->path, "write failed");
    ++l->rows;
  }

  std::size_t size() const noexcept { return files_.size(); }

  void finish() {
    for (auto& f : files_) {
      const bool bad = std::ferror(f.file) != 0;
      const bool flush_failed = std::fflush(f.file) != 0 || ::fsync(::fileno(f.file)) != 0;
      const bool close_failed = std::fclose(f.file) != 0;
      f.file = nullptr;
      if (bad || flush_failed || close_failed) throw IoError(f.path, "write failed");
    }
    if (files_.size() == 1) files_[0].path = out_;
    for (auto& f : files_) {
      std::error_code ec;
      std::filesystem::rename(f.tmp, f.path, ec);
      if (ec) throw IoError(f.path, "cannot rename the finished temporary file to it: " + ec.message());
      f.committed = true;
      result_.files.push_back(f.path);
      result_.rows.push_back(f.rows);
    }
  }

 private:
  struct Label {
    std::string label, path;
    std::filesystem::path tmp;
    std::FILE* file;
    std::uint64_t rows;
    bool committed;
  };
  std::string split_name(const std::string& label) const {
    std::string stem = out_;
    if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".txt") == 0) {
      stem.resize(stem.size() - 4);
    }
    std::string clean;
    for (char c : label) {
      const bool bad = c == '/' || c == '\\' || c == ':' || c == '*' || c == '?' || c == '"' ||
                       c == '<' || c == '>' || c == '|' || static_cast<unsigned char>(c) < 0x20;
      clean += bad ? '_' : c;
    }
    return stem + "_" + clean + ".txt";
  }
  std::string in_, out_;
  RawlogJobResult& result_;
  std::deque<Label> files_;
};

[[noreturn]] void no_time(const AnyRawlogReader& reader, std::string_view what) {
  throw ParseError({reader.path(), std::nullopt, reader.position(), std::string(what)},
                   fmt::format("{} has no timestamp: the text export needs one per row", what));
}

}  // namespace

// ------------------------------------------------------------ formatting

std::string mrpt_txt_time(Timestamp t) {
  // mrpt::Clock::toDouble: (ticks since 1601 - offset) / 1e7.
  const auto ticks = static_cast<std::int64_t>(t.to_mrpt() - Timestamp::kMrptEpochOffsetTicks);
  return fmt::format("{:16.6f}", static_cast<double>(ticks) / 10000000.0);
}

std::string mrpt_txt_scan_row(const RangeScan2D& scan) {
  std::string row;
  row.reserve(scan.size() * 8 + 16);
  for (float r : scan.ranges) fmt::format_to(std::back_inserter(row), "{:.3f} ", r);
  row += "    ";
  for (bool v : scan.valid) row += v ? "1 " : "0 ";
  row += "    ";
  for (std::int32_t i : scan.intensity) fmt::format_to(std::back_inserter(row), "{} ", i);
  return row;
}

std::string mrpt_txt_odometry_row(const Pose2& odometry, const std::optional<EncoderTicks>& ticks,
                                  const std::optional<Twist2>& velocity) {
  const Twist2 v = velocity.value_or(Twist2{});
  const EncoderTicks e = ticks.value_or(EncoderTicks{});
  return fmt::format("{:18.5f} {:18.5f} {:18.5f} {:18} {:18} {:18} {:18} {:18.5f} {:18.5f} {:18.5f}",
                     odometry.x(), odometry.y(), odometry.phi(), ticks ? 1 : 0, e.left, e.right,
                     velocity ? 1 : 0, v.vx, v.vy, v.omega);
}

// ------------------------------------------------------------ convert

RawlogJobResult convert_rawlog(const std::string& in, const std::string& out,
                               const ConvertOptions& options, const RawlogProgressFn& progress) {
  ROVE_CHECK_MSG(!options.layout || *options.layout == RawlogLayout::ActionsSensoryFrames ||
                     *options.layout == RawlogLayout::Observations,
                 "convert_rawlog: the output layout is #1 or #2");
  options.motion_model.check();
  check_in_out(in, out);
  AnyRawlogOptions read = options.read;
  if (options.layout) {
    read.carmen.layout = *options.layout;
    read.bag.layout = *options.layout;
  }
  AnyRawlogReader reader(in, read);
  RawlogJobResult r;
  r.input_format = reader.format();
  write_file_atomically(out, [&](const std::filesystem::path& tmp) {
    // The output layout: as requested, else the input's; an MRPT file
    // declares none, so its first entry decides (a later entry of the other
    // kind is then converted as below).
    std::optional<RawlogEntry> first = reader.next();
    RawlogLayout out_layout = options.layout.value_or(
        reader.declared_layout().value_or(first ? layout_of({*first}) : RawlogLayout::ActionsSensoryFrames));
    if (out_layout == RawlogLayout::Empty) out_layout = RawlogLayout::ActionsSensoryFrames;
    RoveRawlogWriter writer(tmp.string(), with_metadata(options.write, in, r.input_format, out_layout));

    // #1 → #2 state.
    Pose2 odometry;  // integrated
    // #2 → #1 state.
    std::optional<Pose2> odometry_latest, odometry_at_last_frame;
    Timestamp odometry_latest_time;
    auto frame = std::make_shared<SensoryFrame>();
    auto flush_frame = [&] {
      if (frame->empty()) return;
      if (odometry_latest && odometry_at_last_frame) {
        RobotMovement2D move(*odometry_latest - *odometry_at_last_frame, options.motion_model);
        move.timestamp = odometry_latest_time;
        ActionCollection ac;
        ac.add(std::make_shared<RobotMovement2D>(std::move(move)));
        writer.write(ac);
        ++r.kept[std::string(RobotMovement2D::kClassName)];
      }
      odometry_at_last_frame = odometry_latest;
      writer.write(*frame);
      count_entry(r.kept, RawlogEntry(FramePtr(frame)));
      frame = std::make_shared<SensoryFrame>();
    };

    for (std::optional<RawlogEntry> e = std::move(first); e; e = reader.next()) {
      throw_if_interrupted();
      ++r.entries_in;
      const bool is_obs = std::holds_alternative<ObsPtr>(*e);
      if (out_layout == RawlogLayout::Mixed || layout_of({*e}) == out_layout) {
        if (out_layout == RawlogLayout::ActionsSensoryFrames) flush_frame();
        writer.write(*e);
        count_entry(r.kept, *e);
      } else if (out_layout == RawlogLayout::Observations) {
        // #1 → #2.
        if (auto* ac = std::get_if<ActionsPtr>(&*e)) {
          for (const auto& a : (*ac)->actions) {
            auto* m = dynamic_cast<const RobotMovement2D*>(a.get());
            if (m == nullptr) {
              ++r.dropped[std::string(a->class_name())];
              continue;
            }
            odometry = odometry + m->mean();
            OdometryObservation o;
            o.timestamp = m->timestamp;
            o.sensor_label = "ODOMETRY";
            o.odometry = odometry;
            o.encoder_ticks = m->encoder_ticks;
            o.velocity = m->velocity;
            writer.write(o);
            ++r.kept[std::string(OdometryObservation::kClassName)];
          }
        } else {
          const auto& sf = std::get<FramePtr>(*e);
          for (const auto& o : sf->observations) {
            writer.write(*o);
            ++r.kept[std::string(o->class_name())];
          }
        }
      } else {
        // #2 → #1.
        ROVE_CHECK(is_obs);
        const auto& o = std::get<ObsPtr>(*e);
        if (auto* odo = dynamic_cast<const OdometryObservation*>(o.get())) {
          flush_frame();
          odometry_latest = odo->odometry;
          odometry_latest_time = odo->timestamp;
          ++r.dropped["OdometryObservation (-> actions)"];
        } else {
          frame->add(o);
        }
      }
      if (progress) progress(reader);
    }
    flush_frame();
    if (const auto* c = reader.carmen()) {
      const auto& s = c->stats();
      if (s.odom_not_used > 0) r.dropped["CARMEN ODOM line (odometry taken from laser lines)"] += s.odom_not_used;
      if (s.truepos_dropped > 0) r.dropped["CARMEN TRUEPOS line"] += s.truepos_dropped;
      const std::uint64_t other = s.log.param + s.log.sync + s.log.other;
      if (other > 0) r.dropped["CARMEN PARAM/SYNC/other line"] += other;
      if (s.log.malformed > 0) r.dropped["CARMEN malformed line"] += s.log.malformed;
    }
    if (const auto* rv = reader.rove(); rv != nullptr && rv->skipped_entries() > 0) {
      r.dropped["entry of unknown class"] += rv->skipped_entries();
    }
    finish(r, writer);
  });
  r.reader_skipped = reader.skipped();
  return r;
}

// ------------------------------------------------------------ cut

RawlogJobResult cut_rawlog(const std::string& in, const std::string& out,
                           const CutOptions& options, const RawlogProgressFn& progress) {
  if (options.from_index && options.to_index && *options.from_index > *options.to_index) {
    throw InvalidArgument(fmt::format("cut_rawlog: from_index {} is after to_index {}",
                                      *options.from_index, *options.to_index));
  }
  if ((options.from_time && !std::isfinite(*options.from_time)) ||
      (options.to_time && !std::isfinite(*options.to_time))) {
    throw InvalidArgument("cut_rawlog: from_time and to_time must be finite");
  }
  if (options.from_time && options.to_time && *options.from_time > *options.to_time) {
    throw InvalidArgument(fmt::format("cut_rawlog: from_time {} is after to_time {}",
                                      format_seconds(*options.from_time),
                                      format_seconds(*options.to_time)));
  }
  check_in_out(in, out);
  AnyRawlogReader reader(in, options.read);
  RawlogJobResult r;
  r.input_format = reader.format();
  write_file_atomically(out, [&](const std::filesystem::path& tmp) {
    RoveRawlogWriter writer(tmp.string(), with_metadata(options.write, in, r.input_format,
                                                        input_layout(reader)));
    bool previous_passed = !options.from_time;
    LogExtent extent;
    std::uint64_t kept = 0;
    while (auto e = reader.next()) {
      throw_if_interrupted();
      ++r.entries_in;
      const std::uint64_t i = extent.entries;
      extent.add(*e);
      bool keep = (!options.from_index || i >= *options.from_index) &&
                  (!options.to_index || i <= *options.to_index);
      if (options.from_time || options.to_time) {
        if (const auto t = entry_time(*e)) {
          const double sec = t->to_seconds();
          previous_passed = (!options.from_time || sec >= *options.from_time) &&
                            (!options.to_time || sec <= *options.to_time);
        }
        keep = keep && previous_passed;
      }
      if (keep) {
        writer.write(*e);
        count_entry(r.kept, *e);
        ++kept;
      } else {
        count_entry(r.dropped, *e);
      }
      if (progress) progress(reader);
      // Past the last index: stop, unless nothing was kept (then the rest
      // is read only to say what the log holds).
      if (options.to_index && i >= *options.to_index && kept > 0) break;
    }
    if (kept == 0) {
      std::string asked;
      std::string option;
      auto add = [&](const char* name, const std::string& value) {
        if (!asked.empty()) asked += ", ";
        asked += fmt::format("{} {}", name, value);
        if (!option.empty()) option += ",";
        option += name;
      };
      if (options.from_index) add("from_index", std::to_string(*options.from_index));
      if (options.to_index) add("to_index", std::to_string(*options.to_index));
      if (options.from_time) add("from_time", format_seconds(*options.from_time));
      if (options.to_time) add("to_time", format_seconds(*options.to_time));
      throw SelectionError(option, fmt::format("{} {} no entry: {}; nothing written",
                                               asked.empty() ? "the bounds" : asked,
                                               asked.empty() ? "select" : "selects",
                                               extent.describe(in)));
    }
    finish(r, writer);
  });
  return r;
}

// ------------------------------------------------------------ decimate

RawlogJobResult decimate_rawlog(const std::string& in, const std::string& out,
                                const DecimateOptions& options, const RawlogProgressFn& progress) {
  ROVE_CHECK_GE(options.every, std::uint64_t{1});
  check_in_out(in, out);
  AnyRawlogReader reader(in, options.read);
  RawlogJobResult r;
  r.input_format = reader.format();
  write_file_atomically(out, [&](const std::filesystem::path& tmp) {
    RoveRawlogWriter writer(tmp.string(), with_metadata(options.write, in, r.input_format,
                                                        input_layout(reader)));
    MovementAccumulator moves;
    std::uint64_t frames = 0;
    std::uint64_t observations = 0;
    while (auto e = reader.next()) {
      throw_if_interrupted();
      ++r.entries_in;
      if (auto* ac = std::get_if<ActionsPtr>(&*e)) {
        for (const auto& a : (*ac)->actions) {
          if (auto* m = dynamic_cast<const RobotMovement2D*>(a.get())) {
            moves.add(*m);
          } else {
            ++r.dropped[std::string(a->class_name())];
          }
        }
      } else if (auto* sf = std::get_if<FramePtr>(&*e)) {
        if (frames++ % options.every == 0) {
          if (auto m = moves.take()) {
            ActionCollection merged;
            merged.add(std::make_shared<RobotMovement2D>(std::move(*m)));
            writer.write(merged);
            ++r.kept[std::string(RobotMovement2D::kClassName)];
          }
          writer.write(**sf);
          count_entry(r.kept, *e);
        } else {
          count_entry(r.dropped, *e);
        }
      } else {
        const auto& o = std::get<ObsPtr>(*e);
        const bool odometry = dynamic_cast<const OdometryObservation*>(o.get()) != nullptr;
        if (odometry || observations++ % options.every == 0) {
          writer.write(*o);
          ++r.kept[std::string(o->class_name())];
        } else {
          ++r.dropped[std::string(o->class_name())];
        }
      }
      if (progress) progress(reader);
    }
    if (auto m = moves.take()) {
      ++r.dropped[std::string(RobotMovement2D::kClassName) + " (after the last kept frame)"];
    }
    finish(r, writer);
  });
  return r;
}

// ------------------------------------------------------------ exports

RawlogJobResult export_scans_txt(const std::string& in, const std::string& out,
                                 const TextExportOptions& options,
                                 const RawlogProgressFn& progress) {
  RawlogJobResult r;
  LabelFiles files(in, out, r);
  AnyRawlogReader reader(in, options.read);
  r.input_format = reader.format();
  std::map<std::string, std::uint64_t> labels;  // every 2D scan's label
  std::map<std::string, std::uint64_t> classes;
  auto export_one = [&](const Observation& o) {
    ++classes[std::string(o.class_name())];
    const auto* scan = dynamic_cast<const RangeScan2D*>(&o);
    if (scan == nullptr) return;
    ++labels[scan->sensor_label];
    if (!options.label.empty() && scan->sensor_label != options.label) return;
    if (!scan->timestamp.valid()) no_time(reader, "RangeScan2D");
    std::string header = "RANGES[i] ... VALID[i]";
    if (!scan->intensity.empty()) header += " ... INTENSITY[i]";
    std::string row = mrpt_txt_time(scan->timestamp);
    row += ' ';
    row += mrpt_txt_scan_row(*scan);
    row += '\n';
    files.add_row(scan->sensor_label, header, row);
    ++r.kept[std::string(RangeScan2D::kClassName)];
  };
  while (auto e = reader.next()) {
    throw_if_interrupted();
    ++r.entries_in;
    if (auto* sf = std::get_if<FramePtr>(&*e)) {
      for (const auto& o : (*sf)->observations) export_one(*o);
    } else if (auto* o = std::get_if<ObsPtr>(&*e)) {
      export_one(**o);
    } else {
      count_entry(classes, *e);
    }
    if (progress) progress(reader);
  }
  if (files.size() == 0) {
    if (labels.empty()) {
      throw SelectionError("", fmt::format("{} holds no 2D scan (it holds: {}); nothing written",
                                           in, classes.empty() ? "nothing" : describe_labels(classes)));
    }
    throw SelectionError("label", fmt::format("no 2D scan has label '{}' in {}; its 2D scan labels "
                                              "are {}; nothing written",
                                              options.label, in, describe_labels(labels)));
  }
  files.finish();
  return r;
}

RawlogJobResult export_odometry_txt(const std::string& in, const std::string& out,
                                    const TextExportOptions& options,
                                    const RawlogProgressFn& progress) {
  RawlogJobResult r;
  LabelFiles files(in, out, r);
  AnyRawlogReader reader(in, options.read);
  r.input_format = reader.format();
  std::map<std::string, std::uint64_t> labels;  // odometry labels present
  std::map<std::string, std::uint64_t> classes;
  const std::string header = fmt::format(
      "{:>18} {:>18} {:>18} {:>18} {:>18} {:>18} {:>18} {:>18} {:>18} {:>18} ", "GLOBAL_ODO_X",
      "GLOBAL_ODO_Y", "GLOBAL_ODO_PHI_RAD", "HAS_ENCODERS", "LEFT_ENC_INCR_TICKS",
      "RIGHT_ENC_INCR_TICKS", "HAS_VELOCITIES", "VEL_VX_MetPerSec", "VEL_VY_MetPerSec",
      "ANG_SPEED_RadPerSec");
  const std::string integrated_label = "ODOMETRY";
  auto label_ok = [&](const std::string& label) {
    ++labels[label];
    return options.label.empty() || label == options.label;
  };
  auto add = [&](const std::string& label, Timestamp t, const Pose2& pose,
                 const std::optional<EncoderTicks>& ticks, const std::optional<Twist2>& v) {
    std::string row = mrpt_txt_time(t);
    row += ' ';
    row += mrpt_txt_odometry_row(pose, ticks, v);
    row += '\n';
    files.add_row(label, header, row);
  };

  // Layout #1: integrate actions; rows whose time comes from the next frame
  // wait in `waiting`.
  Pose2 integrated;
  bool seen_action = false;
  bool identity_row_done = false;
  struct Waiting {
    Pose2 pose;
    std::optional<EncoderTicks> ticks;
    std::optional<Twist2> velocity;
  };
  std::vector<Waiting> waiting;

  while (auto e = reader.next()) {
    throw_if_interrupted();
    ++r.entries_in;
    count_entry(classes, *e);
    if (auto* ac = std::get_if<ActionsPtr>(&*e)) {
      for (const auto& a : (*ac)->actions) {
        const auto* m = dynamic_cast<const RobotMovement2D*>(a.get());
        if (m == nullptr) continue;
        seen_action = true;
        integrated = integrated + m->mean();
        if (!label_ok(integrated_label)) continue;
        ++r.kept[std::string(RobotMovement2D::kClassName)];
        if (m->timestamp.valid()) {
          if (!waiting.empty()) no_time(reader, "RobotMovement2D");
          add(integrated_label, m->timestamp, integrated, m->encoder_ticks, m->velocity);
        } else {
          waiting.push_back({integrated, m->encoder_ticks, m->velocity});
        }
      }
    } else if (auto* sf = std::get_if<FramePtr>(&*e)) {
      std::optional<Timestamp> t = entry_time(*e);
      if (!waiting.empty()) {
        if (!t) no_time(reader, "RobotMovement2D");
        for (const auto& w : waiting) add(integrated_label, *t, w.pose, w.ticks, w.velocity);
        waiting.clear();
      }
      if (!seen_action && !identity_row_done && t && label_ok(integrated_label)) {
        identity_row_done = true;
        add(integrated_label, *t, Pose2(), std::nullopt, std::nullopt);
      }
      for (const auto& o : (*sf)->observations) {
        if (const auto* odo = dynamic_cast<const OdometryObservation*>(o.get())) {
          if (!label_ok(odo->sensor_label)) continue;
          if (!odo->timestamp.valid()) no_time(reader, "OdometryObservation");
          add(odo->sensor_label, odo->timestamp, odo->odometry, odo->encoder_ticks,
              odo->velocity);
          ++r.kept[std::string(OdometryObservation::kClassName)];
        }
      }
    } else {
      const auto& o = std::get<ObsPtr>(*e);
      if (const auto* odo = dynamic_cast<const OdometryObservation*>(o.get())) {
        if (label_ok(odo->sensor_label)) {
          if (!odo->timestamp.valid()) no_time(reader, "OdometryObservation");
          add(odo->sensor_label, odo->timestamp, odo->odometry, odo->encoder_ticks,
              odo->velocity);
          ++r.kept[std::string(OdometryObservation::kClassName)];
        }
      }
    }
    if (progress) progress(reader);
  }
  if (!waiting.empty()) no_time(reader, "RobotMovement2D");
  if (files.size() == 0) {
    if (labels.empty()) {
      throw SelectionError("", fmt::format("{} holds no odometry (it holds: {}); nothing written",
                                           in, classes.empty() ? "nothing" : describe_labels(classes)));
    }
    throw SelectionError("label", fmt::format("no odometry has label '{}' in {}; its odometry "
                                              "labels are {}; nothing written",
                                              options.label, in, describe_labels(labels)));
  }
  files.finish();
  return r;
}

}  // namespace rove
