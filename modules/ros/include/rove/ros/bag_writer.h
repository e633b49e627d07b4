#pragma once
/// \file
/// Writing rove rawlog entries to a ROS 1 bag with the rosbag C++ API:
/// RangeScan2D → sensor_msgs/LaserScan on "/<label>" ("/scan" when
/// unlabelled); RobotMovement2D actions → nav_msgs/Odometry on "/odom" (the
/// increments integrated from the identity at the first observation, as
/// MRPT's rawlog-edit does); OdometryObservation → nav_msgs/Odometry as it
/// is; RangeImage3D → "/<label>/depth/image_raw" (16UC1 when its scale is
/// 1000 units per meter, else 32FC1 meters) with ".../camera_info", its
/// intensity image on "/<label>/rgb/image_raw" + camera_info, stored points
/// as sensor_msgs/PointCloud2 on "/<label>/points"; ImageObservation →
/// "/<label>/image_raw" + camera_info. Each sensor's pose on the robot goes
/// to /tf_static (base_frame → "<label>" frame, optical frames for
/// cameras), written before its first message.
///
/// What carries over exactly, and what a bag cannot hold, is listed in
/// docs/ros.md: scan validity flags map to ranges (an invalid ray whose
/// range would read as valid is written as +Inf, REP 117's "no return"),
/// intensities become float32, Pose3 angles become quaternions.

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "rove/io/any_rawlog.h"

namespace rove {

/// Chunk compression of a written bag.
enum class BagCompression : std::uint8_t { None = 0, Bz2 = 1, Lz4 = 2 };

/// Options of write_bag.
struct BagWriteOptions {
  /// Chunk compression.
  BagCompression compression = BagCompression::Lz4;
  /// The robot's frame (parent of the sensor frames and child of odometry).
  std::string base_frame = "base_link";
  /// The odometry frame.
  std::string odom_frame = "odom";
  /// The odometry topic.
  std::string odom_topic = "/odom";
  /// Reading options of the input.
  AnyRawlogOptions read;
};

/// What write_bag wrote and left out.
struct BagWriteResult {
  /// The input's format.
  RawlogFormat input_format = RawlogFormat::Mrpt;
  /// Entries read.
  std::uint64_t entries_in = 0;
  /// Messages written, by topic.
  std::map<std::string, std::uint64_t> messages_by_topic;
  /// Observations and actions left out, by class name and reason.
  std::map<std::string, std::uint64_t> dropped;
};

/// Converts the log at `in` (any format AnyRawlogReader reads) to a ROS bag
/// at `out`, written under a temporary name and renamed when complete.
/// `progress` (may be empty) is called after each entry. Throws what the
/// reader throws, IoError if `out` is `in` or cannot be written,
/// SelectionError when nothing could be written.
BagWriteResult write_bag(const std::string& in, const std::string& out,
                         const BagWriteOptions& options = {},
                         const std::function<void(const AnyRawlogReader&)>& progress = {});

}  // namespace rove
