#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "commands.h"
#include "report.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/progress.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/rawlog_reader.h"
#include "rove/io/rawlog_tools.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/observation.h"
#include "rove/obs/selection_error.h"
#include "rove/obs/sensory_frame.h"
#include "rove/serialization/input_file.h"
#ifdef ROVE_HAVE_ROS
#include "rove/ros/bag_writer.h"
#endif

namespace rove::cli {

namespace {

// Default maximum range of CARMEN FLASER/RLASER lines (CarmenLogOptions).
constexpr float kDefaultCarmenMaxRange = CarmenLogOptions{}.flaser_max_range;

struct RawlogInfoOptions {
  std::string file;
  bool json = false;
  bool progress = true;
  float max_range = kDefaultCarmenMaxRange;
};

AnyRawlogOptions read_options(float carmen_max_range,
                              const std::vector<std::string>& bag_topics = {}) {
  AnyRawlogOptions o;
  o.carmen.log.flaser_max_range = carmen_max_range;
  o.bag.topics = bag_topics;
  return o;
}

bool is_bag_path(const std::string& path) {
  return path.size() >= 4 && path.compare(path.size() - 4, 4, ".bag") == 0;
}

// The --max-range flag of every command that reads a rawlog.
void add_max_range(CLI::App* cmd, float& max_range) {
  cmd->add_option("--max-range", max_range,
                  "CARMEN logs: maximum range of FLASER/RLASER scans, meters, when the log has no "
                  "PARAM robot_front_laser_max / robot_rear_laser_max; readings at or above it "
                  "are \"no return\" (e.g. 50 for the ACES log)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
}

// CARMEN maximum ranges as read, for the summaries.
std::string carmen_ranges(const CarmenLogStats& s) {
  auto one = [](float r, bool from_log) {
    return fmt::format("{:g} m ({})", r, from_log ? "PARAM line" : "--max-range");
  };
  std::string out = "FLASER " + one(s.front_max_range, s.front_max_range_from_log);
  if (s.rlaser > 0) out += ", RLASER " + one(s.rear_max_range, s.rear_max_range_from_log);
  return out;
}

// What `rove rawlog info` counts while streaming a rawlog once.
struct RawlogSummary {
  std::uint64_t entries = 0;
  std::uint64_t action_collections = 0;
  std::uint64_t actions = 0;
  std::uint64_t sensory_frames = 0;
  std::uint64_t observations_in_frames = 0;
  std::uint64_t bare_observations = 0;
  std::uint64_t bytes = 0;  // decompressed
  // (class name, sensor label) -> count, for observations; class -> count for actions.
  std::map<std::pair<std::string, std::string>, std::uint64_t> observation_kinds;
  std::map<std::string, std::uint64_t> action_kinds;
  // Earliest and latest observation time (actions are not counted, as in
  // rawlog-edit --info).
  std::optional<Timestamp> first, last;
  // CARMEN logs: the reader's counts (maximum ranges used).
  std::optional<CarmenLogStats> carmen;
  // What the reader left out (ROS bags: messages by topic, where it stopped).
  std::vector<std::string> skipped;

  void add_time(Timestamp t) {
    if (!t.valid()) return;
    if (!first || t < *first) first = t;
    if (!last || *last < t) last = t;
  }
  void add_observation(const Observation& o) {
    ++observation_kinds[{std::string(o.class_name()), o.sensor_label}];
    add_time(o.timestamp);
  }
};

// Progress of a job that streams one input file: against the file size for
// plain rove and MRPT files (whose reader reports byte offsets), as a count
// of entries otherwise (gzip offsets are decompressed bytes; CARMEN logs
// report lines).
// The bar appears with the first entry read, so a job refused before it
// reads anything (same file as output, not a log) prints no progress.
class FileProgress {
 public:
  FileProgress(const std::string& path, bool show, const std::string& label)
      : path_(path), show_(show), label_(label) {}
  void update(const AnyRawlogReader& reader) {
    if (!show_) return;
    if (!progress_) {
      if (reader.format() != RawlogFormat::Carmen && !is_gzip_file(path_)) {
        total_ = std::filesystem::file_size(path_);
      }
      progress_.emplace(total_, label_ + " " + printable(path_), std::cerr);
    }
    if (total_) {
      progress_->set(std::min<std::uint64_t>(reader.position(), *total_));
    } else {
      progress_->advance();
    }
  }
  RawlogProgressFn fn() {
    if (!show_) return {};
    return [this](const AnyRawlogReader& r) { update(r); };
  }
  void finish() {
    if (progress_) progress_->finish();
  }

 private:
  std::string path_;
  bool show_;
  std::string label_;
  std::optional<std::uint64_t> total_;
  std::optional<Progress> progress_;
};

RawlogSummary summarize(const std::string& path, bool show_progress, float max_range,
                        RawlogFormat& format) {
  RawlogSummary s;
  AnyRawlogReader reader(path, read_options(max_range));
  format = reader.format();
  FileProgress progress(path, show_progress, "reading");
  while (auto entry = reader.next()) {
    throw_if_interrupted();
    ++s.entries;
    std::visit(
        [&s](const auto& e) {
          using T = std::remove_const_t<typename std::decay_t<decltype(e)>::element_type>;
          if constexpr (std::is_same_v<T, ActionCollection>) {
            ++s.action_collections;
            for (const auto& a : e->actions) {
              ++s.actions;
              ++s.action_kinds[std::string(a->class_name())];
            }
          } else if constexpr (std::is_same_v<T, SensoryFrame>) {
            ++s.sensory_frames;
            for (const auto& o : e->observations) {
              ++s.observations_in_frames;
              s.add_observation(*o);
            }
          } else {
            ++s.bare_observations;
            s.add_observation(*e);
          }
        },
        *entry);
    progress.update(reader);
  }
  progress.finish();
  s.bytes = format == RawlogFormat::Carmen ? 0 : reader.position();
  if (const auto* c = reader.carmen()) s.carmen = c->stats().log;
  s.skipped = reader.skipped();
  return s;
}

void print_text(const std::string& path, RawlogFormat format, const RawlogSummary& s) {
  fmt::print("file: {}\n", printable(path));
  fmt::print("format: {}\n", to_string(format));
  fmt::print("entries: {} ({} action collections, {} sensory frames, {} bare observations)\n",
             s.entries, s.action_collections, s.sensory_frames, s.bare_observations);
  fmt::print("layout: {}\n", s.bare_observations == 0 ? "#1 (actions + sensory frames)"
                             : s.sensory_frames == 0 && s.action_collections == 0
                                 ? "#2 (observations)"
                                 : "mixed");
  fmt::print("uncompressed bytes: {}\n", s.bytes);
  if (s.first && s.last) {
    fmt::print("time span: {:.6f} .. {:.6f} s ({:.3f} s)\n", s.first->to_seconds(),
               s.last->to_seconds(), s.last->to_seconds() - s.first->to_seconds());
  } else {
    fmt::print("time span: no timestamps\n");
  }
  fmt::print("observations: {} ({} in sensory frames)\n",
             s.observations_in_frames + s.bare_observations, s.observations_in_frames);
  for (const auto& [kind, n] : s.observation_kinds) {
    fmt::print("  {:>8}  {} [{}]\n", n, kind.first,
               kind.second.empty() ? "no label" : kind.second);
  }
  fmt::print("actions: {}\n", s.actions);
  for (const auto& [kind, n] : s.action_kinds) fmt::print("  {:>8}  {}\n", n, kind);
  if (s.carmen) fmt::print("CARMEN maximum range: {}\n", carmen_ranges(*s.carmen));
  fmt::print("skipped:{}\n", s.skipped.empty() ? " nothing" : "");
  for (const auto& line : s.skipped) fmt::print("  {}\n", line);
}

void print_json(const std::string& path, RawlogFormat format, const RawlogSummary& s) {
  JsonWriter j(0);
  j.begin_object();
  j.key("file").value(path);
  j.key("format").value(to_string(format));
  j.key("entries").value(s.entries);
  j.key("action_collections").value(s.action_collections);
  j.key("sensory_frames").value(s.sensory_frames);
  j.key("bare_observations").value(s.bare_observations);
  j.key("actions").value(s.actions);
  j.key("observations").value(s.observations_in_frames + s.bare_observations);
  j.key("uncompressed_bytes").value(s.bytes);
  if (s.first && s.last) {
    j.key("time_first").value(s.first->to_seconds());
    j.key("time_last").value(s.last->to_seconds());
  }
  j.key("observation_kinds").begin_array();
  for (const auto& [kind, n] : s.observation_kinds) {
    j.begin_object().key("class").value(kind.first).key("label").value(kind.second);
    j.key("count").value(n).end_object();
  }
  j.end_array();
  j.key("action_kinds").begin_array();
  for (const auto& [kind, n] : s.action_kinds) {
    j.begin_object().key("class").value(kind).key("count").value(n).end_object();
  }
  j.end_array();
  if (s.carmen) {
    j.key("carmen_max_range").begin_object();
    j.key("flaser").value(s.carmen->front_max_range);
    j.key("flaser_from_log").value(s.carmen->front_max_range_from_log);
    j.key("rlaser").value(s.carmen->rear_max_range);
    j.key("rlaser_from_log").value(s.carmen->rear_max_range_from_log);
    j.end_object();
  }
  j.key("skipped").begin_array();
  for (const auto& line : s.skipped) j.value(line);
  j.end_array();
  write_issues(j, {});
  j.end_object();
  fmt::print("{}\n", j.str());
}

// What a job kept and dropped, per class, on stdout.
void print_job(const std::string& verb, const std::string& in, const std::string& out,
               const RawlogJobResult& r, bool bag_out = false) {
  fmt::print("{} {} ({}) -> {}\n", verb, printable(in), to_string(r.input_format), printable(out));
  if (bag_out) {
    fmt::print("entries: {} read, {} messages written\n", r.entries_in, r.entries_out);
  } else {
    fmt::print("entries: {} read, {} written\n", r.entries_in, r.entries_out);
  }
  fmt::print("kept:\n");
  for (const auto& [k, n] : r.kept) fmt::print("  {:>8}  {}\n", n, k);
  fmt::print("dropped:{}\n", r.dropped.empty() && r.reader_skipped.empty() ? " none" : "");
  for (const auto& [k, n] : r.dropped) fmt::print("  {:>8}  {}\n", n, k);
  for (const auto& line : r.reader_skipped) fmt::print("  {}\n", line);
}

void print_export(const RawlogJobResult& r) {
  for (std::size_t i = 0; i < r.files.size(); ++i) {
    fmt::print("wrote {} ({} rows)\n", printable(r.files[i]), r.rows[i]);
  }
}

// Runs a job: a selection that finds nothing names the command-line flag
// that asked for it; Ctrl-C says that the output was not written.
// `flags` maps option names to the flags that set them; with `rename`, the
// option names in the message are replaced by the flags too.
template <typename Job>
RawlogJobResult run_job(const std::string& out, const std::map<std::string, std::string>& flags,
                        bool rename, const Job& job) {
  try {
    return job();
  } catch (const SelectionError& e) {
    std::string option = e.option();
    std::string named;
    std::string message = e.message();
    for (const auto& [field, flag] : flags) {
      for (std::size_t at = message.find(field); rename && at != std::string::npos;
           at = message.find(field, at + flag.size())) {
        message.replace(at, field.size(), flag);
      }
      if (option.find(field) != std::string::npos) {
        if (!named.empty()) named += ", ";
        named += flag;
      }
    }
    throw Error(named.empty() ? message : named + ": " + message);
  } catch (const Interrupted&) {
    fmt::print(stderr, "rove: interrupted: {} not written (nothing was written)\n", printable(out));
    throw;
  }
}

const std::map<std::string, std::string> kCutFlags = {{"from_index", "--from"},
                                                      {"to_index", "--to"},
                                                      {"from_time", "--from-time"},
                                                      {"to_time", "--to-time"}};
const std::map<std::string, std::string> kLabelFlag = {{"label", "--label"}};

RoveRawlogWriterOptions writer_options(bool gzip) {
  RoveRawlogWriterOptions w;
  w.gzip = gzip;
  w.metadata.emplace("tool_version", std::string("rove ") + ROVE_VERSION);
  return w;
}

struct JobOptions {
  std::string in, out;
  bool progress = true;
  bool gzip = true;
  int layout = 0;
  std::optional<std::uint64_t> from_index, to_index;
  std::optional<double> from_time, to_time;
  std::uint64_t every = 1;
  std::string label;
  float max_range = kDefaultCarmenMaxRange;
  std::vector<std::string> topics;
  std::string compression = "lz4";
};

void add_io(CLI::App* cmd, JobOptions& o, const std::string& out_help) {
  cmd->add_option("input", o.in, "rove rawlog, MRPT rawlog (plain or gzip), CARMEN log (plain or bzip2) or ROS bag")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("output", o.out, out_help)->required();
  cmd->add_flag("!--no-progress", o.progress, "Do not report progress on stderr");
  add_max_range(cmd, o.max_range);
}

/// `rawlog export-scans` / `export-odometry`: a text export of one rawlog.
using TextExportFn = RawlogJobResult (*)(const std::string&, const std::string&,
                                         const TextExportOptions&, const RawlogProgressFn&);
void add_text_export(CLI::App* rawlog, const std::shared_ptr<JobOptions>& job,
                     const std::string& name, const std::string& help,
                     const std::string& out_help, TextExportFn export_fn) {
  auto* cmd = rawlog->add_subcommand(name, help);
  add_io(cmd, *job, out_help);
  cmd->add_option("--label", job->label, "Export only this sensor label (default: every label)");
  cmd->callback([job, export_fn] {
    TextExportOptions o;
    o.label = job->label;
    o.read = read_options(job->max_range);
    FileProgress progress(job->in, job->progress, "exporting");
    const RawlogJobResult r = run_job(job->out, kLabelFlag, false, [&] {
      return export_fn(job->in, job->out, o, progress.fn());
    });
    progress.finish();
    print_export(r);
  });
}

}  // namespace

void add_rawlog_command(CLI::App& app) {
  auto* rawlog = app.add_subcommand(
      "rawlog", "Inspect, convert and export robot datasets (rove and MRPT rawlogs, CARMEN logs, ROS bags)");
  rawlog->require_subcommand(1);
  auto options = std::make_shared<RawlogInfoOptions>();
  auto* info = rawlog->add_subcommand(
      "info", "Stream a rawlog once and count its entries per type and sensor label");
  info->add_option("file", options->file,
                   "rove rawlog, MRPT rawlog (plain or gzip), CARMEN log (plain or bzip2) or ROS bag")
      ->required()
      ->check(CLI::ExistingFile);
  info->add_flag("--json", options->json, "Print one JSON object instead of text");
  info->add_flag("!--no-progress", options->progress, "Do not report progress on stderr");
  add_max_range(info, options->max_range);
  info->callback([options] {
    RawlogFormat format = RawlogFormat::Mrpt;
    const RawlogSummary s =
        summarize(options->file, options->progress, options->max_range, format);
    if (options->json) {
      print_json(options->file, format, s);
    } else {
      print_text(options->file, format, s);
    }
  });

  auto job = std::make_shared<JobOptions>();

  auto* convert = rawlog->add_subcommand(
      "convert",
      "Convert an MRPT rawlog, a CARMEN log or a rove rawlog to a rove rawlog (gzip by default), "
      "reporting what was kept and dropped per class");
  add_io(convert, *job, "rove rawlog to write, or a ROS bag when it ends in .bag");
  convert->add_option("--topics", job->topics,
                      "ROS bag input: read only these topics (e.g. /scan /odom; /tf and "
                      "camera_info topics are always used for sensor poses and cameras)");
  convert->add_option("--compression", job->compression, "ROS bag output: chunk compression")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "bz2", "lz4"}));
  convert->add_option("--layout", job->layout,
                      "Output layout: 1 = actions + sensory frames, 2 = observations (default: "
                      "the input's; CARMEN: 1)")
      ->check(CLI::IsMember({1, 2}));
  convert->add_flag("!--no-gzip", job->gzip, "Write plain bytes instead of gzip");
  convert->callback([job] {
    if (is_bag_path(job->out)) {
#ifdef ROVE_HAVE_ROS
      BagWriteOptions o;
      o.compression = job->compression == "none" ? BagCompression::None
                      : job->compression == "bz2" ? BagCompression::Bz2
                                                  : BagCompression::Lz4;
      o.read = read_options(job->max_range, job->topics);
      FileProgress progress(job->in, job->progress, "converting");
      RawlogJobResult r;
      run_job(job->out, {}, false, [&] {
        const BagWriteResult w = write_bag(job->in, job->out, o, progress.fn());
        r.input_format = w.input_format;
        r.entries_in = w.entries_in;
        for (const auto& [topic, n] : w.messages_by_topic) {
          r.kept["messages on " + topic] = n;
          r.entries_out += n;
        }
        r.dropped = w.dropped;
        return r;
      });
      progress.finish();
      print_job("converted", job->in, job->out, r, true);
      return;
#else
      throw Error(fmt::format("{}: writing ROS bags needs the rove::ros adapter, which this build "
                              "lacks (Debian's ROS 1 packages: scripts/install-deps --ros)",
                              printable(job->out)));
#endif
    }
    ConvertOptions o;
    if (job->layout == 1) o.layout = RawlogLayout::ActionsSensoryFrames;
    if (job->layout == 2) o.layout = RawlogLayout::Observations;
    o.write = writer_options(job->gzip);
    o.read = read_options(job->max_range, job->topics);
    FileProgress progress(job->in, job->progress, "converting");
    const RawlogJobResult r =
        run_job(job->out, {}, false, [&] { return convert_rawlog(job->in, job->out, o, progress.fn()); });
    progress.finish();
    print_job("converted", job->in, job->out, r);
  });

  add_text_export(rawlog, job, "export-scans",
                  "Export 2D laser scans as text with the columns and number format of MRPT's "
                  "rawlog-edit --export-2d-scans-txt (time, ranges, validity[, intensity]); one "
                  "file per sensor label: OUTPUT itself for a single label, else "
                  "OUTPUT_<label>.txt",
                  "text file to write (e.g. scans.txt)", export_scans_txt);
  add_text_export(rawlog, job, "export-odometry",
                  "Export odometry as text with the columns of MRPT's rawlog-edit "
                  "--export-odometry-txt (time, x, y, phi, encoders, velocities). Layout #1 logs "
                  "(where rawlog-edit writes no odometry) get the actions integrated from the "
                  "identity, under label ODOMETRY",
                  "text file to write (e.g. odometry.txt)", export_odometry_txt);

  auto* cut = rawlog->add_subcommand(
      "cut",
      "Keep the entries between two indices (0-based, inclusive) and/or times (seconds since "
      "the Unix epoch, inclusive); writes a rove rawlog with the input's layout");
  add_io(cut, *job, "rove rawlog to write");
  cut->add_option("--from", job->from_index, "First entry index to keep (default: the first)");
  cut->add_option("--to", job->to_index, "Last entry index to keep (default: the last)");
  cut->add_option("--from-time", job->from_time, "Keep entries at or after this time, seconds since the Unix epoch (default: no bound)");
  cut->add_option("--to-time", job->to_time, "Keep entries at or before this time, seconds since the Unix epoch (default: no bound)");
  cut->add_flag("!--no-gzip", job->gzip, "Write plain bytes instead of gzip");
  cut->callback([job] {
    if (!job->from_index && !job->to_index && !job->from_time && !job->to_time) {
      throw CLI::ValidationError("cut", "give at least one of --from, --to, --from-time, --to-time");
    }
    if (job->from_index && job->to_index && *job->from_index > *job->to_index) {
      throw CLI::ValidationError(
          "--from", fmt::format("{} is after --to {}", *job->from_index, *job->to_index));
    }
    if (job->from_time && job->to_time && *job->from_time > *job->to_time) {
      throw CLI::ValidationError(
          "--from-time", fmt::format("{} is after --to-time {}", *job->from_time, *job->to_time));
    }
    CutOptions o;
    o.from_index = job->from_index;
    o.to_index = job->to_index;
    o.from_time = job->from_time;
    o.to_time = job->to_time;
    o.write = writer_options(job->gzip);
    o.read = read_options(job->max_range);
    FileProgress progress(job->in, job->progress, "cutting");
    const RawlogJobResult r =
        run_job(job->out, kCutFlags, true, [&] { return cut_rawlog(job->in, job->out, o, progress.fn()); });
    progress.finish();
    print_job("cut", job->in, job->out, r);
  });

  auto* decimate = rawlog->add_subcommand(
      "decimate",
      "Keep one of every K sensory frames (layout #1; the odometry actions in between are "
      "composed into one) or observations (layout #2; odometry observations are all kept); "
      "writes a rove rawlog with the input's layout");
  add_io(decimate, *job, "rove rawlog to write");
  decimate->add_option("--every", job->every, "K: keep one of every K")
      ->required()
      ->check(CLI::PositiveNumber);
  decimate->add_flag("!--no-gzip", job->gzip, "Write plain bytes instead of gzip");
  decimate->callback([job] {
    DecimateOptions o;
    o.every = job->every;
    o.write = writer_options(job->gzip);
    o.read = read_options(job->max_range);
    FileProgress progress(job->in, job->progress, "decimating");
    const RawlogJobResult r = run_job(
        job->out, {}, false, [&] { return decimate_rawlog(job->in, job->out, o, progress.fn()); });
    progress.finish();
    print_job("decimated", job->in, job->out, r);
  });
}

}  // namespace rove::cli
