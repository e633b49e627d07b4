#pragma once
/// \file
/// The colour and depth images of RGB-D frames, read without OpenCV (libpng
/// and rove's own PGM parser), so that only the vision code needs OpenCV:
///
///  - colour: PNG of any bit depth and colour type, as 8-bit RGB (gray
///    replicated into the three channels, palettes expanded, 16-bit samples
///    keep their high byte, alpha dropped, interlaced images read);
///  - depth: 16-bit single-channel PNG (TUM, ICL-NUIM, the RGB-D tutorial)
///    or binary PGM (`P5`) with a maxval above 255 (16-bit big-endian
///    samples, as Kinect dumps write them), the raw sample values.
///
/// A depth image of 8 bits or with several channels is refused with what it
/// is (an 8-bit depth image has lost its range). Other formats (JPEG, ...)
/// are refused naming the file. Bad input raises rove::ParseError naming the
/// file and the byte offset, before any allocation the data cannot back
/// (as gray_image.h).

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/gray_image.h"

namespace rove {

/// An 8-bit RGB image, row 0 at the top.
struct ColorImage8 {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3·width·height bytes, R G B per pixel, row by row
};

/// A 16-bit single-channel image, row 0 at the top.
struct DepthImage16 {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint16_t> values;  ///< width·height samples, row by row
};

/// Decodes a PNG colour image held in memory; `source` names it in errors.
ColorImage8 decode_color_image(std::span<const std::uint8_t> data, std::string_view source,
                               const ImageLimits& limits = {});
/// Decodes a 16-bit PNG or PGM depth image held in memory (told apart by
/// their first bytes).
DepthImage16 decode_depth_image(std::span<const std::uint8_t> data, std::string_view source,
                                const ImageLimits& limits = {});
/// Reads a colour image file (see decode_color_image). Throws IoError if it
/// cannot be read, ParseError if it is malformed or not a PNG.
ColorImage8 read_color_image(const std::string& path, const ImageLimits& limits = {});
/// Reads a depth image file (see decode_depth_image).
DepthImage16 read_depth_image(const std::string& path, const ImageLimits& limits = {});

}  // namespace rove
