#include "rove/vision/range_image_frame.h"

#include <cmath>
#include <vector>

#include "rove/core/check.h"
#include "rove/poses/lie_conversion.h"

namespace rove {

PinholeCamera intensity_camera_of(const RangeImage3D& observation) {
  ROVE_CHECK_MSG(observation.intensity.has_value(), "the 3D range observation has no intensity image");
  PinholeCamera c = observation.intensity_camera;
  if (c.width == 0 && c.height == 0) {
    c.width = observation.intensity->width;
    c.height = observation.intensity->height;
  }
  return c;
}

RgbdFrame rgbd_frame_from_range_image(const RangeImage3D& observation) {
  observation.check();
  ROVE_CHECK_MSG(observation.intensity.has_value(), "the 3D range observation has no intensity image");
  const Image& image = *observation.intensity;
  ROVE_CHECK_MSG(image.pixel_type == PixelType::U8 && (image.channels == 1 || image.channels == 3),
                 "the intensity image must have 8-bit samples and 1 or 3 channels, it has {} channels",
                 image.channels);
  ROVE_CHECK_MSG(observation.depth.pixel_count() > 0, "the 3D range observation has no depth image");
  const PinholeCamera camera = intensity_camera_of(observation);
  ROVE_CHECK_MSG(camera.width == image.width && camera.height == image.height,
                 "the intensity image is {}x{}, its camera {}x{}", image.width, image.height, camera.width,
                 camera.height);

  RgbdFrame frame;
  frame.color = image;
  frame.depth = DepthImage::zeros_f32(image.width, image.height, 1.0);
  auto& depth = std::get<std::vector<float>>(frame.depth.values);

  RangeImageProjectionOptions po;
  po.frame = RangeImageFrame::Optical;
  const RangeImageProjection proj = observation.project(po);
  // T_intensity_depth: the depth camera's optical frame seen from the
  // intensity camera's, both through the sensor frame.
  const SE3d T_intensity_depth =
      to_se3(observation.T_sensor_intensity).inverse() * to_se3(sensor_from_optical());
  const Eigen::Matrix3d R = T_intensity_depth.rotation_matrix();
  const Eigen::Vector3d t = T_intensity_depth.translation();
  const double w = image.width, h = image.height;
  for (const Eigen::Vector3d& p : proj.points) {
    const Eigen::Vector3d q = R * p + t;
    if (!(q.z() > 0.0)) continue;
    const Eigen::Vector2d px = camera.project(q);
    const double u = std::round(px.x()), v = std::round(px.y());
    if (!(u >= 0.0 && v >= 0.0 && u < w && v < h)) continue;
    float& d = depth[static_cast<std::size_t>(v) * image.width + static_cast<std::size_t>(u)];
    const auto z = static_cast<float>(q.z());
    if (d == 0.0f || z < d) d = z;
  }
  for (const float d : depth) frame.valid_depth_pixels += d > 0.0f ? 1 : 0;
  return frame;
}

}  // namespace rove
