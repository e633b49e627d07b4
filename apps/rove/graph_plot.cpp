// A small RGB PNG rasterizer for pose-graph plots (zlib for the image data,
// the PNG chunk layout of the PNG specification, ISO/IEC 15948).
#include "graph_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

#include <zlib.h>

#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove::cli {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

class Canvas {
 public:
  Canvas(int w, int h) : w_(w), h_(h), px_(static_cast<std::size_t>(w) * h * 3, 255) {}
  void set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    auto* p = &px_[(static_cast<std::size_t>(y) * w_ + x) * 3];
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
  }
  // Bresenham line.
  void line(int x0, int y0, int x1, int y1, Rgb c) {
    const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
    const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (int guard = 0; guard < 4 * (w_ + h_); ++guard) {
      set(x0, y0, c);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) err += dy, x0 += sx;
      if (e2 <= dx) err += dx, y0 += sy;
    }
  }
  void dot(int x, int y, int r, Rgb c) {
    for (int j = -r; j <= r; ++j)
      for (int i = -r; i <= r; ++i)
        if (i * i + j * j <= r * r) set(x + i, y + j, c);
  }
  int width() const { return w_; }
  int height() const { return h_; }
  const std::vector<std::uint8_t>& pixels() const { return px_; }

 private:
  int w_, h_;
  std::vector<std::uint8_t> px_;
};

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}

void put_chunk(std::vector<std::uint8_t>& out, const char* type,
               const std::vector<std::uint8_t>& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const uLong crc = crc32(0L, out.data() + start, static_cast<uInt>(out.size() - start));
  put_u32(out, static_cast<std::uint32_t>(crc));
}

void write_png(const Canvas& c, const std::string& path) {
  // Scanlines, each prefixed with filter type 0.
  std::vector<std::uint8_t> raw;
  raw.reserve(static_cast<std::size_t>(c.height()) * (1 + 3 * c.width()));
  for (int y = 0; y < c.height(); ++y) {
    raw.push_back(0);
    const auto* row = &c.pixels()[static_cast<std::size_t>(y) * c.width() * 3];
    raw.insert(raw.end(), row, row + 3 * c.width());
  }
  uLongf zlen = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> z(zlen);
  if (compress2(z.data(), &zlen, raw.data(), static_cast<uLong>(raw.size()), 6) != Z_OK) {
    throw IoError(path, "zlib could not compress the image");
  }
  z.resize(zlen);
  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  std::vector<std::uint8_t> ihdr;
  put_u32(ihdr, static_cast<std::uint32_t>(c.width()));
  put_u32(ihdr, static_cast<std::uint32_t>(c.height()));
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // 8 bits, RGB, deflate, no filter, no interlace
  put_chunk(png, "IHDR", ihdr);
  put_chunk(png, "IDAT", z);
  put_chunk(png, "IEND", {});
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw IoError(path, "cannot create the file");
  const bool ok = std::fwrite(png.data(), 1, png.size(), f) == png.size();
  if (std::fclose(f) != 0 || !ok) throw IoError(path, "cannot write the file");
}

}  // namespace

void write_graph_plot(const PoseGraph2D& before, const PoseGraph2D& after,
                      const std::string& path, int panel_px) {
  ROVE_CHECK_MSG(panel_px >= 64 && panel_px <= 8192, "panel size {} outside [64, 8192]",
                 panel_px);
  // One scale for both panels: the bounding box of all vertices.
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x;
  double hi_x = -lo_x, hi_y = -lo_x;
  for (const auto* g : {&before, &after}) {
    for (const auto& [id, v] : g->vertices()) {
      const auto& t = v.pose.translation();
      lo_x = std::min(lo_x, t.x()), hi_x = std::max(hi_x, t.x());
      lo_y = std::min(lo_y, t.y()), hi_y = std::max(hi_y, t.y());
    }
  }
  if (!(lo_x <= hi_x)) lo_x = lo_y = -1.0, hi_x = hi_y = 1.0;
  const double span = std::max({hi_x - lo_x, hi_y - lo_y, 1e-9});
  const int margin = 10, inner = panel_px - 2 * margin, gap = 10;
  Canvas canvas(2 * panel_px + gap, panel_px);
  for (int y = 0; y < panel_px; ++y)
    for (int x = panel_px; x < panel_px + gap; ++x) canvas.set(x, y, {200, 200, 200});
  const double scale = inner / span;
  const double cx = 0.5 * (lo_x + hi_x), cy = 0.5 * (lo_y + hi_y);
  int panel = 0;
  for (const auto* g : {&before, &after}) {
    const int ox = panel++ * (panel_px + gap);
    auto to_px = [&](const SE2d& p, int& x, int& y) {
      x = ox + panel_px / 2 + static_cast<int>(std::lround((p.translation().x() - cx) * scale));
      y = panel_px / 2 - static_cast<int>(std::lround((p.translation().y() - cy) * scale));
    };
    // Loop closures first, odometry on top of them.
    for (int pass = 0; pass < 2; ++pass) {
      for (const auto& e : g->edges()) {
        const bool odometry = e.to == e.from + 1 || e.from == e.to + 1;
        if (odometry != (pass == 1)) continue;
        int x0, y0, x1, y1;
        to_px(g->pose(e.from), x0, y0);
        to_px(g->pose(e.to), x1, y1);
        canvas.line(x0, y0, x1, y1, odometry ? Rgb{40, 80, 220} : Rgb{240, 150, 150});
      }
    }
    for (const auto& [id, v] : g->vertices()) {
      int x, y;
      to_px(v.pose, x, y);
      if (v.fixed) {
        canvas.dot(x, y, 4, {0, 160, 0});
      } else {
        canvas.set(x, y, {0, 0, 0});
      }
    }
  }
  write_png(canvas, path);
}

}  // namespace rove::cli
