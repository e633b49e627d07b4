#include "ros_convert.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>

#include "rove/core/error.h"
#include "rove/core/memory_budget.h"
#include "rove/poses/angle.h"
#include "rove/poses/pose3_quat.h"

namespace rove::bag_detail {
namespace {

// Slack between a scan's angle_max − angle_min and angle_increment ·
// (rays − 1): float32 rounding of each field.
constexpr double kAngleSlack = 1e-5;

std::uint16_t swap16(std::uint16_t v) { return static_cast<std::uint16_t>((v >> 8) | (v << 8)); }

// Checks an image message's shape; returns the bytes per pixel.
std::size_t check_image(const ImageMsg& m, std::size_t bytes_per_pixel) {
  const std::uint64_t row = std::uint64_t{m.width} * bytes_per_pixel;
  if (m.width == 0 || m.height == 0) throw InvalidArgument("empty image (width or height 0)");
  if (m.step < row) {
    throw InvalidArgument(fmt::format("step {} is less than width {} × {} bytes", m.step, m.width,
                                      bytes_per_pixel));
  }
  if (std::uint64_t{m.step} * m.height > m.data.size()) {
    throw InvalidArgument(fmt::format("data holds {} bytes, step {} × height {} needs {}",
                                      m.data.size(), m.step, m.height,
                                      std::uint64_t{m.step} * m.height));
  }
  check_memory_budget(row * m.height, "an image from a ROS bag");
  return bytes_per_pixel;
}

}  // namespace

std::string normalize_frame(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

std::string topic_namespace(const std::string& topic) {
  const auto slash = topic.rfind('/');
  return slash == std::string::npos ? std::string() : topic.substr(0, slash);
}

std::string label_of_topic(const std::string& topic) {
  std::size_t begin = topic.find_first_not_of('/');
  if (begin == std::string::npos) return topic;
  const std::size_t end = topic.find('/', begin);
  return topic.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

std::string ros_name(const std::string& label, const std::string& fallback) {
  if (label.empty()) return fallback;
  std::string out;
  for (char ch : label) {
    const auto c = static_cast<unsigned char>(ch);
    out += std::isalnum(c) || c == '_' ? ch : '_';
  }
  if (!std::isalpha(static_cast<unsigned char>(out[0]))) out = "s_" + out;
  return out;
}

std::int64_t stamp_or(const MsgHeader& h, std::int64_t fallback_ns) {
  if (h.sec == 0 && h.nsec == 0) return fallback_ns;
  return std::int64_t{h.sec} * 1'000'000'000 + h.nsec;
}

void set_stamp(MsgHeader& h, Timestamp t) {
  if (!t.valid() || t.ns < 0 || t.ns / 1'000'000'000 > std::numeric_limits<std::uint32_t>::max()) {
    h.sec = h.nsec = 0;
    return;
  }
  h.sec = static_cast<std::uint32_t>(t.ns / 1'000'000'000);
  h.nsec = static_cast<std::uint32_t>(t.ns % 1'000'000'000);
}

Pose3 pose3_from_ros(const std::array<double, 3>& t, const std::array<double, 4>& q) {
  return Pose3(Pose3Quat(t[0], t[1], t[2], q[3], q[0], q[1], q[2]));
}

void pose3_to_ros(const Pose3& p, std::array<double, 3>& t, std::array<double, 4>& q) {
  const Pose3Quat pq(p);
  t = {pq.x(), pq.y(), pq.z()};
  q = {pq.qx(), pq.qy(), pq.qz(), pq.qw()};
}

void TfTree::set(const TransformMsg& t) {
  const std::string child = normalize_frame(t.child_frame_id);
  const std::string parent = normalize_frame(t.header.frame_id);
  if (child.empty() || parent.empty() || child == parent) {
    throw InvalidArgument(fmt::format("transform with frames \"{}\" ← \"{}\"", parent, child));
  }
  parent_of_.insert_or_assign(child, std::make_pair(parent, pose3_from_ros(t.translation, t.rotation)));
}

std::optional<Pose3> TfTree::lookup(const std::string& base, const std::string& frame) const {
  const std::string b = normalize_frame(base);
  std::string cur = normalize_frame(frame);
  Pose3 T;
  for (int depth = 0; depth < 64; ++depth) {
    if (cur == b) return T;
    auto it = parent_of_.find(cur);
    if (it == parent_of_.end()) return std::nullopt;
    T = it->second.second + T;
    cur = it->second.first;
  }
  return std::nullopt;  // a cycle or an absurdly deep tree
}

bool ros_range_valid(float r, float range_min, float range_max) {
  return std::isfinite(r) && r >= range_min && r <= range_max;
}

std::shared_ptr<RangeScan2D> scan_from_ros(const LaserScanMsg& m, const std::string& where) {
  const std::size_t n = m.ranges.size();
  if (n < 2) throw InvalidArgument(fmt::format("{}: a scan of {} rays (rove needs 2 or more)", where, n));
  const double inc = m.angle_increment;
  if (!std::isfinite(inc) || inc == 0.0 || !std::isfinite(m.angle_min)) {
    throw InvalidArgument(fmt::format("{}: angle_increment {} / angle_min {}", where, inc, m.angle_min));
  }
  // The field of view: angle_max − angle_min when the rays span it (as
  // rosbag drivers and rove's writer state it; exact for the float32
  // apertures of MRPT logs), else what the increment spans.
  const double spanned = std::abs(inc) * static_cast<double>(n - 1);
  const double stated = std::abs(double{m.angle_max} - double{m.angle_min});
  const double aperture = std::abs(stated - spanned) <= kAngleSlack * std::max(1.0, spanned)
                              ? stated
                              : spanned;
  if (aperture > 2.0 * kPi + kAngleSlack) {
    throw InvalidArgument(fmt::format("{}: the rays span {} rad, more than a turn", where, aperture));
  }
  auto s = std::make_shared<RangeScan2D>();
  s->aperture = std::min(aperture, 2.0 * kPi);
  s->right_to_left = inc > 0.0;
  // The direction of the middle ray: zero for the usual symmetric scans.
  double center = aperture == stated ? (double{m.angle_min} + double{m.angle_max}) / 2.0
                                     : m.angle_min + inc * static_cast<double>(n - 1) / 2.0;
  if (center != 0.0) s->T_robot_sensor = Pose3(0, 0, 0, center, 0, 0);
  s->max_range = m.range_max;
  s->ranges = m.ranges;
  s->valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) s->valid[i] = ros_range_valid(m.ranges[i], m.range_min, m.range_max);
  if (m.intensities.size() == n) {
    s->intensity.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float v = m.intensities[i];
      s->intensity[i] = !std::isfinite(v) ? 0
                        : v >= 2147483647.0f ? std::numeric_limits<std::int32_t>::max()
                        : v <= -2147483648.0f ? std::numeric_limits<std::int32_t>::min()
                                              : static_cast<std::int32_t>(std::lround(v));
    }
  }
  return s;
}

LaserScanMsg scan_to_ros(const RangeScan2D& s) {
  s.check();
  LaserScanMsg m;
  const std::size_t n = s.size();
  const double half = s.aperture / 2.0;
  const double inc = n >= 2 ? s.aperture / static_cast<double>(n - 1) : 0.0;
  m.angle_min = static_cast<float>(s.right_to_left ? -half : half);
  m.angle_max = static_cast<float>(s.right_to_left ? half : -half);
  m.angle_increment = static_cast<float>(s.right_to_left ? inc : -inc);
  m.range_min = 0.0f;
  m.range_max = s.max_range;
  m.ranges = s.ranges;
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.valid[i] && ros_range_valid(m.ranges[i], m.range_min, m.range_max)) {
      m.ranges[i] = std::numeric_limits<float>::infinity();  // REP 117: no return
    }
  }
  if (!s.intensity.empty()) {
    m.intensities.resize(n);
    for (std::size_t i = 0; i < n; ++i) m.intensities[i] = static_cast<float>(s.intensity[i]);
  }
  return m;
}

Pose2 pose2_from_ros(const OdometryMsg& m, const std::string& where) {
  for (double v : m.position) {
    if (!std::isfinite(v)) throw InvalidArgument(fmt::format("{}: non-finite position", where));
  }
  return Pose2(pose3_from_ros(m.position, m.orientation));
}

std::shared_ptr<RangeImage3D> cloud_from_ros(const PointCloud2Msg& m, const std::string& where) {
  if (m.is_bigendian) throw InvalidArgument(where + ": big-endian point cloud");
  const PointFieldMsg* f[3] = {nullptr, nullptr, nullptr};
  for (const PointFieldMsg& pf : m.fields) {
    for (int k = 0; k < 3; ++k) {
      if (pf.name == std::string(1, static_cast<char>('x' + k))) f[k] = &pf;
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (f[k] == nullptr || (f[k]->datatype != 7 && f[k]->datatype != 8)) {
      throw InvalidArgument(fmt::format("{}: no float32/float64 field \"{}\"", where,
                                        static_cast<char>('x' + k)));
    }
    const std::uint32_t bytes = f[k]->datatype == 7 ? 4 : 8;
    if (std::uint64_t{f[k]->offset} + bytes > m.point_step) {
      throw InvalidArgument(fmt::format("{}: field \"{}\" at offset {} lies outside point_step {}",
                                        where, static_cast<char>('x' + k), f[k]->offset, m.point_step));
    }
  }
  if (std::uint64_t{m.point_step} * m.width > m.row_step ||
      std::uint64_t{m.row_step} * m.height > m.data.size()) {
    throw InvalidArgument(fmt::format("{}: {} × {} points of {} bytes (rows of {}) do not fit in {} bytes",
                                      where, m.width, m.height, m.point_step, m.row_step, m.data.size()));
  }
  auto obs = std::make_shared<RangeImage3D>();
  RangeImagePoints pts;
  const bool organized = m.height > 1 && m.width <= 65536 && m.height <= 65536;
  check_memory_budget(std::uint64_t{m.width} * m.height * 12, "a point cloud from a ROS bag");
  for (std::uint32_t v = 0; v < m.height; ++v) {
    for (std::uint32_t u = 0; u < m.width; ++u) {
      const std::uint8_t* p = m.data.data() + std::size_t{v} * m.row_step + std::size_t{u} * m.point_step;
      Eigen::Vector3f xyz;
      for (int k = 0; k < 3; ++k) {
        if (f[k]->datatype == 7) {
          float x;
          std::memcpy(&x, p + f[k]->offset, 4);
          xyz[k] = x;
        } else {
          double x;
          std::memcpy(&x, p + f[k]->offset, 8);
          xyz[k] = static_cast<float>(x);
        }
      }
      if (!xyz.allFinite()) continue;
      pts.p_sensor.push_back(xyz);
      if (organized) {
        pts.pixel_u.push_back(static_cast<std::uint16_t>(u));
        pts.pixel_v.push_back(static_cast<std::uint16_t>(v));
      }
    }
  }
  obs->points = std::move(pts);
  obs->max_range = std::numeric_limits<double>::infinity();
  return obs;
}

PointCloud2Msg cloud_to_ros(const RangeImagePoints& p) {
  PointCloud2Msg m;
  m.height = 1;
  m.width = static_cast<std::uint32_t>(p.p_sensor.size());
  m.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
  m.point_step = 12;
  m.row_step = 12 * m.width;
  m.data.resize(std::size_t{m.row_step});
  bool dense = true;
  for (std::size_t i = 0; i < p.p_sensor.size(); ++i) {
    std::memcpy(m.data.data() + 12 * i, p.p_sensor[i].data(), 12);
    dense = dense && p.p_sensor[i].allFinite();
  }
  m.is_dense = dense;
  return m;
}

bool is_depth_encoding(const std::string& e) {
  return e == "16UC1" || e == "mono16" || e == "32FC1";
}

PinholeCamera camera_from_ros(const CameraInfoMsg& c) {
  PinholeCamera cam;
  cam.width = c.width;
  cam.height = c.height;
  cam.fx = c.K[0];
  cam.fy = c.K[4];
  cam.cx = c.K[2];
  cam.cy = c.K[5];
  const bool brown = c.distortion_model == "plumb_bob" || c.distortion_model == "rational_polynomial";
  for (std::size_t i = 0; i < c.D.size(); ++i) {
    if (brown && i < 5) {
      cam.distortion[i] = c.D[i];
    } else if (c.D[i] != 0.0) {
      throw InvalidArgument(fmt::format("distortion model \"{}\" with {} coefficients (rove models "
                                        "plumb_bob's five)", c.distortion_model, c.D.size()));
    }
  }
  cam.check();
  return cam;
}

CameraInfoMsg camera_to_ros(const PinholeCamera& c) {
  CameraInfoMsg m;
  m.width = c.width;
  m.height = c.height;
  m.distortion_model = "plumb_bob";
  m.D.assign(c.distortion.begin(), c.distortion.end());
  m.K = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
  m.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.P = {c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0};
  return m;
}

std::shared_ptr<RangeImage3D> depth_from_ros(const ImageMsg& m, const CameraInfoMsg* info,
                                             const std::string& where) {
  if (info == nullptr) {
    throw InvalidArgument(where + ": no sensor_msgs/CameraInfo in the image's namespace before it");
  }
  auto obs = std::make_shared<RangeImage3D>();
  obs->depth_camera = camera_from_ros(*info);
  if (obs->depth_camera.width != m.width || obs->depth_camera.height != m.height) {
    throw InvalidArgument(fmt::format("{}: a {}×{} image with a {}×{} CameraInfo", where, m.width,
                                      m.height, obs->depth_camera.width, obs->depth_camera.height));
  }
  const bool f32 = m.encoding == "32FC1";
  check_image(m, f32 ? 4 : 2);
  if (f32) {
    obs->depth = DepthImage::zeros_f32(m.width, m.height, 1.0);
    auto& v = std::get<std::vector<float>>(obs->depth.values);
    for (std::uint32_t r = 0; r < m.height; ++r) {
      for (std::uint32_t u = 0; u < m.width; ++u) {
        std::uint32_t bits;
        std::memcpy(&bits, m.data.data() + std::size_t{r} * m.step + 4 * u, 4);
        if (m.is_bigendian) bits = __builtin_bswap32(bits);
        std::memcpy(&v[std::size_t{r} * m.width + u], &bits, 4);
      }
    }
  } else {
    obs->depth = DepthImage::zeros_u16(m.width, m.height, 1000.0);
    auto& v = std::get<std::vector<std::uint16_t>>(obs->depth.values);
    for (std::uint32_t r = 0; r < m.height; ++r) {
      for (std::uint32_t u = 0; u < m.width; ++u) {
        std::uint16_t x;
        std::memcpy(&x, m.data.data() + std::size_t{r} * m.step + 2 * u, 2);
        v[std::size_t{r} * m.width + u] = m.is_bigendian ? swap16(x) : x;
      }
    }
  }
  obs->max_range = std::numeric_limits<double>::infinity();
  return obs;
}

std::shared_ptr<ImageObservation> image_from_ros(const ImageMsg& m, const CameraInfoMsg* info,
                                                 const std::string& where) {
  struct Enc {
    const char* name;
    std::uint32_t channels;
    bool swap_rb;
  };
  static constexpr Enc kEncodings[] = {{"rgb8", 3, false}, {"bgr8", 3, true},   {"rgba8", 4, false},
                                       {"bgra8", 4, true}, {"mono8", 1, false}, {"8UC1", 1, false},
                                       {"8UC3", 3, true}};
  const Enc* enc = nullptr;
  for (const Enc& e : kEncodings) {
    if (m.encoding == e.name) enc = &e;
  }
  if (enc == nullptr) {
    throw InvalidArgument(fmt::format("{}: image encoding \"{}\" (rove reads rgb8, bgr8, rgba8, "
                                      "bgra8, mono8, 8UC1, 8UC3, and 16UC1/mono16/32FC1 as depth)",
                                      where, m.encoding));
  }
  check_image(m, enc->channels);
  auto obs = std::make_shared<ImageObservation>();
  obs->image = Image::zeros(m.width, m.height, enc->channels, PixelType::U8);
  const std::size_t row = std::size_t{m.width} * enc->channels;
  for (std::uint32_t r = 0; r < m.height; ++r) {
    std::uint8_t* out = obs->image.data.data() + r * row;
    std::memcpy(out, m.data.data() + std::size_t{r} * m.step, row);
    if (enc->swap_rb) {
      for (std::size_t i = 0; i < row; i += enc->channels) std::swap(out[i], out[i + 2]);
    }
  }
  if (info != nullptr) {
    obs->camera = camera_from_ros(*info);
    if (obs->camera.width != m.width || obs->camera.height != m.height) {
      throw InvalidArgument(fmt::format("{}: a {}×{} image with a {}×{} CameraInfo", where, m.width,
                                        m.height, obs->camera.width, obs->camera.height));
    }
  }
  return obs;
}

void attach_intensity(RangeImage3D& rgbd, const ImageObservation& color) {
  rgbd.intensity = color.image;
  rgbd.intensity_camera = color.camera;
  rgbd.T_sensor_intensity = rgbd.T_robot_sensor.inverse() + color.T_robot_sensor;
}

ImageMsg depth_to_ros(const DepthImage& d) {
  d.check();
  ImageMsg m;
  m.width = d.width;
  m.height = d.height;
  if (const auto* u16 = std::get_if<std::vector<std::uint16_t>>(&d.values); u16 && d.scale == 1000.0) {
    m.encoding = "16UC1";
    m.step = 2 * d.width;
    m.data.resize(u16->size() * 2);
    std::memcpy(m.data.data(), u16->data(), m.data.size());
    return m;
  }
  m.encoding = "32FC1";
  m.step = 4 * d.width;
  m.data.resize(d.pixel_count() * 4);
  for (std::uint32_t v = 0; v < d.height; ++v) {
    for (std::uint32_t u = 0; u < d.width; ++u) {
      const float meters = static_cast<float>(d.meters(u, v));
      std::memcpy(m.data.data() + 4 * (std::size_t{v} * d.width + u), &meters, 4);
    }
  }
  return m;
}

ImageMsg image_to_ros(const Image& image) {
  image.check();
  ImageMsg m;
  m.width = image.width;
  m.height = image.height;
  const auto bps = bytes_per_sample(image.pixel_type);
  if (image.pixel_type == PixelType::U8 && image.channels == 1) m.encoding = "mono8";
  else if (image.pixel_type == PixelType::U8 && image.channels == 3) m.encoding = "rgb8";
  else if (image.pixel_type == PixelType::U8 && image.channels == 4) m.encoding = "rgba8";
  else if (image.pixel_type == PixelType::U16 && image.channels == 1) m.encoding = "mono16";
  else if (image.pixel_type == PixelType::F32 && image.channels == 1) m.encoding = "32FC1";
  else {
    throw InvalidArgument(fmt::format("an image of {} channels of {}-byte samples has no ROS encoding",
                                      image.channels, bps));
  }
  m.step = static_cast<std::uint32_t>(image.width * image.channels * bps);
  m.data = image.data;
  return m;
}

}  // namespace rove::bag_detail
