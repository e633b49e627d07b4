#pragma once
/// \file
/// A palette-indexed raster for the command line's plots (graph-slam --plot,
/// eval --plot), written as a palette PNG by io's image writer.

#include <cstdint>
#include <cstdlib>

#include "rove/io/gray_image.h"

namespace rove::cli {

/// Pixels as palette indices; drawing outside the image is clipped.
class Canvas {
 public:
  /// A w×h image filled with palette index `background`.
  Canvas(int w, int h, std::uint8_t background = 0) {
    image_.width = static_cast<std::uint32_t>(w);
    image_.height = static_cast<std::uint32_t>(h);
    image_.pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), background);
  }
  /// Sets one pixel (ignored outside the image).
  void set(int x, int y, std::uint8_t c) {
    if (x < 0 || y < 0 || x >= width() || y >= height()) return;
    image_.pixels[static_cast<std::size_t>(y) * image_.width + static_cast<std::size_t>(x)] = c;
  }
  /// A Bresenham line from (x0, y0) to (x1, y1).
  void line(int x0, int y0, int x1, int y1, std::uint8_t c) {
    const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
    const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (int guard = 0; guard < 4 * (width() + height()); ++guard) {
      set(x0, y0, c);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) err += dy, x0 += sx;
      if (e2 <= dx) err += dx, y0 += sy;
    }
  }
  /// A filled disc of radius r.
  void dot(int x, int y, int r, std::uint8_t c) {
    for (int j = -r; j <= r; ++j)
      for (int i = -r; i <= r; ++i)
        if (i * i + j * j <= r * r) set(x + i, y + j, c);
  }
  /// Fills the rectangle [x0, x1) × [y0, y1).
  void fill(int x0, int y0, int x1, int y1, std::uint8_t c) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) set(x, y, c);
  }
  int width() const { return static_cast<int>(image_.width); }    ///< pixels
  int height() const { return static_cast<int>(image_.height); }  ///< pixels
  const GrayImage& image() const { return image_; }                ///< the indices

 private:
  GrayImage image_;
};

}  // namespace rove::cli
