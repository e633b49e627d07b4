#pragma once
/// \file
/// RGB-D frames: a color image and a depth image registered to it (same
/// size, pixel (u, v) of both seeing the same ray), read from image files,
/// and turned into colored point clouds.

#include <cstddef>
#include <cstdint>
#include <string>

#include "rove/maps/point_cloud.h"
#include "rove/math/se3.h"
#include "rove/obs/depth_image.h"
#include "rove/obs/image.h"
#include "rove/obs/pinhole_camera.h"

namespace rove {

/// A color image and its registered depth image. A plain value.
struct RgbdFrame {
  /// 8-bit color, 3 channels R, G, B (or 1 channel gray).
  Image color;
  /// Depth registered to `color` (same width and height); 0 = no measurement.
  DepthImage depth;
  /// Number of depth pixels with a measurement (> 0).
  std::size_t valid_depth_pixels = 0;
};

/// Reads a color image (PNG, JPEG, … as OpenCV decodes them; stored as RGB)
/// and a 16-bit depth PNG whose values are `depth_scale` units per meter
/// (5000 for TUM and ICL-NUIM, 1000 for Kinect millimeters).
/// Errors (each names the file): IoError for a missing or unreadable file;
/// ParseError for a file that is not an image, a depth image that is not
/// 16-bit single-channel (an 8-bit depth image has lost its range), images
/// of different sizes, and a depth image with no measurement at all.
/// Precondition (InvalidArgument): depth_scale finite and > 0.
RgbdFrame read_rgbd_frame(const std::string& color_path, const std::string& depth_path,
                          double depth_scale);

/// Options of rgbd_to_cloud.
struct RgbdCloudOptions {
  /// Depths (meters) outside [min_depth, max_depth] are skipped.
  /// Defaults 0.1 m and 8 m (a Kinect's useful range).
  double min_depth = 0.1;
  double max_depth = 8.0;
  /// Use every `stride`-th pixel along rows and columns (≥ 1). Default 1.
  std::uint32_t stride = 1;
  /// Pose of the camera's optical frame in the frame the points are
  /// written in (identity: the optical frame itself).
  SE3d T_target_camera;
};

/// The colored cloud of a frame: every pixel with depth z in range gives
/// p_camera = z·camera.unproject(u, v) (depth along the optical axis; any
/// focal-length sign, distortion inverted as PinholeCamera::unproject), then
/// T_target_camera·p_camera, colored by the color image at (u, v) (gray
/// images give R = G = B). Preconditions (InvalidArgument): camera passes
/// check(), frame's images have one size and it equals the camera's when the
/// camera states one, 8-bit color with 1 or 3 channels, options valid.
PointCloud rgbd_to_cloud(const RgbdFrame& frame, const PinholeCamera& camera,
                         const RgbdCloudOptions& options = {});

/// The 3D point at pixel (u, v) from depth, in the camera's optical frame,
/// or false when the pixel has no depth in [min_depth, max_depth]. The
/// depth is read at the nearest pixel of (u, v).
bool depth_point(const DepthImage& depth, const PinholeCamera& camera, double u, double v,
                 double min_depth, double max_depth, Eigen::Vector3d& p_camera);

}  // namespace rove
