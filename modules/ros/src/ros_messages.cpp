#include "ros_messages.h"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <vector>

#include "rove/core/error.h"

namespace rove::bag_detail {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the ROS wire format is little-endian; this reader copies fields as they are");

// Reads fields in order, checking each length against what is left.
class Cursor {
 public:
  Cursor(std::span<const std::uint8_t> bytes, const std::string& source)
      : bytes_(bytes), source_(source) {}

  template <typename T>
  T pod(std::string_view field) {
    need(sizeof(T), field);
    T v;
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::uint32_t count(std::string_view field, std::size_t element_bytes) {
    const auto n = pod<std::uint32_t>(field);
    if (element_bytes > 0 && n > (bytes_.size() - at_) / element_bytes) {
      fail(field, fmt::format("declares {} elements of {} bytes, only {} bytes are left", n,
                              element_bytes, bytes_.size() - at_));
    }
    return n;
  }
  std::string string(std::string_view field) {
    const std::uint32_t n = count(field, 1);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + at_), n);
    at_ += n;
    return s;
  }
  template <typename T>
  std::vector<T> vector(std::string_view field) {
    const std::uint32_t n = count(field, sizeof(T));
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), bytes_.data() + at_, n * sizeof(T));
    at_ += std::size_t{n} * sizeof(T);
    return v;
  }
  template <typename T, std::size_t N>
  void array(std::array<T, N>& a, std::string_view field) {
    need(N * sizeof(T), field);
    std::memcpy(a.data(), bytes_.data() + at_, N * sizeof(T));
    at_ += N * sizeof(T);
  }
  void header(MsgHeader& h) {
    h.seq = pod<std::uint32_t>("header.seq");
    h.sec = pod<std::uint32_t>("header.stamp.sec");
    h.nsec = pod<std::uint32_t>("header.stamp.nsec");
    h.frame_id = string("header.frame_id");
  }
  void finish(std::string_view type) {
    if (at_ != bytes_.size()) {
      fail(type, fmt::format("{} bytes after the last field (the message is {} bytes)",
                             bytes_.size() - at_, bytes_.size()));
    }
  }

 private:
  void need(std::size_t n, std::string_view field) {
    if (bytes_.size() - at_ < n) {
      fail(field, fmt::format("needs {} bytes, only {} are left", n, bytes_.size() - at_));
    }
  }
  [[noreturn]] void fail(std::string_view field, std::string problem) {
    throw ParseError({source_, std::nullopt, at_, std::string(field)}, std::move(problem));
  }

  std::span<const std::uint8_t> bytes_;
  const std::string& source_;
  std::size_t at_ = 0;
};

}  // namespace

void parse(std::span<const std::uint8_t> bytes, const std::string& source, LaserScanMsg& m) {
  Cursor c(bytes, source);
  c.header(m.header);
  m.angle_min = c.pod<float>("angle_min");
  m.angle_max = c.pod<float>("angle_max");
  m.angle_increment = c.pod<float>("angle_increment");
  m.time_increment = c.pod<float>("time_increment");
  m.scan_time = c.pod<float>("scan_time");
  m.range_min = c.pod<float>("range_min");
  m.range_max = c.pod<float>("range_max");
  m.ranges = c.vector<float>("ranges");
  m.intensities = c.vector<float>("intensities");
  c.finish(kLaserScanType);
}

void parse(std::span<const std::uint8_t> bytes, const std::string& source, OdometryMsg& m) {
  Cursor c(bytes, source);
  c.header(m.header);
  m.child_frame_id = c.string("child_frame_id");
  c.array(m.position, "pose.pose.position");
  c.array(m.orientation, "pose.pose.orientation");
  c.array(m.pose_covariance, "pose.covariance");
  c.array(m.linear, "twist.twist.linear");
  c.array(m.angular, "twist.twist.angular");
  c.array(m.twist_covariance, "twist.covariance");
  c.finish(kOdometryType);
}

void parse(std::span<const std::uint8_t> bytes, const std::string& source, PointCloud2Msg& m) {
  Cursor c(bytes, source);
  c.header(m.header);
  m.height = c.pod<std::uint32_t>("height");
  m.width = c.pod<std::uint32_t>("width");
  // A PointField is at least 13 bytes (empty name).
  const std::uint32_t n = c.count("fields", 13);
  m.fields.resize(n);
  for (PointFieldMsg& f : m.fields) {
    f.name = c.string("fields.name");
    f.offset = c.pod<std::uint32_t>("fields.offset");
    f.datatype = c.pod<std::uint8_t>("fields.datatype");
    f.count = c.pod<std::uint32_t>("fields.count");
  }
  m.is_bigendian = c.pod<std::uint8_t>("is_bigendian") != 0;
  m.point_step = c.pod<std::uint32_t>("point_step");
  m.row_step = c.pod<std::uint32_t>("row_step");
  m.data = c.vector<std::uint8_t>("data");
  m.is_dense = c.pod<std::uint8_t>("is_dense") != 0;
  c.finish(kPointCloud2Type);
}

void parse(std::span<const std::uint8_t> bytes, const std::string& source, ImageMsg& m) {
  Cursor c(bytes, source);
  c.header(m.header);
  m.height = c.pod<std::uint32_t>("height");
  m.width = c.pod<std::uint32_t>("width");
  m.encoding = c.string("encoding");
  m.is_bigendian = c.pod<std::uint8_t>("is_bigendian");
  m.step = c.pod<std::uint32_t>("step");
  m.data = c.vector<std::uint8_t>("data");
  c.finish(kImageType);
}

void parse(std::span<const std::uint8_t> bytes, const std::string& source, CameraInfoMsg& m) {
  Cursor c(bytes, source);
  c.header(m.header);
  m.height = c.pod<std::uint32_t>("height");
  m.width = c.pod<std::uint32_t>("width");
  m.distortion_model = c.string("distortion_model");
  m.D = c.vector<double>("D");
  c.array(m.K, "K");
  c.array(m.R, "R");
  c.array(m.P, "P");
  m.binning_x = c.pod<std::uint32_t>("binning_x");
  m.binning_y = c.pod<std::uint32_t>("binning_y");
  m.roi_x_offset = c.pod<std::uint32_t>("roi.x_offset");
  m.roi_y_offset = c.pod<std::uint32_t>("roi.y_offset");
  m.roi_height = c.pod<std::uint32_t>("roi.height");
  m.roi_width = c.pod<std::uint32_t>("roi.width");
  m.roi_do_rectify = c.pod<std::uint8_t>("roi.do_rectify") != 0;
  c.finish(kCameraInfoType);
}

void parse(std::span<const std::uint8_t> bytes, const std::string& source, TfMsg& m) {
  Cursor c(bytes, source);
  // A TransformStamped is at least 12 + 4 + 4 + 56 = 76 bytes.
  const std::uint32_t n = c.count("transforms", 76);
  m.transforms.resize(n);
  for (TransformMsg& t : m.transforms) {
    c.header(t.header);
    t.child_frame_id = c.string("transforms.child_frame_id");
    c.array(t.translation, "transforms.transform.translation");
    c.array(t.rotation, "transforms.transform.rotation");
  }
  c.finish(kTfType);
}

}  // namespace rove::bag_detail
