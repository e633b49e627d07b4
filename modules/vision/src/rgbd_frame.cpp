#include "rove/vision/rgbd_frame.h"

#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/frame_images.h"

namespace rove {

RgbdFrame read_rgbd_frame(const std::string& color_path, const std::string& depth_path,
                          double depth_scale) {
  ROVE_CHECK_MSG(std::isfinite(depth_scale) && depth_scale > 0.0,
                 "read_rgbd_frame: depth_scale = {} must be finite and > 0", depth_scale);
  check_regular_input(color_path, "color image");
  check_regular_input(depth_path, "depth image");
  ColorImage8 color = read_color_image(color_path);
  DepthImage16 depth = read_depth_image(depth_path);
  if (color.width != depth.width || color.height != depth.height) {
    throw ParseError({depth_path, std::nullopt, std::nullopt, "depth image"},
                     fmt::format("depth image is {}x{} but its color image '{}' is {}x{}",
                                 depth.width, depth.height, printable(color_path), color.width,
                                 color.height));
  }
  RgbdFrame frame;
  frame.color = Image::zeros(color.width, color.height, 3, PixelType::U8);
  frame.color.data = std::move(color.rgb);
  frame.depth = DepthImage::zeros_u16(depth.width, depth.height, depth_scale);
  auto& values = std::get<std::vector<std::uint16_t>>(frame.depth.values);
  values = std::move(depth.values);
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
