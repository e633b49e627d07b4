#pragma once
/// \file
/// DepthImage: a range or depth image stored as 16-bit integers or floats,
/// with the scale that turns stored values into meters.

#include <cstddef>
#include <cstdint>
#include <variant>
#include <vector>

#include "rove/serialization/archive.h"

namespace rove {

/// A depth (or range) image, row-major: value (u, v) at index v·width + u.
/// A stored value d means d / scale meters; 0 means "no measurement".
/// Typical scales: 1000 (millimeters, Kinect/RealSense, MRPT's rangeUnits
/// 0.001), 5000 (TUM RGB-D PNGs), 1 (float images in meters). MRPT's
/// `rangeUnits` is 1 / scale. A plain value; thread-compatible.
struct DepthImage {
  /// Columns, pixels.
  std::uint32_t width = 0;
  /// Rows, pixels.
  std::uint32_t height = 0;
  /// Stored units per meter: meters = value / scale. Must be > 0.
  double scale = 1000.0;
  /// The values: 16-bit unsigned or 32-bit float, width·height of them.
  std::variant<std::vector<std::uint16_t>, std::vector<float>> values =
      std::vector<std::uint16_t>{};

  /// A zero-filled 16-bit image.
  static DepthImage zeros_u16(std::uint32_t width, std::uint32_t height, double scale);
  /// A zero-filled float image.
  static DepthImage zeros_f32(std::uint32_t width, std::uint32_t height, double scale);

  /// Number of values the shape requires.
  std::size_t pixel_count() const noexcept {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  /// Throws InvalidArgument unless the value count equals width·height and
  /// scale is finite and > 0.
  void check() const;
  /// The value at (u, v) in meters (value / scale); NaN for a non-finite
  /// float value. Precondition (InvalidArgument): u < width, v < height,
  /// check() passes.
  double meters(std::uint32_t u, std::uint32_t v) const;
  /// Sets pixel (u, v) from meters: rounded to the nearest stored unit for
  /// 16-bit images (throws InvalidArgument if out of [0, 65535] units),
  /// stored as float otherwise.
  void set_meters(std::uint32_t u, std::uint32_t v, double meters);

  /// Exact equality of every field.
  friend bool operator==(const DepthImage&, const DepthImage&) = default;
};

/// Writes a DepthImage (versioned record).
void save(OutArchive& ar, const DepthImage& d);
/// Reads a DepthImage written by save; sizes that do not match the shape
/// are a ParseError.
void load(InArchive& ar, DepthImage& d);

}  // namespace rove
