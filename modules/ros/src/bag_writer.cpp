#include "rove/ros/bag_writer.h"

#include <fmt/format.h>

#include <set>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "ros_convert.h"
#include "ros_plain.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/selection_error.h"
#include "rove/obs/sensory_frame.h"

namespace rove {

using namespace bag_detail;

namespace {

class Converter {
 public:
  Converter(RosbagWriter& bag, const BagWriteOptions& o, BagWriteResult& r)
      : bag_(bag), o_(o), r_(r) {}

  void entry(const RawlogEntry& e) {
    std::visit(
        [this](const auto& p) {
          using T = std::remove_const_t<typename std::decay_t<decltype(p)>::element_type>;
          if constexpr (std::is_same_v<T, ActionCollection>) {
            actions(*p);
          } else if constexpr (std::is_same_v<T, SensoryFrame>) {
            for (const auto& obs : p->observations) observation(*obs);
          } else {
            observation(*p);
          }
        },
        e);
  }

 private:
  template <typename Msg>
  void write(const std::string& topic, const Msg& m) {
    bag_.write(topic, m_sec_, m_nsec_, m);
    ++r_.messages_by_topic[topic];
  }

  // Uses `t` (or the previous message's time when invalid) as record time.
  void at(Timestamp t, MsgHeader& h) {
    if (t.valid()) set_stamp(h, t);
    else { h.sec = m_sec_; h.nsec = m_nsec_; }
    if (h.sec != 0 || h.nsec != 0) {
      m_sec_ = h.sec;
      m_nsec_ = h.nsec;
    }
    if (m_sec_ == 0 && m_nsec_ == 0) m_nsec_ = 1;  // rosbag refuses time zero
  }

  void odometry(const Pose2& pose, Timestamp t, const std::optional<Twist2>& v) {
    OdometryMsg m;
    m.header.frame_id = o_.odom_frame;
    m.child_frame_id = o_.base_frame;
    at(t, m.header);
    pose3_to_ros(Pose3(pose), m.position, m.orientation);
    if (v) {
      m.linear = {v->vx, v->vy, 0.0};
      m.angular = {0.0, 0.0, v->omega};
    }
    write(o_.odom_topic, m);
  }

  void actions(const ActionCollection& ac) {
    auto move = best_movement_2d(ac);
    if (!move) {
      for (const auto& a : ac.actions) ++r_.dropped[std::string(a->class_name()) + " (no ROS message)"];
      return;
    }
    for (const auto& a : ac.actions) {
      if (a.get() != move.get()) ++r_.dropped[std::string(a->class_name()) + " (not the best movement)"];
    }
    if (!odom_) {
      // Odometry starts at the identity at the first observation.
      odom_ = Pose2();
      if (first_obs_) odometry(*odom_, *first_obs_, std::nullopt);
    }
    odom_ = *odom_ + move->mean();
    odometry(*odom_, move->timestamp, move->velocity);
  }

  void sensor_tf(const std::string& frame, const Pose3& T_base_frame, Timestamp t) {
    if (!tf_frames_.insert(frame).second) return;
    TfMsg tf;
    TransformMsg tr;
    tr.header.frame_id = o_.base_frame;
    at(t, tr.header);
    tr.child_frame_id = frame;
    pose3_to_ros(T_base_frame, tr.translation, tr.rotation);
    tf.transforms.push_back(tr);
    write("/tf_static", tf);
  }

  void observation(const Observation& obs) {
    if (!first_obs_ && obs.timestamp.valid()) first_obs_ = obs.timestamp;
    if (const auto* s = dynamic_cast<const RangeScan2D*>(&obs)) {
      const std::string name = ros_name(s->sensor_label, "scan");
      sensor_tf(name, s->T_robot_sensor, s->timestamp);
      LaserScanMsg m = scan_to_ros(*s);
      m.header.frame_id = name;
      at(s->timestamp, m.header);
      write("/" + name, m);
    } else if (const auto* o = dynamic_cast<const OdometryObservation*>(&obs)) {
      odometry(o->odometry, o->timestamp, o->velocity);
    } else if (const auto* d = dynamic_cast<const RangeImage3D*>(&obs)) {
      const std::string name = ros_name(d->sensor_label, "camera");
      if (d->depth.pixel_count() > 0) {
        const std::string frame = name + "_depth_optical_frame";
        sensor_tf(frame, d->T_robot_sensor + sensor_from_optical(), d->timestamp);
        CameraInfoMsg ci = camera_to_ros(d->depth_camera);
        ci.header.frame_id = frame;
        at(d->timestamp, ci.header);
        write("/" + name + "/depth/camera_info", ci);
        ImageMsg m = depth_to_ros(d->depth);
        m.header = ci.header;
        write("/" + name + "/depth/image_raw", m);
        if (d->intensity) {
          const std::string rgb = name + "_rgb_optical_frame";
          sensor_tf(rgb, d->T_robot_sensor + d->T_sensor_intensity, d->timestamp);
          CameraInfoMsg ci2 = camera_to_ros(d->intensity_camera);
          ci2.header.frame_id = rgb;
          at(d->timestamp, ci2.header);
          write("/" + name + "/rgb/camera_info", ci2);
          ImageMsg im = image_to_ros(*d->intensity);
          im.header = ci2.header;
          write("/" + name + "/rgb/image_raw", im);
        }
      } else if (d->points) {
        sensor_tf(name, d->T_robot_sensor, d->timestamp);
        PointCloud2Msg m = cloud_to_ros(*d->points);
        m.header.frame_id = name;
        at(d->timestamp, m.header);
        write("/" + name + "/points", m);
      } else {
        ++r_.dropped["RangeImage3D (neither depth nor points)"];
      }
    } else if (const auto* im = dynamic_cast<const ImageObservation*>(&obs)) {
      const std::string name = ros_name(im->sensor_label, "camera");
      const std::string frame = name + "_optical_frame";
      sensor_tf(frame, im->T_robot_sensor, im->timestamp);
      ImageMsg m = image_to_ros(im->image);
      m.header.frame_id = frame;
      at(im->timestamp, m.header);
      if (im->camera.width != 0) {
        CameraInfoMsg ci = camera_to_ros(im->camera);
        ci.header = m.header;
        write("/" + name + "/camera_info", ci);
      }
      write("/" + name + "/image_raw", m);
    } else {
      ++r_.dropped[std::string(obs.class_name()) + " (no ROS message)"];
    }
  }

  RosbagWriter& bag_;
  const BagWriteOptions& o_;
  BagWriteResult& r_;
  std::uint32_t m_sec_ = 0, m_nsec_ = 0;
  std::optional<Pose2> odom_;
  std::optional<Timestamp> first_obs_;
  std::set<std::string> tf_frames_;
};

}  // namespace

BagWriteResult write_bag(const std::string& in, const std::string& out,
                         const BagWriteOptions& options,
                         const std::function<void(const AnyRawlogReader&)>& progress) {
  check_outputs_distinct({in}, {out});
  BagWriteResult result;
  AnyRawlogReader reader(in, options.read);
  result.input_format = reader.format();
  const auto tmp = temporary_sibling(out);
  try {
    {
      RosbagWriter bag(tmp.string(), static_cast<ChunkCompression>(options.compression));
      Converter convert(bag, options, result);
      while (auto e = reader.next()) {
        throw_if_interrupted();
        ++result.entries_in;
        convert.entry(*e);
        if (progress) progress(reader);
      }
      bag.close();
    }
    if (result.messages_by_topic.empty()) {
      throw SelectionError("input", fmt::format("{}: no observation or odometry that a ROS bag "
                                                "holds ({} entries read)",
                                                printable(in), result.entries_in));
    }
    std::filesystem::rename(tmp, out);
  } catch (const Error&) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  } catch (const std::runtime_error& e) {
    // rosbag's errors and the rename's.
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw IoError(out, e.what());
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  return result;
}

}  // namespace rove
