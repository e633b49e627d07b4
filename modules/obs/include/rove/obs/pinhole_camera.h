#pragma once
/// \file
/// PinholeCamera: intrinsic parameters of a pinhole camera with OpenCV's
/// "plumb bob" (Brown–Conrady) distortion, as MRPT's TCamera.
///
/// Camera (optical) frame: z forward along the optical axis, x right, y down.
/// Pixel (u, v): u along image columns (right), v along rows (down), the
/// center of the top-left pixel at (0, 0).
///
/// Projection of p = (x, y, z), z > 0 (Hartley & Zisserman, "Multiple View
/// Geometry", 2nd ed., eq. 6.4; distortion as OpenCV's calib3d docs):
///   a = x/z, b = y/z, r² = a² + b²,
///   a' = a(1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 a b + p2 (r² + 2a²),
///   b' = b(1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2b²) + 2 p2 a b,
///   u = fx a' + cx, v = fy b' + cy.

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "rove/serialization/archive.h"

namespace rove {

/// Intrinsics of a pinhole camera. A plain value; thread-compatible.
struct PinholeCamera {
  /// Image width in pixels.
  std::uint32_t width = 0;
  /// Image height in pixels.
  std::uint32_t height = 0;
  /// Focal length along u, pixels. Nonzero; negative for an image whose
  /// columns are mirrored (u grows to the left of the optical frame's x).
  double fx = 0.0;
  /// Focal length along v, pixels. Nonzero; negative for an image whose rows
  /// are mirrored (ICL-NUIM's renderer: fy = −480).
  double fy = 0.0;
  /// Principal point u, pixels.
  double cx = 0.0;
  /// Principal point v, pixels.
  double cy = 0.0;
  /// Distortion (k1, k2, p1, p2, k3), OpenCV's order; all zero: none.
  std::array<double, 5> distortion{};

  /// True if every distortion coefficient is zero.
  bool has_distortion() const noexcept;

  /// Throws InvalidArgument unless fx, fy are finite and nonzero, cx, cy and
  /// the distortion coefficients are finite.
  void check() const;

  /// Pixel of a point in the camera frame (meters), with distortion.
  /// Preconditions (InvalidArgument): check() passes, p.z() > 0.
  Eigen::Vector2d project(const Eigen::Vector3d& p_camera) const;

  /// The normalized ray (a, b, 1) whose projection is pixel (u, v): the
  /// point at depth z is z·(a, b, 1). Without distortion exactly
  /// ((u − cx)/fx, (v − cy)/fy, 1); with distortion the model is inverted
  /// by fixed-point iteration (as OpenCV's undistortPoints) until the
  /// re-projection moves by less than 1e-12 (normalized units) or 100
  /// iterations. Precondition (InvalidArgument): check() passes, u, v finite.
  Eigen::Vector3d unproject(double u, double v) const;

  /// Exact equality of every field.
  friend bool operator==(const PinholeCamera&, const PinholeCamera&) = default;
};

/// Writes a PinholeCamera (versioned record).
void save(OutArchive& ar, const PinholeCamera& c);
/// Reads a PinholeCamera written by save.
void load(InArchive& ar, PinholeCamera& c);

}  // namespace rove
