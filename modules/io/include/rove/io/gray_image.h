#pragma once
/// \file
/// 8-bit gray images in PNG and PGM files, the pixel layer of occupancy-grid
/// maps (see grid_image.h for what the pixels mean).
///
/// Reading accepts: PNG of any bit depth and color type (16-bit samples
/// keep their high byte, palettes are expanded, color pixels become the
/// average of their R, G, B as ROS map_server does, alpha is ignored,
/// interlaced images are read); PGM binary (`P5`) and ASCII (`P2`) with any
/// maxval 1–65535 (16-bit P5 samples big-endian as Netpbm says), values
/// scaled to 0–255 as round(255·v / maxval), `#` comments in the header.
/// Bytes after a P5 image are ignored (Netpbm allows several images).
///
/// Bad input raises rove::ParseError naming the source and the byte offset
/// (truncated data, a sample above maxval, a bad header field) before any
/// allocation the data cannot back: the declared width × height is checked
/// against ImageLimits and against what the remaining bytes can hold (for
/// PNG, deflate's 1032:1 ratio bound).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rove {

/// A gray image, 8 bits per pixel, row 0 at the top, `width` pixels per row.
struct GrayImage {
  std::uint32_t width = 0;            ///< pixels per row
  std::uint32_t height = 0;           ///< rows
  std::vector<std::uint8_t> pixels;   ///< width·height values, row by row from the top

  /// Pixel at column u, row v (row 0 = top). No bounds check.
  std::uint8_t at(std::uint32_t u, std::uint32_t v) const noexcept {
    return pixels[static_cast<std::size_t>(v) * width + u];
  }
  friend bool operator==(const GrayImage&, const GrayImage&) = default;
};

/// Caps applied before allocating from a header's declared size.
struct ImageLimits {
  std::uint32_t max_side = 1u << 16;          ///< largest width or height, pixels
  std::uint64_t max_pixels = std::uint64_t{1} << 28;  ///< largest width·height (256 Mpx)
};

/// File format of a gray image.
enum class ImageFormat : std::uint8_t {
  Png,  ///< PNG, 8-bit gray
  Pgm,  ///< PGM binary (P5), maxval 255
};

/// The format named by a file's extension (`.png`, `.pgm`, case-insensitive).
/// Throws InvalidArgument for another extension.
ImageFormat image_format_from_path(std::string_view path);

/// Decodes a PNG held in memory; `source` names it in errors.
GrayImage decode_png(std::span<const std::uint8_t> data, std::string_view source,
                     const ImageLimits& limits = {});
/// Decodes a PGM (P5 or P2) held in memory; `source` names it in errors.
GrayImage decode_pgm(std::span<const std::uint8_t> data, std::string_view source,
                     const ImageLimits& limits = {});
/// Decodes PNG or PGM, told apart by their first bytes (`\x89PNG`, `P5`/`P2`).
GrayImage decode_gray_image(std::span<const std::uint8_t> data, std::string_view source,
                            const ImageLimits& limits = {});
/// Reads a PNG or PGM file (format from its first bytes). Throws IoError if
/// it cannot be read, ParseError if it is malformed.
GrayImage read_gray_image(const std::string& path, const ImageLimits& limits = {});

/// An RGB color of a PNG palette.
struct PaletteColor {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const PaletteColor&, const PaletteColor&) = default;
};

/// How encode_png writes an image.
struct PngEncoding {
  /// Empty: the pixels are gray values. Otherwise (1 to 256 colors) the
  /// pixels are indices into this palette (an 8-bit palette PNG).
  std::vector<PaletteColor> palette;
  /// false: libpng's default filters and compression (smallest files).
  /// true: no row filters and run-length deflate at level 1, several times
  /// faster on pictures that are mostly one flat color, for larger files.
  bool fast = false;
};

/// Encodes as an 8-bit gray (or palette) PNG, no ancillary chunks.
/// Preconditions (InvalidArgument): width, height > 0, pixels.size() ==
/// width·height, at most 256 palette colors and every pixel a valid index
/// into a non-empty palette.
std::vector<std::uint8_t> encode_png(const GrayImage& image, const PngEncoding& encoding = {});
/// Encodes as PGM `P5`, maxval 255, header `P5\n<w> <h>\n255\n`. Same
/// preconditions as encode_png.
std::vector<std::uint8_t> encode_pgm(const GrayImage& image);
/// Writes `image` to `path` in `format`, atomically (rove/core/files.h: a
/// temporary sibling renamed over `path` when complete). Throws IoError if it
/// cannot be written.
void write_gray_image(const std::string& path, const GrayImage& image, ImageFormat format);
/// Writes `image` as a PNG encoded with `encoding`, atomically. Throws IoError.
void write_png(const std::string& path, const GrayImage& image, const PngEncoding& encoding);

}  // namespace rove
