#pragma once
// Plain copies of the ROS 1 messages rove reads and writes. This header is
// included both by the translation units that use ROS's own message classes
// (compiled as C++17: Debian's generated ROS 1 headers use
// std::allocator<void>::rebind, which C++20 removed) and by rove's C++20
// code, so it holds nothing but standard types.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rove::bag_detail {

// std_msgs/Header.
struct MsgHeader {
  std::uint32_t seq = 0;
  std::uint32_t sec = 0;
  std::uint32_t nsec = 0;
  std::string frame_id;
};

// sensor_msgs/LaserScan.
struct LaserScanMsg {
  MsgHeader header;
  float angle_min = 0, angle_max = 0, angle_increment = 0;
  float time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges;
  std::vector<float> intensities;
};

// nav_msgs/Odometry (pose and twist with covariance).
struct OdometryMsg {
  MsgHeader header;
  std::string child_frame_id;
  std::array<double, 3> position{};
  std::array<double, 4> orientation{0, 0, 0, 1};  // x, y, z, w
  std::array<double, 36> pose_covariance{};
  std::array<double, 3> linear{};
  std::array<double, 3> angular{};
  std::array<double, 36> twist_covariance{};
};

// sensor_msgs/PointField.
struct PointFieldMsg {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;  // 1 INT8 .. 7 FLOAT32, 8 FLOAT64
  std::uint32_t count = 0;
};

// sensor_msgs/PointCloud2.
struct PointCloud2Msg {
  MsgHeader header;
  std::uint32_t height = 0, width = 0;
  std::vector<PointFieldMsg> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0, row_step = 0;
  std::vector<std::uint8_t> data;
  bool is_dense = false;
};

// sensor_msgs/Image.
struct ImageMsg {
  MsgHeader header;
  std::uint32_t height = 0, width = 0;
  std::string encoding;
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;
  std::vector<std::uint8_t> data;
};

// sensor_msgs/CameraInfo (with its RegionOfInterest).
struct CameraInfoMsg {
  MsgHeader header;
  std::uint32_t height = 0, width = 0;
  std::string distortion_model;
  std::vector<double> D;
  std::array<double, 9> K{};
  std::array<double, 9> R{};
  std::array<double, 12> P{};
  std::uint32_t binning_x = 0, binning_y = 0;
  std::uint32_t roi_x_offset = 0, roi_y_offset = 0, roi_height = 0, roi_width = 0;
  bool roi_do_rectify = false;
};

// geometry_msgs/TransformStamped.
struct TransformMsg {
  MsgHeader header;
  std::string child_frame_id;
  std::array<double, 3> translation{};
  std::array<double, 4> rotation{0, 0, 0, 1};  // x, y, z, w
};

// tf2_msgs/TFMessage.
struct TfMsg {
  std::vector<TransformMsg> transforms;
};

// Compression of the chunks a bag is written with.
enum class ChunkCompression : std::uint8_t { None = 0, Bz2 = 1, Lz4 = 2 };

// Writes a ROS 1 bag through the rosbag C++ API (rosbag::Bag). Errors of
// the library are thrown as std::runtime_error with its message.
class RosbagWriter {
 public:
  RosbagWriter(const std::string& path, ChunkCompression compression);
  ~RosbagWriter();
  RosbagWriter(const RosbagWriter&) = delete;
  RosbagWriter& operator=(const RosbagWriter&) = delete;

  // Each writes one message with the record time (sec, nsec).
  void write(const std::string& topic, std::uint32_t sec, std::uint32_t nsec, const LaserScanMsg& m);
  void write(const std::string& topic, std::uint32_t sec, std::uint32_t nsec, const OdometryMsg& m);
  void write(const std::string& topic, std::uint32_t sec, std::uint32_t nsec, const PointCloud2Msg& m);
  void write(const std::string& topic, std::uint32_t sec, std::uint32_t nsec, const ImageMsg& m);
  void write(const std::string& topic, std::uint32_t sec, std::uint32_t nsec, const CameraInfoMsg& m);
  void write(const std::string& topic, std::uint32_t sec, std::uint32_t nsec, const TfMsg& m);
  // A std_msgs/String (a type rove does not read; for the tests).
  void write_text(const std::string& topic, std::uint32_t sec, std::uint32_t nsec,
                  const std::string& text);
  // Closes the bag (writes its index). Called by the destructor otherwise.
  void close();

 private:
  struct Impl;
  Impl* impl_;
};

// The messages of a bag as the rosbag C++ API reads them (rosbag::View over
// every topic, in time order): topic, datatype and the serialized size of
// each. Used by the tests as an independent reader.
struct RosbagViewEntry {
  std::string topic;
  std::string datatype;
  std::uint32_t sec = 0, nsec = 0;
  std::uint32_t size = 0;
};
std::vector<RosbagViewEntry> read_with_rosbag_view(const std::string& path);

// The MD5 sums and datatypes that Debian's message packages define, as the
// generated headers state them (for the tests to check the reader's table).
struct RosTypeInfo {
  std::string datatype;
  std::string md5sum;
};
std::vector<RosTypeInfo> ros_type_infos();

}  // namespace rove::bag_detail
