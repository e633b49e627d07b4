#include "rove/obs/range_image_3d.h"

#include <cmath>
#include <span>
#include <string>

#include "archive_helpers.h"
#include "rove/core/check.h"
#include "rove/poses/angle.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {

Pose3 sensor_from_optical() { return Pose3(0.0, 0.0, 0.0, -kPi / 2.0, 0.0, -kPi / 2.0); }

void RangeImage3D::check() const {
  depth.check();
  depth_camera.check();
  ROVE_CHECK_MSG(depth.pixel_count() == 0 ||
                     (depth.width == depth_camera.width && depth.height == depth_camera.height),
                 "RangeImage3D: depth image is {}x{} but depth_camera is {}x{}", depth.width,
                 depth.height, depth_camera.width, depth_camera.height);
  for (const auto& [name, layer] : other_depth_layers) {
    layer.check();
    ROVE_CHECK_MSG(layer.width == depth.width && layer.height == depth.height,
                   "RangeImage3D: depth layer '{}' is {}x{} but depth is {}x{}", name,
                   layer.width, layer.height, depth.width, depth.height);
  }
  if (points) {
    const std::size_t n = points->p_sensor.size();
    ROVE_CHECK_MSG((points->pixel_u.empty() && points->pixel_v.empty()) ||
                       (points->pixel_u.size() == n && points->pixel_v.size() == n),
                   "RangeImage3D: {} points but {}/{} pixel coordinates", n,
                   points->pixel_u.size(), points->pixel_v.size());
  }
  if (confidence) confidence->check();
  ROVE_CHECK_MSG(!std::isnan(max_range) && max_range > 0.0,
                 "RangeImage3D: max_range {} m must be > 0", max_range);
  if (intensity) intensity->check();
}

RangeImageProjection RangeImage3D::project(const RangeImageProjectionOptions& options) const {
  check();
  // Output = R · p_optical + t for the requested frame.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  if (options.frame != RangeImageFrame::Optical) {
    Pose3 T = sensor_from_optical();
    if (options.frame == RangeImageFrame::Robot) {
      T = T_robot_sensor + T;
      if (options.T_target_robot) T = *options.T_target_robot + T;
    }
    R = T.rotation();
    t = T.translation();
  }
  const bool transform = options.frame != RangeImageFrame::Optical;
  const bool distorted = depth_camera.has_distortion();

  RangeImageProjection out;
  const std::size_t n = depth.pixel_count();
  out.points.reserve(n);
  out.pixel_u.reserve(n);
  out.pixel_v.reserve(n);
  std::visit(
      [&](const auto& values) {
        std::size_t i = 0;
        for (std::uint32_t v = 0; v < depth.height; ++v) {
          for (std::uint32_t u = 0; u < depth.width; ++u, ++i) {
            const double s = static_cast<double>(values[i]) / depth.scale;
            if (!(std::isfinite(s) && s > 0.0 && s <= max_range)) continue;
            // Ray through pixel (u, v): (a, b, 1); Hartley & Zisserman eq. 6.4 inverted.
            Eigen::Vector3d ray;
            if (distorted) {
              ray = depth_camera.unproject(u, v);
            } else {
              ray << (u - depth_camera.cx) / depth_camera.fx,
                  (v - depth_camera.cy) / depth_camera.fy, 1.0;
            }
            const Eigen::Vector3d p = range_is_depth ? Eigen::Vector3d(ray * s)
                                                     : Eigen::Vector3d(ray * (s / ray.norm()));
            out.points.push_back(transform ? Eigen::Vector3d(R * p + t) : p);
            out.pixel_u.push_back(u);
            out.pixel_v.push_back(v);
          }
        }
      },
      depth.values);
  return out;
}

bool operator==(const RangeImage3D& a, const RangeImage3D& b) {
  return a.header_equals(b) && a.depth == b.depth && a.range_is_depth == b.range_is_depth &&
         a.max_range == b.max_range && a.depth_camera == b.depth_camera &&
         a.intensity == b.intensity && a.intensity_camera == b.intensity_camera &&
         a.T_sensor_intensity == b.T_sensor_intensity &&
         a.intensity_channel == b.intensity_channel && a.confidence == b.confidence &&
         a.points == b.points && a.std_error_m == b.std_error_m &&
         a.other_depth_layers == b.other_depth_layers;
}

void RangeImage3D::save_payload(OutArchive& ar) const {
  save_header(ar);
  save(ar, depth);
  ar.write_scalar(range_is_depth);
  ar.write_scalar(max_range);
  save(ar, depth_camera);
  save(ar, intensity);
  save(ar, intensity_camera);
  detail::save_pose3(ar, T_sensor_intensity);
  // version 2
  ar.write_scalar(static_cast<std::uint8_t>(intensity_channel));
  save(ar, confidence);
  save(ar, points);
  ar.write_scalar(std_error_m);
  save(ar, other_depth_layers);
}

void save(OutArchive& ar, const RangeImagePoints& p) {
  write_version(ar, 1);
  ar.write_length(p.p_sensor.size(), "points");
  for (const Eigen::Vector3f& v : p.p_sensor) {
    ar.write_scalars(std::span<const float>(v.data(), 3));
  }
  save(ar, p.pixel_u);
  save(ar, p.pixel_v);
}

void load(InArchive& ar, RangeImagePoints& p) {
  read_version(ar, "RangeImagePoints", 1);
  const std::uint32_t n = ar.read_length("points", 3 * sizeof(float));
  p.p_sensor.assign(n, Eigen::Vector3f::Zero());
  for (Eigen::Vector3f& v : p.p_sensor) ar.read_scalars(std::span<float>(v.data(), 3), "points");
  const std::uint64_t at = ar.offset();
  load(ar, p.pixel_u);
  load(ar, p.pixel_v);
  if (!((p.pixel_u.empty() && p.pixel_v.empty()) ||
        (p.pixel_u.size() == n && p.pixel_v.size() == n))) {
    ar.fail_at(at, "pixel_u", "pixel coordinates do not match the point count");
  }
}

void RangeImage3D::load_payload(InArchive& ar, std::uint8_t version) {
  const std::uint64_t start = ar.offset();
  load_header(ar);
  load(ar, depth);
  range_is_depth = ar.read_scalar<bool>("range_is_depth");
  max_range = ar.read_scalar<double>("max_range");
  load(ar, depth_camera);
  load(ar, intensity);
  load(ar, intensity_camera);
  T_sensor_intensity = detail::load_pose3(ar, "T_sensor_intensity");
  intensity_channel = IntensityChannel::Visible;
  confidence.reset();
  points.reset();
  std_error_m = 0.01;
  other_depth_layers.clear();
  if (version >= 2) {
    const std::uint64_t at = ar.offset();
    const auto c = ar.read_scalar<std::uint8_t>("intensity_channel");
    if (c > 1) ar.fail_at(at, "intensity_channel", "unknown intensity channel " + std::to_string(c));
    intensity_channel = static_cast<IntensityChannel>(c);
    load(ar, confidence);
    load(ar, points);
    std_error_m = ar.read_scalar<double>("std_error");
    load(ar, other_depth_layers);
  }
  // Each part reads on its own; with a depth image they must agree (image
  // sizes, camera, a positive maximum range). One without a depth image
  // (e.g. default-constructed, camera unset) is stored as it was written.
  if (depth.pixel_count() > 0) parse_guard(ar, start, kClassName, [&] { check(); });
}

}  // namespace rove
