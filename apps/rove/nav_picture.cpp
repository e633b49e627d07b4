#include "nav_picture.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rove/io/gray_image.h"

namespace rove::cli {

namespace {

const std::vector<PaletteColor> kNavPalette = {
    {255, 255, 255},  // free
    {0, 0, 0},        // obstacle
    {235, 215, 215},  // nearer than the radius
    {30, 90, 230},    // planned path
    {230, 120, 0},    // driven path
    {0, 170, 0},      // start
    {210, 0, 0},      // goal
    {120, 0, 160},    // robot
    {0, 190, 190},    // scan points
    {250, 200, 0},    // local plan
    {255, 0, 255},    // collision
    {160, 160, 160},  // separator
};

int window_side(double extent, double res, double pixels_per_cell) {
  return std::max(1, static_cast<int>(std::ceil(extent / res * pixels_per_cell)));
}

}  // namespace

NavPicture::NavPicture(const NavigationGrid& grid, double radius, int max_side)
    : NavPicture(grid, radius, grid.x_min(), grid.y_min(), grid.x_max(), grid.y_max(), max_side) {}

NavPicture::NavPicture(const NavigationGrid& grid, double radius, double x0, double y0, double x1,
                       double y1, int max_side, double pixels_per_cell)
    : x0_(x0), y0_(y0), canvas_(1, 1) {
  const double res = grid.resolution();
  int w = window_side(x1 - x0, res, pixels_per_cell), h = window_side(y1 - y0, res, pixels_per_cell);
  const double shrink = std::min(1.0, static_cast<double>(max_side) / std::max(w, h));
  w = std::max(1, static_cast<int>(w * shrink));
  h = std::max(1, static_cast<int>(h * shrink));
  scale_ = pixels_per_cell * shrink / res;
  canvas_ = Canvas(w, h, kNavFree);
  const auto r = static_cast<float>(radius);
  for (int j = 0; j < h; ++j) {
    const double y = y0_ + (h - 1 - j + 0.5) / scale_;
    const int cy = grid.cell_y(y);
    for (int i = 0; i < w; ++i) {
      const int cx = grid.cell_x(x0_ + (i + 0.5) / scale_);
      if (grid.occupied(cx, cy)) {
        canvas_.set(i, j, kNavObstacle);
      } else if (grid.clearance(cx, cy) <= r) {
        canvas_.set(i, j, kNavInflated);
      }
    }
  }
}

int NavPicture::px(double x) const { return static_cast<int>(std::floor((x - x0_) * scale_)); }
int NavPicture::py(double y) const {
  return canvas_.height() - 1 - static_cast<int>(std::floor((y - y0_) * scale_));
}

void NavPicture::polyline(const std::vector<Eigen::Vector2d>& points, std::uint8_t color, int width) {
  const int lo = -(width - 1) / 2, hi = width / 2;
  for (std::size_t i = 1; i < points.size(); ++i) {
    for (int dy = lo; dy <= hi; ++dy) {
      for (int dx = lo; dx <= hi; ++dx) {
        canvas_.line(px(points[i - 1].x()) + dx, py(points[i - 1].y()) + dy, px(points[i].x()) + dx,
                     py(points[i].y()) + dy, color);
      }
    }
  }
  if (points.size() == 1) canvas_.set(px(points[0].x()), py(points[0].y()), color);
}

void NavPicture::dot(const Eigen::Vector2d& p, int r, std::uint8_t color) {
  canvas_.dot(px(p.x()), py(p.y()), r, color);
}

void NavPicture::robot(const Eigen::Vector2d& p, double heading, double radius, std::uint8_t color) {
  const int steps = 48;
  for (int k = 0; k < steps; ++k) {
    const double a0 = 2 * std::numbers::pi * k / steps, a1 = 2 * std::numbers::pi * (k + 1) / steps;
    canvas_.line(px(p.x() + radius * std::cos(a0)), py(p.y() + radius * std::sin(a0)),
                 px(p.x() + radius * std::cos(a1)), py(p.y() + radius * std::sin(a1)), color);
  }
  canvas_.line(px(p.x()), py(p.y()), px(p.x() + radius * std::cos(heading)),
               py(p.y() + radius * std::sin(heading)), color);
}

void NavPicture::write(const std::string& path) const {
  PngEncoding encoding;
  encoding.palette = kNavPalette;
  write_png(path, canvas_.image(), encoding);
}

void NavPicture::write_strip(const std::vector<NavPicture>& frames, const std::string& path) {
  constexpr int kGap = 4;
  int w = 0, h = 1;
  for (const auto& f : frames) {
    w += f.canvas_.width() + (w > 0 ? kGap : 0);
    h = std::max(h, f.canvas_.height());
  }
  Canvas strip(std::max(w, 1), h, kNavSeparator);
  int at = 0;
  for (const auto& f : frames) {
    for (int j = 0; j < f.canvas_.height(); ++j) {
      for (int i = 0; i < f.canvas_.width(); ++i) {
        strip.set(at + i, j, f.canvas_.image().pixels[static_cast<std::size_t>(j) * f.canvas_.image().width + i]);
      }
    }
    at += f.canvas_.width() + kGap;
  }
  PngEncoding encoding;
  encoding.palette = kNavPalette;
  write_png(path, strip.image(), encoding);
}

}  // namespace rove::cli
