#pragma once
/// \file
/// Image: an uncompressed image buffer (width, height, channels, sample
/// type, row-major bytes). Decoding PNG/JPEG is not this type's job.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "rove/serialization/archive.h"

namespace rove {

/// Type of one channel sample.
enum class PixelType : std::uint8_t {
  U8 = 0,   ///< unsigned 8-bit
  U16 = 1,  ///< unsigned 16-bit, little-endian in `data`
  F32 = 2,  ///< IEEE float, little-endian in `data`
};

/// Bytes per sample of a PixelType (1, 2 or 4).
std::size_t bytes_per_sample(PixelType t) noexcept;

/// An image: `height` rows of `width` pixels of `channels` samples, tightly
/// packed row-major (pixel (u, v) channel c at sample index
/// (v·width + u)·channels + c). Color order for 3 channels is R, G, B (MRPT
/// stores B, G, R: convert on import). A plain value; thread-compatible.
struct Image {
  /// Columns, pixels.
  std::uint32_t width = 0;
  /// Rows, pixels.
  std::uint32_t height = 0;
  /// Samples per pixel (1 gray, 3 RGB, 4 RGBA); >= 1 for a non-empty image.
  std::uint32_t channels = 1;
  /// Sample type.
  PixelType pixel_type = PixelType::U8;
  /// The samples, width·height·channels·bytes_per_sample bytes.
  std::vector<std::uint8_t> data;

  /// An image of the given shape with all bytes zero. Throws
  /// InvalidArgument if channels is 0 or the size overflows.
  static Image zeros(std::uint32_t width, std::uint32_t height, std::uint32_t channels,
                     PixelType type);

  /// True if width or height is 0.
  bool empty() const noexcept { return width == 0 || height == 0; }
  /// The byte count the shape requires.
  std::size_t expected_bytes() const;
  /// Throws InvalidArgument unless data.size() == expected_bytes() and
  /// channels >= 1.
  void check() const;

  /// Exact equality of every field.
  friend bool operator==(const Image&, const Image&) = default;
};

/// Writes an Image (versioned record).
void save(OutArchive& ar, const Image& image);
/// Reads an Image written by save; a data size that does not match the
/// shape is a ParseError.
void load(InArchive& ar, Image& image);

}  // namespace rove
