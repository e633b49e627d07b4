// The only translation unit that includes ROS's own headers: compiled as
// C++17 (see ros_plain.h), it turns rove's plain message copies into ROS's
// message classes and writes them with rosbag::Bag; and it reads a bag with
// rosbag::View for the tests.

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <stdexcept>

#include "ros_plain.h"

namespace rove::bag_detail {
namespace {

std_msgs::Header to_ros(const MsgHeader& h) {
  std_msgs::Header r;
  r.seq = h.seq;
  r.stamp = ::ros::Time(h.sec, h.nsec);
  r.frame_id = h.frame_id;
  return r;
}

template <typename To, typename From>
void copy_array(To& to, const From& from) {
  std::copy(from.begin(), from.end(), to.begin());
}

sensor_msgs::LaserScan to_ros(const LaserScanMsg& m) {
  sensor_msgs::LaserScan r;
  r.header = to_ros(m.header);
  r.angle_min = m.angle_min;
  r.angle_max = m.angle_max;
  r.angle_increment = m.angle_increment;
  r.time_increment = m.time_increment;
  r.scan_time = m.scan_time;
  r.range_min = m.range_min;
  r.range_max = m.range_max;
  r.ranges = m.ranges;
  r.intensities = m.intensities;
  return r;
}

nav_msgs::Odometry to_ros(const OdometryMsg& m) {
  nav_msgs::Odometry r;
  r.header = to_ros(m.header);
  r.child_frame_id = m.child_frame_id;
  r.pose.pose.position.x = m.position[0];
  r.pose.pose.position.y = m.position[1];
  r.pose.pose.position.z = m.position[2];
  r.pose.pose.orientation.x = m.orientation[0];
  r.pose.pose.orientation.y = m.orientation[1];
  r.pose.pose.orientation.z = m.orientation[2];
  r.pose.pose.orientation.w = m.orientation[3];
  copy_array(r.pose.covariance, m.pose_covariance);
  r.twist.twist.linear.x = m.linear[0];
  r.twist.twist.linear.y = m.linear[1];
  r.twist.twist.linear.z = m.linear[2];
  r.twist.twist.angular.x = m.angular[0];
  r.twist.twist.angular.y = m.angular[1];
  r.twist.twist.angular.z = m.angular[2];
  copy_array(r.twist.covariance, m.twist_covariance);
  return r;
}

sensor_msgs::PointCloud2 to_ros(const PointCloud2Msg& m) {
  sensor_msgs::PointCloud2 r;
  r.header = to_ros(m.header);
  r.height = m.height;
  r.width = m.width;
  for (const PointFieldMsg& f : m.fields) {
    sensor_msgs::PointField rf;
    rf.name = f.name;
    rf.offset = f.offset;
    rf.datatype = f.datatype;
    rf.count = f.count;
    r.fields.push_back(rf);
  }
  r.is_bigendian = m.is_bigendian;
  r.point_step = m.point_step;
  r.row_step = m.row_step;
  r.data = m.data;
  r.is_dense = m.is_dense;
  return r;
}

sensor_msgs::Image to_ros(const ImageMsg& m) {
  sensor_msgs::Image r;
  r.header = to_ros(m.header);
  r.height = m.height;
  r.width = m.width;
  r.encoding = m.encoding;
  r.is_bigendian = m.is_bigendian;
  r.step = m.step;
  r.data = m.data;
  return r;
}

sensor_msgs::CameraInfo to_ros(const CameraInfoMsg& m) {
  sensor_msgs::CameraInfo r;
  r.header = to_ros(m.header);
  r.height = m.height;
  r.width = m.width;
  r.distortion_model = m.distortion_model;
  r.D = m.D;
  copy_array(r.K, m.K);
  copy_array(r.R, m.R);
  copy_array(r.P, m.P);
  r.binning_x = m.binning_x;
  r.binning_y = m.binning_y;
  r.roi.x_offset = m.roi_x_offset;
  r.roi.y_offset = m.roi_y_offset;
  r.roi.height = m.roi_height;
  r.roi.width = m.roi_width;
  r.roi.do_rectify = m.roi_do_rectify;
  return r;
}

tf2_msgs::TFMessage to_ros(const TfMsg& m) {
  tf2_msgs::TFMessage r;
  for (const TransformMsg& t : m.transforms) {
    geometry_msgs::TransformStamped rt;
    rt.header = to_ros(t.header);
    rt.child_frame_id = t.child_frame_id;
    rt.transform.translation.x = t.translation[0];
    rt.transform.translation.y = t.translation[1];
    rt.transform.translation.z = t.translation[2];
    rt.transform.rotation.x = t.rotation[0];
    rt.transform.rotation.y = t.rotation[1];
    rt.transform.rotation.z = t.rotation[2];
    rt.transform.rotation.w = t.rotation[3];
    r.transforms.push_back(rt);
  }
  return r;
}

}  // namespace

struct RosbagWriter::Impl {
  rosbag::Bag bag;
  bool open = false;

  template <typename Msg>
  void write(const std::string& topic, std::uint32_t sec, std::uint32_t nsec, const Msg& m) {
    try {
      bag.write(topic, ::ros::Time(sec, nsec), to_ros(m));
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("rosbag: ") + e.what());
    }
  }
};

RosbagWriter::RosbagWriter(const std::string& path, ChunkCompression compression)
    : impl_(new Impl) {
  try {
    impl_->bag.open(path, rosbag::bagmode::Write);
    switch (compression) {
      case ChunkCompression::None: impl_->bag.setCompression(rosbag::compression::Uncompressed); break;
      case ChunkCompression::Bz2: impl_->bag.setCompression(rosbag::compression::BZ2); break;
      case ChunkCompression::Lz4: impl_->bag.setCompression(rosbag::compression::LZ4); break;
    }
    impl_->open = true;
  } catch (const std::exception& e) {
    delete impl_;
    throw std::runtime_error(std::string("rosbag: ") + e.what());
  }
}

RosbagWriter::~RosbagWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; close() reports errors when called.
  }
  delete impl_;
}

void RosbagWriter::close() {
  if (!impl_->open) return;
  impl_->open = false;
  try {
    impl_->bag.close();
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("rosbag: ") + e.what());
  }
}

void RosbagWriter::write(const std::string& t, std::uint32_t s, std::uint32_t n, const LaserScanMsg& m) { impl_->write(t, s, n, m); }
void RosbagWriter::write(const std::string& t, std::uint32_t s, std::uint32_t n, const OdometryMsg& m) { impl_->write(t, s, n, m); }
void RosbagWriter::write(const std::string& t, std::uint32_t s, std::uint32_t n, const PointCloud2Msg& m) { impl_->write(t, s, n, m); }
void RosbagWriter::write(const std::string& t, std::uint32_t s, std::uint32_t n, const ImageMsg& m) { impl_->write(t, s, n, m); }
void RosbagWriter::write(const std::string& t, std::uint32_t s, std::uint32_t n, const CameraInfoMsg& m) { impl_->write(t, s, n, m); }
void RosbagWriter::write(const std::string& t, std::uint32_t s, std::uint32_t n, const TfMsg& m) { impl_->write(t, s, n, m); }

void RosbagWriter::write_text(const std::string& t, std::uint32_t s, std::uint32_t n,
                              const std::string& text) {
  std_msgs::String m;
  m.data = text;
  try {
    impl_->bag.write(t, ::ros::Time(s, n), m);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("rosbag: ") + e.what());
  }
}

std::vector<RosbagViewEntry> read_with_rosbag_view(const std::string& path) {
  std::vector<RosbagViewEntry> out;
  try {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    for (const rosbag::MessageInstance& m : view) {
      RosbagViewEntry e;
      e.topic = m.getTopic();
      e.datatype = m.getDataType();
      e.sec = m.getTime().sec;
      e.nsec = m.getTime().nsec;
      e.size = m.size();
      out.push_back(e);
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("rosbag: ") + e.what());
  }
  return out;
}

std::vector<RosTypeInfo> ros_type_infos() {
  using ::ros::message_traits::DataType;
  using ::ros::message_traits::MD5Sum;
  return {
      {DataType<sensor_msgs::LaserScan>::value(), MD5Sum<sensor_msgs::LaserScan>::value()},
      {DataType<nav_msgs::Odometry>::value(), MD5Sum<nav_msgs::Odometry>::value()},
      {DataType<sensor_msgs::PointCloud2>::value(), MD5Sum<sensor_msgs::PointCloud2>::value()},
      {DataType<sensor_msgs::Image>::value(), MD5Sum<sensor_msgs::Image>::value()},
      {DataType<sensor_msgs::CameraInfo>::value(), MD5Sum<sensor_msgs::CameraInfo>::value()},
      {DataType<tf2_msgs::TFMessage>::value(), MD5Sum<tf2_msgs::TFMessage>::value()},
  };
}

}  // namespace rove::bag_detail
