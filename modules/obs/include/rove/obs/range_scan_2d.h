#pragma once
/// \file
/// RangeScan2D: a planar range scan from a 2D laser scanner (MRPT's
/// CObservation2DRangeScan).
///
/// Sensor frame: x forward (the scan's center ray), y left, z up; rays lie
/// in the sensor's XY plane. Ray i points at angle ray_angle(i) from +x,
/// counter-clockwise positive, with MRPT's spacing (see ray_angle).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/observation.h"
#include "rove/poses/angle.h"

namespace rove {

/// The frame RangeScan2D projects its points into.
enum class ScanFrame : std::uint8_t {
  Sensor = 0,  ///< the scanner's own frame (x forward, y left, z up)
  Robot = 1,   ///< the robot frame: T_robot_sensor ⊕ p_sensor
};

/// A planar range scan. Fields are public; the functions that use them
/// check their consistency (check()) and throw InvalidArgument otherwise.
///
/// Which rays count: ray i yields a point iff valid[i] is true and
/// ranges[i] is finite and >= 0. A NaN, infinite or negative range is
/// therefore never projected even if flagged valid; set_ranges() clears the
/// flag of such rays when it builds the flags.
class RangeScan2D final : public ObservationOf<RangeScan2D> {
 public:
  /// Stored class name: "RangeScan2D".
  static constexpr std::string_view kClassName = "RangeScan2D";

  /// Measured range of each ray, meters.
  std::vector<float> ranges;
  /// Validity flag of each ray (same size as ranges).
  std::vector<bool> valid;
  /// Optional intensity (reflectivity) of each ray, sensor units; either
  /// empty or the same size as ranges.
  std::vector<std::int32_t> intensity;
  /// Angular field of view, radians, in (0, 2π] (MRPT's `aperture`).
  double aperture = kPi;
  /// true: rays sweep counter-clockwise (from −aperture/2 to +aperture/2,
  /// seen from above, z up); false: clockwise (MRPT's `rightToLeft`).
  bool right_to_left = true;
  /// Largest range the sensor reports, meters (MRPT default 80 m).
  float max_range = 80.0f;
  /// Standard deviation of a range measurement, meters (MRPT default 0.01).
  float std_error = 0.01f;
  /// Angular width of one beam, radians (MRPT default 0.25°).
  float beam_aperture = static_cast<float>(0.25 * kPi / 180.0);

  /// An empty scan with MRPT's default parameters.
  RangeScan2D() = default;

  /// Number of rays.
  std::size_t size() const noexcept { return ranges.size(); }

  /// Replaces the ranges and derives the flags: valid[i] = ranges[i] is
  /// finite and 0 < ranges[i] < max_range. Clears intensity.
  void set_ranges(std::vector<float> new_ranges);

  /// Throws InvalidArgument unless valid (and intensity, if not empty) has
  /// the size of ranges, aperture is finite and in (0, 2π], max_range and
  /// std_error are finite and >= 0.
  void check() const;

  /// Whether ray i yields a point (see the class comment). Precondition
  /// (InvalidArgument): i < size(), valid.size() == size().
  bool ray_yields_point(std::size_t i) const;

  /// Angle of ray i in the sensor frame, radians, as MRPT computes it
  /// (CObservation2DRangeScan::getScanAngle, CSinCosLookUpTableFor2DScans):
  /// with N = size() rays and Δ = aperture / (N − 1),
  ///   right_to_left: θ_i = −aperture/2 + i·Δ,
  ///   otherwise:     θ_i = +aperture/2 − i·Δ.
  /// Evaluated in double precision directly (MRPT's getScanAngle uses
  /// float). For aperture = 2π the first and last ray coincide, as in MRPT.
  /// Preconditions (InvalidArgument): N >= 2, i < N, aperture as in check().
  double ray_angle(std::size_t i) const;
  /// ray_angle(i) for every ray.
  std::vector<double> ray_angles() const;

  /// The points (x, y, z) of the rays that yield one, in ray order, in the
  /// sensor frame (z = 0) or the robot frame (T_robot_sensor ⊕ p), meters.
  /// An empty scan gives no points. Preconditions (InvalidArgument): check()
  /// passes and, if any ray yields a point, size() >= 2.
  std::vector<Eigen::Vector3d> points_3d(ScanFrame frame = ScanFrame::Robot) const;
  /// As points_3d, keeping (x, y) only: the planar scan as MRPT's 2D point
  /// maps load it (the sensor's height and tilt are applied, then z dropped).
  std::vector<Eigen::Vector2d> points_2d(ScanFrame frame = ScanFrame::Robot) const;
  /// Indices of the rays that yield points, in the order points_3d lists
  /// them.
  std::vector<std::size_t> point_ray_indices() const;

  /// Exact equality of every field.
  friend bool operator==(const RangeScan2D& a, const RangeScan2D& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields; throws InvalidArgument if check() fails.
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
