#include "rove/io/carmen_log.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>

#include "carmen_input.h"
#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/angle.h"

namespace rove {

std::string_view to_string(CarmenMessage message) noexcept {
  switch (message) {
    case CarmenMessage::Flaser: return "FLASER";
    case CarmenMessage::Rlaser: return "RLASER";
    case CarmenMessage::Odom: return "ODOM";
    case CarmenMessage::RobotLaser1: return "ROBOTLASER1";
    case CarmenMessage::TruePos: return "TRUEPOS";
  }
  return "UNKNOWN";
}

namespace {

/// Thrown inside the line parser; turned into ParseError or a skip.
struct LineProblem {
  std::string field;
  std::string problem;
};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

/// Walks the tokens of one message, naming each field it reads.
class Fields {
 public:
  Fields(std::string_view message, const std::vector<std::string_view>& tokens)
      : message_(message), tokens_(tokens) {}

  std::size_t remaining() const { return tokens_.size() - pos_; }

  std::string_view text(std::string_view field) {
    if (pos_ >= tokens_.size()) {
      throw LineProblem{name(field), "missing field (line has too few fields)"};
    }
    return tokens_[pos_++];
  }

  double number(std::string_view field) {
    const std::string_view t = text(field);
    double v = 0.0;
    const char* first = t.data();
    if (t.size() > 1 && t.front() == '+' && t[1] != '-') ++first;  // from_chars rejects '+'
    const auto [ptr, ec] = std::from_chars(first, t.data() + t.size(), v);
    if (ec == std::errc::result_out_of_range) {
      throw LineProblem{name(field), "number out of range: '" + std::string(t) + "'"};
    }
    if (ec != std::errc() || ptr != t.data() + t.size()) {
      throw LineProblem{name(field), "not a number: '" + std::string(t) + "'"};
    }
    if (!std::isfinite(v)) {
      throw LineProblem{name(field), "not a finite number: '" + std::string(t) + "'"};
    }
    return v;
  }

  /// A count of items that follow; each takes at least one token, so a
  /// count above the tokens left is malformed (and never allocated).
  /// With `trailing`, the line must hold exactly count + trailing fields
  /// after the count.
  std::size_t count(std::string_view field, std::optional<std::size_t> trailing = std::nullopt) {
    const double v = number(field);
    if (v < 0.0 || v != std::floor(v)) {
      throw LineProblem{name(field), "not a non-negative integer"};
    }
    if (v > static_cast<double>(remaining())) {
      throw LineProblem{name(field), "declares more items than the line holds"};
    }
    const auto n = static_cast<std::size_t>(v);
    if (trailing && remaining() != n + *trailing) {
      throw LineProblem{name(field), "wrong field count: " + std::to_string(n) + " items need " +
                                         std::to_string(n + *trailing) +
                                         " fields after the count, the line has " +
                                         std::to_string(remaining())};
    }
    return n;
  }

  Pose2 pose(std::string_view fx, std::string_view fy, std::string_view ftheta) {
    const double x = number(fx);
    const double y = number(fy);
    const double theta = number(ftheta);
    return Pose2(x, y, theta);
  }

  void expect_end() {
    if (pos_ != tokens_.size()) {
      throw LineProblem{name("logger_timestamp"),
                        "wrong field count: " + std::to_string(tokens_.size() - pos_) +
                            " extra field(s) after the logger timestamp"};
    }
  }

  std::string name(std::string_view field) const {
    std::string s(message_);
    s += '.';
    s += field;
    return s;
  }

 private:
  std::string_view message_;
  const std::vector<std::string_view>& tokens_;
  std::size_t pos_ = 1;  // token 0 is the message name
};

std::string indexed(std::string_view base, std::size_t i) {
  return std::string(base) + "[" + std::to_string(i) + "]";
}

}  // namespace

struct CarmenLogReader::Impl {
  Impl(detail::CarmenRawSource source, std::string name, CarmenLogOptions opts)
      : source_name(name),
        options(std::move(opts)),
        lines(std::move(source), std::move(name), options.max_line_bytes) {
    stats.front_max_range = options.flaser_max_range;
    stats.rear_max_range = options.flaser_max_range;
  }

  std::string source_name;
  CarmenLogOptions options;
  detail::CarmenLineReader lines;
  CarmenLogStats stats;
  std::string line;
  std::vector<std::string_view> tokens;

  Timestamp time_of(double logger_ts, const std::string& field) const {
    // Keep the sum inside int64 nanoseconds (about ±292 years).
    constexpr double kLimit = 9.0e9;
    const double ns = logger_ts * 1e9;
    if (std::fabs(logger_ts) > kLimit) {
      throw LineProblem{field, "timestamp out of range"};
    }
    const std::int64_t offset = static_cast<std::int64_t>(std::llround(ns));
    std::int64_t total = 0;
    if (!options.start_time.valid() || __builtin_add_overflow(options.start_time.ns, offset, &total) ||
        total == Timestamp::kInvalidNs) {
      throw LineProblem{field, "timestamp out of range"};
    }
    return Timestamp::from_ns(total);
  }

  void tail(Fields& f, CarmenRecord& r, std::string_view message) {
    r.ipc_timestamp = f.number("ipc_timestamp");
    r.ipc_hostname = std::string(f.text("ipc_hostname"));
    r.logger_timestamp = f.number("logger_timestamp");
    f.expect_end();
    r.timestamp = time_of(r.logger_timestamp, std::string(message) + ".logger_timestamp");
  }

  void parse_flaser(Fields& f, CarmenRecord& r, std::string_view message) {
    // x y theta odom_x odom_y odom_theta ipc_timestamp ipc_hostname logger_timestamp
    constexpr std::size_t kTrailing = 9;
    const std::size_t n = f.count("num_readings", kTrailing);
    std::vector<float> ranges(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double v = f.number(indexed("range", i));
      if (std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
        throw LineProblem{f.name(indexed("range", i)), "range does not fit a float"};
      }
      ranges[i] = static_cast<float>(v);
    }
    r.laser_pose = f.pose("x", "y", "theta");
    r.robot_pose = f.pose("odom_x", "odom_y", "odom_theta");
    tail(f, r, message);
    auto scan = std::make_unique<RangeScan2D>();
    scan->aperture = kPi;
    scan->right_to_left = true;
    scan->max_range =
        r.type == CarmenMessage::Rlaser ? stats.rear_max_range : stats.front_max_range;
    scan->set_ranges(std::move(ranges));
    scan->timestamp = r.timestamp;
    scan->sensor_label =
        r.type == CarmenMessage::Rlaser ? options.rear_laser_label : options.front_laser_label;
    scan->T_robot_sensor = Pose3(r.laser_pose - r.robot_pose);
    r.scan = std::move(scan);
  }

  void parse_odom(Fields& f, CarmenRecord& r) {
    r.robot_pose = f.pose("x", "y", "theta");
    r.tv = f.number("tv");
    r.rv = f.number("rv");
    r.accel = f.number("accel");
    tail(f, r, "ODOM");
    auto odo = std::make_unique<OdometryObservation>();
    odo->odometry = r.robot_pose;
    odo->velocity = Twist2{r.tv, 0.0, r.rv};
    odo->timestamp = r.timestamp;
    odo->sensor_label = options.odometry_label;
    r.odometry = std::move(odo);
  }

  void parse_truepos(Fields& f, CarmenRecord& r) {
    r.true_pose = f.pose("true_x", "true_y", "true_theta");
    r.robot_pose = f.pose("odom_x", "odom_y", "odom_theta");
    tail(f, r, "TRUEPOS");
  }

  void parse_robotlaser1(Fields& f, CarmenRecord& r) {
    r.laser_type = f.number("laser_type");
    r.start_angle = f.number("start_angle");
    const double fov = f.number("field_of_view");
    if (!(fov > 0.0) || fov > 2.0 * kPi) {
      throw LineProblem{f.name("field_of_view"), "must lie in (0, 2π] radians"};
    }
    r.angular_resolution = f.number("angular_resolution");
    const double max_range = f.number("maximum_range");
    if (max_range < 0.0 || max_range > static_cast<double>(std::numeric_limits<float>::max())) {
      throw LineProblem{f.name("maximum_range"), "must be a non-negative float"};
    }
    f.number("accuracy");
    f.number("remission_mode");
    const std::size_t n = f.count("num_readings");
    std::vector<float> ranges(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double v = f.number(indexed("range", i));
      if (std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
        throw LineProblem{f.name(indexed("range", i)), "range does not fit a float"};
      }
      ranges[i] = static_cast<float>(v);
    }
    // laser pose (3), robot pose (3), tv rv forward_safety_dist
    // side_safety_dist turn_axis (5), ipc_timestamp ipc_hostname logger_timestamp (3)
    constexpr std::size_t kTrailing = 14;
    const std::size_t m = f.count("num_remissions", kTrailing);
    r.remissions.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      const double v = f.number(indexed("remission", i));
      if (std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
        throw LineProblem{f.name(indexed("remission", i)), "remission does not fit a float"};
      }
      r.remissions[i] = static_cast<float>(v);
    }
    r.laser_pose = f.pose("laser_x", "laser_y", "laser_theta");
    r.robot_pose = f.pose("robot_x", "robot_y", "robot_theta");
    r.tv = f.number("tv");
    r.rv = f.number("rv");
    f.number("forward_safety_dist");
    f.number("side_safety_dist");
    f.number("turn_axis");
    tail(f, r, "ROBOTLASER1");
    auto scan = std::make_unique<RangeScan2D>();
    scan->aperture = fov;
    scan->right_to_left = true;
    scan->max_range = static_cast<float>(max_range);
    scan->set_ranges(std::move(ranges));
    scan->timestamp = r.timestamp;
    scan->sensor_label = options.front_laser_label;
    // Ray 0 of a RangeScan2D points at −aperture/2 in the sensor frame; in
    // the laser frame it points at start_angle.
    const Pose2 laser_to_scan(0.0, 0.0, r.start_angle + fov / 2.0);
    scan->T_robot_sensor = Pose3((r.laser_pose - r.robot_pose) + laser_to_scan);
    r.scan = std::move(scan);
  }

  /// PARAM name value ...: the laser maximum ranges; other parameters are
  /// only counted.
  void read_param() {
    if (tokens.size() < 3) return;
    const bool front = tokens[1] == "robot_front_laser_max";
    const bool rear = tokens[1] == "robot_rear_laser_max";
    if (!front && !rear) return;
    const std::string field = "PARAM " + std::string(tokens[1]);
    const std::string_view t = tokens[2];
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    // The range is kept as a float: a value that rounds to 0 there (below
    // 1.4e-45 m) would turn every later reading into "no return".
    if (ec != std::errc() || ptr != t.data() + t.size() || !std::isfinite(v) ||
        !(static_cast<float>(std::min(v, 1.0)) > 0.0f) ||
        v > static_cast<double>(std::numeric_limits<float>::max())) {
      throw LineProblem{field, "not a positive range in meters: '" + std::string(t) + "'"};
    }
    if (front) {
      stats.front_max_range = static_cast<float>(v);
      stats.front_max_range_from_log = true;
    } else {
      stats.rear_max_range = static_cast<float>(v);
      stats.rear_max_range_from_log = true;
    }
  }

  /// Parses a data line; returns true if it produced a record.
  bool parse(CarmenRecord& r) {
    const std::string_view name = tokens[0];
    std::optional<CarmenMessage> type;
    if (name == "FLASER") type = CarmenMessage::Flaser;
    else if (name == "RLASER") type = CarmenMessage::Rlaser;
    else if (name == "ODOM") type = CarmenMessage::Odom;
    else if (name == "ROBOTLASER1") type = CarmenMessage::RobotLaser1;
    else if (name == "TRUEPOS") type = CarmenMessage::TruePos;
    if (!type) {
      if (name == "PARAM") {
        read_param();  // a malformed range is counted as malformed only
        ++stats.param;
      }
      else if (name == "SYNC") ++stats.sync;
      else ++stats.other;
      return false;
    }
    r = CarmenRecord{};
    r.type = *type;
    r.line = stats.lines;
    Fields f(name, tokens);
    switch (*type) {
      case CarmenMessage::Flaser:
      case CarmenMessage::Rlaser: parse_flaser(f, r, name); break;
      case CarmenMessage::Odom: parse_odom(f, r); break;
      case CarmenMessage::RobotLaser1: parse_robotlaser1(f, r); break;
      case CarmenMessage::TruePos: parse_truepos(f, r); break;
    }
    switch (*type) {
      case CarmenMessage::Flaser: ++stats.flaser; break;
      case CarmenMessage::Rlaser: ++stats.rlaser; break;
      case CarmenMessage::Odom: ++stats.odom; break;
      case CarmenMessage::RobotLaser1: ++stats.robotlaser1; break;
      case CarmenMessage::TruePos: ++stats.truepos; break;
    }
    return true;
  }

  bool next(CarmenRecord& r) {
    bool too_long = false;
    while (lines.next(line, too_long)) {
      ++stats.lines;
      try {
        if (too_long) {
          throw LineProblem{"", "line longer than " + std::to_string(options.max_line_bytes) +
                                    " bytes"};
        }
        split(line, tokens);
        if (tokens.empty()) {
          ++stats.blank;
          continue;
        }
        if (tokens[0].front() == '#') {
          ++stats.comments;
          continue;
        }
        if (parse(r)) return true;
      } catch (const LineProblem& p) {
        if (options.skip_malformed) {
          ++stats.malformed;
          continue;
        }
        ParseError::Location where;
        where.source = source_name;
        where.line = stats.lines;
        where.field = p.field;
        throw ParseError(std::move(where), p.problem);
      }
    }
    return false;
  }
};

CarmenLogReader::CarmenLogReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
CarmenLogReader::CarmenLogReader(CarmenLogReader&&) noexcept = default;
CarmenLogReader& CarmenLogReader::operator=(CarmenLogReader&&) noexcept = default;
CarmenLogReader::~CarmenLogReader() = default;

namespace {
void check_options(const CarmenLogOptions& options) {
  ROVE_CHECK_GT(options.max_line_bytes, std::size_t{0});
  ROVE_CHECK_MSG(std::isfinite(options.flaser_max_range) && options.flaser_max_range > 0.0f,
                 "CARMEN maximum range {} m must be finite and > 0", options.flaser_max_range);
}
}  // namespace

CarmenLogReader CarmenLogReader::open(const std::string& path, CarmenLogOptions options) {
  check_options(options);
  ROVE_CHECK(options.start_time.valid());
  return CarmenLogReader(
      std::make_unique<Impl>(detail::CarmenRawSource::file(path), path, std::move(options)));
}

CarmenLogReader CarmenLogReader::from_memory(std::string bytes, std::string source,
                                             CarmenLogOptions options) {
  check_options(options);
  ROVE_CHECK(options.start_time.valid());
  return CarmenLogReader(std::make_unique<Impl>(detail::CarmenRawSource::memory(std::move(bytes)),
                                                std::move(source), std::move(options)));
}

bool CarmenLogReader::next(CarmenRecord& record) { return impl_->next(record); }

const CarmenLogStats& CarmenLogReader::stats() const noexcept { return impl_->stats; }

bool is_carmen_message_name(std::string_view name) noexcept {
  static constexpr std::string_view kNames[] = {
      "FLASER",    "RLASER",    "ODOM",      "ROBOTLASER1", "TRUEPOS",     "PARAM",
      "SYNC",      "RAWLASER1", "RAWLASER2", "RAWLASER3",   "RAWLASER4",   "ROBOTLASER2",
      "NMEAGGA",   "NMEARMC"};
  for (const std::string_view n : kNames) {
    if (name == n) return true;
  }
  return false;
}

bool looks_like_carmen_log(const std::string& path, std::size_t max_bytes) {
  detail::CarmenLineReader lines(detail::CarmenRawSource::file(path), path, max_bytes);
  std::string line;
  std::vector<std::string_view> tokens;
  std::size_t seen = 0;
  bool too_long = false;
  while (seen < max_bytes && lines.next(line, too_long)) {
    seen += line.size() + 1;
    split(line, tokens);
    if (tokens.empty() || tokens[0].front() == '#') continue;
    if (is_carmen_message_name(tokens[0])) return true;
  }
  return false;
}

CarmenLogStats count_carmen_log(const std::string& path, const CarmenLogOptions& options) {
  CarmenLogReader reader = CarmenLogReader::open(path, options);
  CarmenRecord record;
  while (reader.next(record)) {
  }
  return reader.stats();
}

}  // namespace rove
