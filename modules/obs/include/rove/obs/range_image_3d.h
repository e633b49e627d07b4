#pragma once
/// \file
/// RangeImage3D: a depth (or range) image from a 3D camera, optionally with
/// an intensity/color image from a second camera: RGB-D and time-of-flight
/// sensors (MRPT's CObservation3DRangeScan, image part).
///
/// Three frames are involved:
///  - the depth camera's optical frame: z forward, x right, y down (pinhole
///    convention, PinholeCamera);
///  - the sensor frame, MRPT's convention for 3D range observations:
///    x forward, y left, z up. A point maps as
///    (x, y, z)_sensor = (z, −x, −y)_optical, i.e. T_sensor_optical =
///    Pose3(0, 0, 0, −90°, 0, −90°) (sensor_from_optical());
///  - the robot frame, through T_robot_sensor (MRPT's `sensorPose`, which
///    refers to the x-forward sensor frame).

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/depth_image.h"
#include "rove/obs/image.h"
#include "rove/obs/observation.h"
#include "rove/obs/pinhole_camera.h"

namespace rove {

/// T_sensor_optical: the optical frame (z forward, x right, y down) seen from
/// the sensor frame (x forward, y left, z up): yaw −90°, roll −90°.
Pose3 sensor_from_optical();

/// The frame RangeImage3D::project writes points in.
enum class RangeImageFrame : std::uint8_t {
  Optical = 0,  ///< depth camera optical frame (z forward, x right, y down)
  Sensor = 1,   ///< sensor frame (x forward, y left, z up), MRPT's local points
  Robot = 2,    ///< robot frame: T_robot_sensor ⊕ p_sensor
};

/// Options of RangeImage3D::project.
struct RangeImageProjectionOptions {
  /// Frame of the output points (default: the robot frame).
  RangeImageFrame frame = RangeImageFrame::Robot;
  /// If set (and frame is kRobot), the points are further mapped by this
  /// pose: T_target_robot ⊕ p_robot, e.g. the robot's pose in the world.
  std::optional<Pose3> T_target_robot;
};

/// The points projected from a range image.
struct RangeImageProjection {
  /// The points, meters, in the requested frame, in row-major pixel order.
  std::vector<Eigen::Vector3d> points;
  /// Column (u) of the pixel each point came from.
  std::vector<std::uint32_t> pixel_u;
  /// Row (v) of the pixel each point came from.
  std::vector<std::uint32_t> pixel_v;
};

/// Which light the intensity image records (MRPT's intensityImageChannel).
enum class IntensityChannel : std::uint8_t {
  Visible = 0,   ///< a color or gray camera
  Infrared = 1,  ///< the depth sensor's infrared camera
};

/// 3D points a sensor (or its driver) computed and stored with the image,
/// in the sensor frame (x forward, y left, z up), meters, float as stored.
struct RangeImagePoints {
  /// The points.
  std::vector<Eigen::Vector3f> p_sensor;
  /// Column and row of the pixel each point came from; both empty when the
  /// source did not store them (MRPT files before version 8).
  std::vector<std::uint16_t> pixel_u, pixel_v;
  /// Exact equality.
  friend bool operator==(const RangeImagePoints&, const RangeImagePoints&) = default;
};

/// Writes RangeImagePoints (versioned record).
void save(OutArchive& ar, const RangeImagePoints& p);
/// Reads RangeImagePoints written by save; pixel vectors whose size is
/// neither 0 nor the point count are a ParseError.
void load(InArchive& ar, RangeImagePoints& p);

/// A depth/range image with its camera model and an optional intensity image.
class RangeImage3D final : public ObservationOf<RangeImage3D> {
 public:
  /// Stored class name: "RangeImage3D".
  static constexpr std::string_view kClassName = "RangeImage3D";

  /// The depth (range_is_depth) or range image; its size must match
  /// depth_camera's width and height.
  DepthImage depth;
  /// true: a value is the depth z along the optical axis; false: the
  /// Euclidean distance from the optical center along the pixel's ray
  /// (MRPT's `range_is_depth`).
  bool range_is_depth = true;
  /// Measurements beyond this distance (meters; depth or range, as stored)
  /// are invalid (MRPT's `maxRange`, default 5 m).
  double max_range = 5.0;
  /// Intrinsics of the depth camera.
  PinholeCamera depth_camera;
  /// The intensity or color image, if any.
  std::optional<Image> intensity;
  /// Intrinsics of the intensity camera.
  PinholeCamera intensity_camera;
  /// T_sensor_intensity: pose of the intensity camera's optical frame in the
  /// depth sensor frame (x forward), MRPT's `relativePoseIntensityWRTDepth`.
  /// Default: both cameras coincide, sensor_from_optical().
  Pose3 T_sensor_intensity = sensor_from_optical();
  /// Which light the intensity image records (version 2).
  IntensityChannel intensity_channel = IntensityChannel::Visible;
  /// A per-pixel confidence image from the sensor, if any (version 2).
  std::optional<Image> confidence;
  /// Points stored with the image, if any (version 2).
  std::optional<RangeImagePoints> points;
  /// Standard deviation of a depth measurement, meters (MRPT's stdError;
  /// version 2).
  double std_error_m = 0.01;
  /// Further depth layers by name (e.g. a second return), each the size of
  /// depth (version 2).
  std::map<std::string, DepthImage> other_depth_layers;

  /// An empty observation.
  RangeImage3D() = default;

  /// Throws InvalidArgument unless depth passes its check, its size equals
  /// depth_camera's (width, height) (unless depth is empty: an observation
  /// may carry only points), depth_camera passes its check, every other
  /// depth layer passes its check and has depth's size, the points' pixel
  /// vectors are empty or one per point,
  /// max_range is > 0 (may be +inf), and the intensity image (if any) passes
  /// its check.
  void check() const;

  /// Projects every valid pixel to a 3D point (pinhole model: Hartley &
  /// Zisserman eq. 6.4 inverted). For pixel (u, v) with stored value d:
  /// s = d / depth.scale meters; valid iff s is finite, s > 0 and
  /// s <= max_range. With (a, b, 1) = depth_camera.unproject(u, v) (without
  /// distortion a = (u − cx)/fx, b = (v − cy)/fy):
  ///   depth:  z = s, x = a·z, y = b·z  (optical frame);
  ///   range:  (x, y, z) = s · (a, b, 1) / |(a, b, 1)|.
  /// The result is then expressed in options.frame. Precondition
  /// (InvalidArgument): check() passes.
  RangeImageProjection project(const RangeImageProjectionOptions& options = {}) const;

  /// Exact equality of every field.
  friend bool operator==(const RangeImage3D& a, const RangeImage3D& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 2; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data,
  /// including a depth image that fails check() (sizes that disagree with
  /// the camera, max_range <= 0).
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
