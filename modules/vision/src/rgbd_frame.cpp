#include "rove/vision/rgbd_frame.h"

#include <cmath>
#include <cstring>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {
namespace {

cv::Mat decode(const std::string& path, int flags, std::string_view what) {
  check_regular_input(path, what);
  cv::Mat m = cv::imread(path, flags);
  if (m.empty()) {
    throw ParseError({path, std::nullopt, std::nullopt, std::string(what)},
                     fmt::format("not an image file OpenCV can decode ({})", what));
  }
  return m;
}

std::string depth_type_name(int type) {
  switch (CV_MAT_DEPTH(type)) {
    case CV_8U: return "8-bit";
    case CV_16U: return "16-bit";
    case CV_32F: return "32-bit float";
    default: return fmt::format("OpenCV type {}", type);
  }
}

}  // namespace

RgbdFrame read_rgbd_frame(const std::string& color_path, const std::string& depth_path,
                          double depth_scale) {
  ROVE_CHECK_MSG(std::isfinite(depth_scale) && depth_scale > 0.0,
                 "read_rgbd_frame: depth_scale = {} must be finite and > 0", depth_scale);
  cv::Mat bgr = decode(color_path, cv::IMREAD_COLOR, "color image");
  cv::Mat depth = decode(depth_path, cv::IMREAD_UNCHANGED, "depth image");
  if (depth.type() != CV_16UC1) {
    throw ParseError(
        {depth_path, std::nullopt, std::nullopt, "depth image"},
        fmt::format("a depth image must be 16-bit with one channel; this one is {} with {} "
                    "channel(s) (an 8-bit depth image has lost its range)",
                    depth_type_name(depth.type()), depth.channels()));
  }
  if (bgr.rows != depth.rows || bgr.cols != depth.cols) {
    throw ParseError({depth_path, std::nullopt, std::nullopt, "depth image"},
                     fmt::format("depth image is {}x{} but its color image '{}' is {}x{}",
                                 depth.cols, depth.rows, printable(color_path), bgr.cols,
                                 bgr.rows));
  }
  RgbdFrame frame;
  const auto w = static_cast<std::uint32_t>(bgr.cols), h = static_cast<std::uint32_t>(bgr.rows);
  frame.color = Image::zeros(w, h, 3, PixelType::U8);
  cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, frame.color.data.data());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  frame.depth = DepthImage::zeros_u16(w, h, depth_scale);
  auto& values = std::get<std::vector<std::uint16_t>>(frame.depth.values);
  for (int r = 0; r < depth.rows; ++r) {
    std::memcpy(values.data() + static_cast<std::size_t>(r) * w, depth.ptr<std::uint16_t>(r),
                w * sizeof(std::uint16_t));
  }
  for (const std::uint16_t v : values) frame.valid_depth_pixels += v != 0 ? 1 : 0;
  if (frame.valid_depth_pixels == 0) {
    throw ParseError({depth_path, std::nullopt, std::nullopt, "depth image"},
                     "the depth image has no measurement (every pixel is 0)");
  }
  return frame;
}

bool depth_point(const DepthImage& depth, const PinholeCamera& camera, double u, double v,
                 double min_depth, double max_depth, Eigen::Vector3d& p_camera) {
  const double ur = std::round(u), vr = std::round(v);
  if (!(ur >= 0.0 && vr >= 0.0 && ur < depth.width && vr < depth.height)) return false;
  const double z = depth.meters(static_cast<std::uint32_t>(ur), static_cast<std::uint32_t>(vr));
  if (!(z >= min_depth && z <= max_depth)) return false;
  p_camera = z * camera.unproject(u, v);
  return true;
}

PointCloud rgbd_to_cloud(const RgbdFrame& frame, const PinholeCamera& camera,
                         const RgbdCloudOptions& options) {
  camera.check();
  frame.color.check();
  frame.depth.check();
  ROVE_CHECK_GE(options.stride, 1u);
  ROVE_CHECK_MSG(options.min_depth >= 0.0 && options.max_depth >= options.min_depth,
                 "rgbd_to_cloud: depth range [{}, {}] is invalid", options.min_depth,
                 options.max_depth);
  ROVE_CHECK_MSG(frame.color.width == frame.depth.width && frame.color.height == frame.depth.height,
                 "rgbd_to_cloud: color {}x{} and depth {}x{} differ", frame.color.width,
                 frame.color.height, frame.depth.width, frame.depth.height);
  ROVE_CHECK_MSG(camera.width == 0 || (camera.width == frame.depth.width &&
                                       camera.height == frame.depth.height),
                 "rgbd_to_cloud: camera {}x{} does not match the frame's {}x{}", camera.width,
                 camera.height, frame.depth.width, frame.depth.height);
  ROVE_CHECK_MSG(frame.color.pixel_type == PixelType::U8 &&
                     (frame.color.channels == 1 || frame.color.channels == 3),
                 "rgbd_to_cloud: color must be 8-bit gray or RGB ({} channels)",
                 frame.color.channels);
  PointCloud cloud;
  cloud.set_channels(PointChannels::Color);
  const Eigen::Matrix3d R = options.T_target_camera.rotation().matrix();
  const Eigen::Vector3d t = options.T_target_camera.translation();
  const bool distorted = camera.has_distortion();
  const std::uint32_t c = frame.color.channels;
  for (std::uint32_t v = 0; v < frame.depth.height; v += options.stride) {
    for (std::uint32_t u = 0; u < frame.depth.width; u += options.stride) {
      const double z = frame.depth.meters(u, v);
      if (!(z >= options.min_depth && z <= options.max_depth)) continue;
      const Eigen::Vector3d ray =
          distorted ? camera.unproject(u, v)
                    : Eigen::Vector3d((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
      const Eigen::Vector3d p = R * (z * ray) + t;
      const std::size_t i = (static_cast<std::size_t>(v) * frame.color.width + u) * c;
      const std::uint8_t* px = frame.color.data.data() + i;
      cloud.push_back(p.cast<float>(), Rgb8{px[0], px[c == 3 ? 1 : 0], px[c == 3 ? 2 : 0]});
    }
  }
  return cloud;
}

}  // namespace rove
