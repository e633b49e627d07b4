#pragma once
// Conversions between ROS messages (their plain copies, ros_plain.h) and
// rove observations, both ways, and the transform tree of /tf.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "ros_plain.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"

namespace rove::bag_detail {

// A frame id without its leading '/' (tf1 style "/base_link").
std::string normalize_frame(const std::string& frame);
// "/camera/depth/image_raw" → "/camera/depth"; "/scan" → "".
std::string topic_namespace(const std::string& topic);
// The first component of a topic: "/camera/depth/image_raw" → "camera".
std::string label_of_topic(const std::string& topic);
// A sensor label as a ROS graph name component ([A-Za-z][A-Za-z0-9_]*).
std::string ros_name(const std::string& label, const std::string& fallback);

// header.stamp in ns, or `fallback_ns` when the stamp is zero.
std::int64_t stamp_or(const MsgHeader& h, std::int64_t fallback_ns);
// A header's stamp from a rove time (invalid → zero).
void set_stamp(MsgHeader& h, Timestamp t);

// Poses: ROS translation + quaternion (x, y, z, w) ↔ Pose3. A zero or
// non-finite quaternion throws InvalidArgument.
Pose3 pose3_from_ros(const std::array<double, 3>& t, const std::array<double, 4>& q);
void pose3_to_ros(const Pose3& p, std::array<double, 3>& t, std::array<double, 4>& q);

// The transforms of /tf and /tf_static: each child frame's latest pose in
// its parent.
class TfTree {
 public:
  void set(const TransformMsg& t);
  // T_base_frame through the chain of parents of `frame`, or nullopt.
  std::optional<Pose3> lookup(const std::string& base, const std::string& frame) const;

 private:
  std::map<std::string, std::pair<std::string, Pose3>> parent_of_;
};

// LaserScan → RangeScan2D. Ray i at angle_min + i·angle_increment; the
// scan's center direction becomes a yaw of T_robot_sensor (zero for the
// usual symmetric scans). valid[i]: range finite and in [range_min,
// range_max]. Throws InvalidArgument for fewer than 2 rays or a zero or
// non-finite increment.
std::shared_ptr<RangeScan2D> scan_from_ros(const LaserScanMsg& m, const std::string& where);
// Whether a LaserScan range reads as valid.
bool ros_range_valid(float r, float range_min, float range_max);
// RangeScan2D → LaserScan (frame_id and stamp left to the caller).
LaserScanMsg scan_to_ros(const RangeScan2D& s);

// Odometry → Pose2 (x, y, yaw of the orientation).
Pose2 pose2_from_ros(const OdometryMsg& m, const std::string& where);

// PointCloud2 with float x, y, z fields → RangeImage3D holding the finite
// points (and their pixel for organized clouds).
std::shared_ptr<RangeImage3D> cloud_from_ros(const PointCloud2Msg& m, const std::string& where);
PointCloud2Msg cloud_to_ros(const RangeImagePoints& p);

bool is_depth_encoding(const std::string& encoding);
// Depth image (16UC1/mono16 millimeters, 32FC1 meters) with its camera.
std::shared_ptr<RangeImage3D> depth_from_ros(const ImageMsg& m, const CameraInfoMsg* info,
                                             const std::string& where);
// Colour or gray image with its camera.
std::shared_ptr<ImageObservation> image_from_ros(const ImageMsg& m, const CameraInfoMsg* info,
                                                 const std::string& where);
// Puts `color`'s image into `rgbd` as its intensity image.
void attach_intensity(RangeImage3D& rgbd, const ImageObservation& color);

ImageMsg depth_to_ros(const DepthImage& d);
ImageMsg image_to_ros(const Image& image);
CameraInfoMsg camera_to_ros(const PinholeCamera& c);
PinholeCamera camera_from_ros(const CameraInfoMsg& c);

}  // namespace rove::bag_detail
