#include "rove/slam/map_export.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"
#include "rove/io/gray_image.h"

namespace rove {

void render_points_png(const std::string& path, const PointCloud& cloud,
                       const std::vector<Pose2>& robot_path, const PointsImageOptions& options) {
  ROVE_CHECK_GT(options.resolution, 0.0);
  ROVE_CHECK_GE(options.margin, 0.0);
  ROVE_CHECK_GE(options.max_side, 16);
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  const auto extend = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  };
  for (const auto& p : cloud.points()) extend(p.x(), p.y());
  for (const auto& p : robot_path) extend(p.x(), p.y());
  if (!(x0 <= x1)) x0 = y0 = x1 = y1 = 0.0;
  x0 -= options.margin;
  y0 -= options.margin;
  x1 += options.margin;
  y1 += options.margin;
  double res = options.resolution;
  const double side = std::max(x1 - x0, y1 - y0);
  if (side / res > options.max_side) res = side / options.max_side;
  const int w = std::max(1, static_cast<int>(std::ceil((x1 - x0) / res)));
  const int h = std::max(1, static_cast<int>(std::ceil((y1 - y0) / res)));
  // A palette image, one byte per pixel: a third of the bytes of RGB for
  // deflate and its checksums to go through (on the demo the RGB picture's
  // encoding was 14 % of the whole `rove icp-slam` run).
  enum : std::uint8_t { kBackground, kPoint, kPath, kStart, kEnd };
  PngEncoding encoding;
  encoding.palette = {{255, 255, 255}, {40, 40, 40}, {220, 30, 30}, {0, 170, 0}, {0, 0, 220}};
  encoding.fast = true;  // libpng's filter search was half of a `rove icp-slam` demo run
  GrayImage image;
  image.width = static_cast<std::uint32_t>(w);
  image.height = static_cast<std::uint32_t>(h);
  image.pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kBackground);
  std::vector<std::uint8_t>& px = image.pixels;
  const auto put = [&](double x, double y, std::uint8_t colour, int radius) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    const int cx = static_cast<int>((x - x0) / res);
    const int cy = h - 1 - static_cast<int>((y - y0) / res);
    for (int dy = -radius; dy <= radius; ++dy) {
      for (int dx = -radius; dx <= radius; ++dx) {
        const int u = cx + dx, v = cy + dy;
        if (u < 0 || v < 0 || u >= w || v >= h) continue;
        px[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)] =
            colour;
      }
    }
  };
  for (const auto& p : cloud.points()) put(p.x(), p.y(), kPoint, 0);
  for (std::size_t i = 1; i < robot_path.size(); ++i) {
    const Pose2& a = robot_path[i - 1];
    const Pose2& b = robot_path[i];
    const int n = std::max(1, static_cast<int>(std::ceil(a.distance_to(b) / (0.5 * res))));
    for (int k = 0; k <= n; ++k) {
      const double s = static_cast<double>(k) / n;
      put(a.x() + s * (b.x() - a.x()), a.y() + s * (b.y() - a.y()), kPath, 0);
    }
  }
  if (!robot_path.empty()) {
    put(robot_path.front().x(), robot_path.front().y(), kStart, 3);
    put(robot_path.back().x(), robot_path.back().y(), kEnd, 3);
  }
  write_png(path, image, encoding);
}

}  // namespace rove
