#include "rove/ros/bag_reader.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <utility>

#include "bag_file.h"
#include "ros_convert.h"
#include "ros_messages.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"

namespace rove {

using namespace bag_detail;

namespace {

enum class Kind { Scan, Odometry, Cloud, Image, CameraInfo, Tf, Unsupported };

Kind kind_of(const BagConnection& c) {
  struct Known {
    std::string_view type, md5;
    Kind kind;
  };
  static constexpr Known kKnown[] = {
      {kLaserScanType, kLaserScanMd5, Kind::Scan},   {kOdometryType, kOdometryMd5, Kind::Odometry},
      {kPointCloud2Type, kPointCloud2Md5, Kind::Cloud}, {kImageType, kImageMd5, Kind::Image},
      {kCameraInfoType, kCameraInfoMd5, Kind::CameraInfo}, {kTfType, kTfMd5, Kind::Tf}};
  for (const Known& k : kKnown) {
    if (c.datatype == k.type && (c.md5sum == k.md5 || c.md5sum == "*")) return k.kind;
  }
  return Kind::Unsupported;
}

// An observation waiting for the time to move on (odometry of its time and
// the colour image of a depth image may still come).
struct PendingObs {
  std::shared_ptr<Observation> obs;
  std::string ns;       // topic namespace (RGB-D pairing)
  bool depth = false;   // a RangeImage3D from a depth image
  bool color = false;   // an ImageObservation that may pair with a depth image
};

}  // namespace

struct BagReader::Impl {
  BagReadOptions options;
  BagFile file;
  BagReadStats stats;
  TfTree tf;
  std::map<std::string, CameraInfoMsg> camera_infos;  // by topic namespace
  std::map<std::uint32_t, Kind> kinds;                // by connection id
  std::vector<PendingObs> pending;
  std::int64_t pending_ns = std::numeric_limits<std::int64_t>::min();
  std::deque<RawlogEntry> ready;
  // Odometry: the latest pose read, and the pose at the previous frame.
  std::optional<Pose2> odom;
  Timestamp odom_time;
  std::optional<Twist2> odom_velocity;
  std::optional<Pose2> odom_at_frame;
  bool finished = false;

  Impl(const std::string& path, BagReadOptions o) : options(std::move(o)), file(path) {}

  bool wanted(const std::string& topic) const {
    if (options.topics.empty()) return true;
    for (const auto& t : options.topics) {
      if (t == topic) return true;
    }
    return false;
  }

  void skip(const BagConnection& c, std::string_view reason) {
    ++stats.skipped[fmt::format("{} ({}): {}", printable(c.topic), printable(c.datatype), reason)];
  }

  std::string source(const BagMessage& m) const {
    return fmt::format("{}: message on {} at {}.{:09}", file.path(), printable(m.connection->topic),
                       m.sec, m.nsec);
  }

  // T_robot_frame from /tf, or identity (counted) when unknown.
  Pose3 sensor_pose(const BagConnection& c, const std::string& frame_id) {
    if (auto p = tf.lookup(options.base_frame, frame_id)) return *p;
    if (normalize_frame(frame_id) != normalize_frame(options.base_frame)) {
      skip(c, fmt::format("no transform {} <- {} known yet (sensor pose taken as the robot's "
                          "origin; the messages were read)",
                          printable(options.base_frame), printable(frame_id)));
    }
    return Pose3();
  }

  void flush_pending() {
    // Pair each depth image with a colour image of the same namespace
    // family (sibling topics of one camera) and time.
    for (auto& d : pending) {
      if (!d.depth || !d.obs) continue;
      for (auto& c : pending) {
        if (!c.color || !c.obs || c.ns != d.ns) continue;
        auto& rgbd = static_cast<RangeImage3D&>(*d.obs);
        auto& img = static_cast<ImageObservation&>(*c.obs);
        attach_intensity(rgbd, img);
        c.obs.reset();
        break;
      }
    }
    for (auto& p : pending) {
      if (p.obs) emit(std::move(p.obs));
    }
    pending.clear();
  }

  void emit(std::shared_ptr<const Observation> obs) {
    if (options.layout == RawlogLayout::Observations) {
      ready.emplace_back(std::move(obs));
      return;
    }
    if (odom) {
      if (odom_at_frame) {
        auto move = std::make_shared<RobotMovement2D>(*odom - *odom_at_frame, options.motion_model);
        move->timestamp = odom_time;
        move->velocity = odom_velocity;
        auto actions = std::make_shared<ActionCollection>();
        actions->add(std::move(move));
        ready.emplace_back(std::shared_ptr<const ActionCollection>(std::move(actions)));
      }
      odom_at_frame = odom;
    }
    auto frame = std::make_shared<SensoryFrame>();
    frame->add(std::move(obs));
    ready.emplace_back(std::shared_ptr<const SensoryFrame>(std::move(frame)));
  }

  void add_pending(PendingObs p, std::int64_t t) {
    if (!pending.empty() && t != pending_ns) flush_pending();
    pending_ns = t;
    pending.push_back(std::move(p));
  }

  // Moves time on to `t`: observations of earlier times are complete.
  void advance(std::int64_t t) {
    if (!pending.empty() && t > pending_ns) flush_pending();
  }

  void handle(const BagMessage& m) {
    const BagConnection& c = *m.connection;
    auto it = kinds.find(c.id);
    if (it == kinds.end()) it = kinds.emplace(c.id, kind_of(c)).first;
    const Kind kind = it->second;
    if (kind == Kind::Unsupported) {
      skip(c, "unsupported message type");
      return;
    }
    // Transforms and camera parameters are read whatever the topic filter
    // says: they describe the selected sensors.
    if (kind != Kind::Tf && kind != Kind::CameraInfo && !wanted(c.topic)) {
      skip(c, "not among --topics");
      return;
    }
    const std::string where = source(m);
    const std::int64_t record_ns = m.time_ns();
    try {
      switch (kind) {
        case Kind::Tf: {
          TfMsg msg;
          parse(m.data, where, msg);
          for (const TransformMsg& t : msg.transforms) tf.set(t);
          break;
        }
        case Kind::CameraInfo: {
          CameraInfoMsg msg;
          parse(m.data, where, msg);
          camera_infos[topic_namespace(c.topic)] = std::move(msg);
          break;
        }
        case Kind::Scan: {
          LaserScanMsg msg;
          parse(m.data, where, msg);
          auto scan = scan_from_ros(msg, where);
          scan->sensor_label = label_of_topic(c.topic);
          scan->T_robot_sensor = sensor_pose(c, msg.header.frame_id) + scan->T_robot_sensor;
          const std::int64_t t = stamp_or(msg.header, record_ns);
          scan->timestamp = Timestamp::from_ns(t);
          advance(t);
          add_pending({std::move(scan), topic_namespace(c.topic), false, false}, t);
          break;
        }
        case Kind::Odometry: {
          OdometryMsg msg;
          parse(m.data, where, msg);
          const std::int64_t t = stamp_or(msg.header, record_ns);
          advance(t);
          const Pose2 pose = pose2_from_ros(msg, where);
          Twist2 v{msg.linear[0], msg.linear[1], msg.angular[2]};
          const bool moving = v.vx != 0.0 || v.vy != 0.0 || v.omega != 0.0;
          if (options.layout == RawlogLayout::Observations) {
            auto o = std::make_shared<OdometryObservation>();
            o->timestamp = Timestamp::from_ns(t);
            o->sensor_label = label_of_topic(c.topic);
            o->odometry = pose;
            if (moving) o->velocity = v;
            add_pending({std::move(o), topic_namespace(c.topic), false, false}, t);
          } else {
            odom = pose;
            odom_time = Timestamp::from_ns(t);
            odom_velocity = moving ? std::optional<Twist2>(v) : std::nullopt;
          }
          break;
        }
        case Kind::Cloud: {
          PointCloud2Msg msg;
          parse(m.data, where, msg);
          auto cloud = cloud_from_ros(msg, where);
          cloud->sensor_label = label_of_topic(c.topic);
          cloud->T_robot_sensor = sensor_pose(c, msg.header.frame_id);
          const std::int64_t t = stamp_or(msg.header, record_ns);
          cloud->timestamp = Timestamp::from_ns(t);
          advance(t);
          add_pending({std::move(cloud), topic_namespace(c.topic), false, false}, t);
          break;
        }
        case Kind::Image: {
          ImageMsg msg;
          parse(m.data, where, msg);
          const std::string ns = topic_namespace(c.topic);
          auto info = camera_infos.find(ns);
          const CameraInfoMsg* ci = info == camera_infos.end() ? nullptr : &info->second;
          const std::int64_t t = stamp_or(msg.header, record_ns);
          advance(t);
          // The RGB-D pairing key: the camera's namespace above
          // "depth"/"rgb" ("/camera/depth/image_raw" → "/camera").
          const std::string family = topic_namespace(ns);
          const Pose3 T_robot_optical = sensor_pose(c, msg.header.frame_id);
          if (is_depth_encoding(msg.encoding)) {
            auto rgbd = depth_from_ros(msg, ci, where);
            rgbd->sensor_label = label_of_topic(c.topic);
            rgbd->timestamp = Timestamp::from_ns(t);
            rgbd->T_robot_sensor = T_robot_optical + sensor_from_optical().inverse();
            add_pending({std::move(rgbd), family, true, false}, t);
          } else {
            auto img = image_from_ros(msg, ci, where);
            img->sensor_label = label_of_topic(c.topic);
            img->timestamp = Timestamp::from_ns(t);
            img->T_robot_sensor = T_robot_optical;
            add_pending({std::move(img), family, false, true}, t);
          }
          break;
        }
        case Kind::Unsupported:
          break;
      }
    } catch (const ParseError& e) {
      skip(c, fmt::format("malformed ({}: {})", e.location().field, e.problem()));
      return;
    } catch (const InvalidArgument& e) {
      skip(c, fmt::format("not convertible ({})", e.message()));
      return;
    }
    ++stats.read_by_topic[c.topic];
  }

  std::optional<RawlogEntry> next() {
    while (ready.empty() && !finished) {
      auto m = file.next();
      if (!m) {
        finished = true;
        flush_pending();
        break;
      }
      handle(*m);
    }
    if (ready.empty()) return std::nullopt;
    RawlogEntry e = std::move(ready.front());
    ready.pop_front();
    return e;
  }
};

BagReader::BagReader(const std::string& path, BagReadOptions options) {
  if (options.layout != RawlogLayout::ActionsSensoryFrames &&
      options.layout != RawlogLayout::Observations) {
    throw InvalidArgument("BagReader: layout must be ActionsSensoryFrames or Observations");
  }
  impl_ = std::make_unique<Impl>(path, std::move(options));
}

BagReader::~BagReader() = default;

std::optional<RawlogEntry> BagReader::next() { return impl_->next(); }

std::uint64_t BagReader::position() const { return impl_->file.position(); }

RawlogLayout BagReader::layout() const { return impl_->options.layout; }

const BagReadStats& BagReader::stats() const {
  BagReadStats& s = impl_->stats;
  const BagFileStats& f = impl_->file.stats();
  s.chunks_by_compression = f.chunks_by_compression;
  s.stopped_at = f.stopped_at;
  s.stop_reason = f.stop_reason;
  s.indexed = f.indexed;
  if (f.orphan_messages > 0) {
    s.skipped["messages of a connection no record defines"] = f.orphan_messages;
  }
  return s;
}

std::vector<std::string> BagReader::skipped() const {
  const BagReadStats& s = stats();
  std::vector<std::string> out;
  for (const auto& [what, n] : s.skipped) out.push_back(fmt::format("{} messages on {}", n, what));
  if (s.stopped_at) {
    out.push_back(fmt::format("stopped at byte {} of {}: {}", *s.stopped_at,
                              impl_->file.file_size(), s.stop_reason));
  } else if (!s.indexed) {
    out.push_back("the bag has no index (it was not closed); every complete message was read");
  }
  return out;
}

void register_bag_reader() {
  register_rawlog_source(RawlogFormat::RosBag,
                         [](const std::string& path, const AnyRawlogOptions& options) {
                           return std::make_unique<BagReader>(path, options.bag);
                         });
}

}  // namespace rove
