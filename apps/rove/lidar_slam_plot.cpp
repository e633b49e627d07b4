// The lidar-slam picture, rasterized as palette indices (canvas.h) and
// written by io's PNG writer.
#include "lidar_slam_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "canvas.h"
#include "rove/core/check.h"
#include "rove/io/gray_image.h"

namespace rove::cli {
namespace {

constexpr std::uint8_t kUnknown = 0, kFree = 1, kOccupied = 2, kPath = 3, kLoop = 4, kSubmap = 5;
const std::vector<PaletteColor> kPalette = {
    {205, 205, 205},  // unknown
    {255, 255, 255},  // free
    {0, 0, 0},        // occupied
    {30, 70, 230},    // path
    {230, 40, 40},    // loop closures
    {0, 160, 0},      // submap origins
};

}  // namespace

void write_slam_plot(const OccupancyGrid& grid, const SlamPlotContent& content,
                     const std::string& path, int max_side) {
  ROVE_CHECK_MSG(grid.size_x() > 0 && grid.size_y() > 0, "the grid has no cells");
  ROVE_CHECK_MSG(max_side >= 64, "max_side {} must be >= 64", max_side);
  const int sx = static_cast<int>(grid.size_x()), sy = static_cast<int>(grid.size_y());
  const int step = std::max(1, (std::max(sx, sy) + max_side - 1) / max_side);
  const int w = (sx + step - 1) / step, h = (sy + step - 1) / step;
  Canvas canvas(w, h, kUnknown);
  // A pixel shows its most occupied cell, so thin walls survive scaling.
  for (int py = 0; py < h; ++py) {
    for (int px = 0; px < w; ++px) {
      float occ = -1.0f;
      for (int j = py * step; j < std::min(sy, (py + 1) * step); ++j)
        for (int i = px * step; i < std::min(sx, (px + 1) * step); ++i)
          occ = std::max(occ, grid.occupancy(i, j));
      const std::uint8_t c = occ > 0.65f ? kOccupied : occ < 0.35f ? kFree : kUnknown;
      canvas.set(px, h - 1 - py, c);
    }
  }
  const double scale = 1.0 / (grid.resolution() * step);
  const auto to_px = [&](const Eigen::Vector2d& p, int& x, int& y) {
    x = static_cast<int>(std::floor((p.x() - grid.x_min()) * scale));
    y = h - 1 - static_cast<int>(std::floor((p.y() - grid.y_min()) * scale));
  };
  for (const auto& [a, b] : content.loop_edges) {
    int x0, y0, x1, y1;
    to_px(a, x0, y0);
    to_px(b, x1, y1);
    canvas.line(x0, y0, x1, y1, kLoop);
  }
  for (std::size_t i = 1; i < content.path.size(); ++i) {
    int x0, y0, x1, y1;
    to_px(content.path[i - 1], x0, y0);
    to_px(content.path[i], x1, y1);
    canvas.line(x0, y0, x1, y1, kPath);
  }
  for (const auto& o : content.submap_origins) {
    int x, y;
    to_px(o, x, y);
    canvas.dot(x, y, 2, kSubmap);
  }
  PngEncoding encoding;
  encoding.palette = kPalette;
  write_png(path, canvas.image(), encoding);
}

}  // namespace rove::cli
