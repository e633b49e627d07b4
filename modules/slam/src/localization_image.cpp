#include "rove/slam/localization_image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "rove/core/check.h"
#include "rove/io/gray_image.h"
#include "rove/io/grid_image.h"

namespace rove {
namespace {

// Palette: 128 grays, then the drawing colors.
constexpr std::uint8_t kGrays = 128;
constexpr std::uint8_t kParticle = kGrays;
constexpr std::uint8_t kPath = kGrays + 1;
constexpr std::uint8_t kStart = kGrays + 2;
constexpr std::uint8_t kEnd = kGrays + 3;
constexpr std::uint8_t kTruth = kGrays + 4;

std::vector<PaletteColor> palette() {
  std::vector<PaletteColor> p;
  for (int k = 0; k < kGrays; ++k) {
    const auto g = static_cast<std::uint8_t>((k * 255 + (kGrays - 1) / 2) / (kGrays - 1));
    p.push_back({g, g, g});
  }
  p.push_back({255, 140, 0});   // particles
  p.push_back({220, 30, 30});   // path
  p.push_back({0, 170, 0});     // start
  p.push_back({0, 0, 220});     // end
  p.push_back({200, 0, 200});   // ground truth
  return p;
}

// Pixels of a grid drawn at one pixel per `k` × `k` cells.
class Canvas {
 public:
  Canvas(const OccupancyGrid& grid, int k) : grid_(grid), k_(k) {
    GridImageOptions scale;
    scale.mode = RosMapMode::Scale;  // 255·p(free)
    const GrayImage full = grid_to_image(grid, scale);
    img_.width = (full.width + static_cast<std::uint32_t>(k) - 1) / static_cast<std::uint32_t>(k);
    img_.height = (full.height + static_cast<std::uint32_t>(k) - 1) / static_cast<std::uint32_t>(k);
    img_.pixels.resize(static_cast<std::size_t>(img_.width) * img_.height);
    for (std::uint32_t r = 0; r < img_.height; ++r) {
      for (std::uint32_t c = 0; c < img_.width; ++c) {
        // The darkest cell of the block, so thin walls survive.
        std::uint8_t v = 255;
        for (std::uint32_t dr = 0; dr < static_cast<std::uint32_t>(k); ++dr) {
          for (std::uint32_t dc = 0; dc < static_cast<std::uint32_t>(k); ++dc) {
            const std::uint32_t fr = r * static_cast<std::uint32_t>(k) + dr;
            const std::uint32_t fc = c * static_cast<std::uint32_t>(k) + dc;
            if (fr < full.height && fc < full.width) {
              v = std::min(v, full.pixels[static_cast<std::size_t>(fr) * full.width + fc]);
            }
          }
        }
        img_.pixels[static_cast<std::size_t>(r) * img_.width + c] = static_cast<std::uint8_t>(v >> 1);
      }
    }
  }

  // Pixel column and row of a world point (may lie outside).
  void to_pixel(double x, double y, int& c, int& r) const {
    const double res = grid_.resolution() * k_;
    c = static_cast<int>(std::floor((x - grid_.x_min()) / res));
    r = static_cast<int>(img_.height) - 1 - static_cast<int>(std::floor((y - grid_.y_min()) / res));
  }

  void put(int c, int r, std::uint8_t color) {
    if (c < 0 || r < 0 || c >= static_cast<int>(img_.width) || r >= static_cast<int>(img_.height)) {
      return;
    }
    img_.pixels[static_cast<std::size_t>(r) * img_.width + static_cast<std::size_t>(c)] = color;
  }

  void point(double x, double y, std::uint8_t color) {
    int c = 0, r = 0;
    to_pixel(x, y, c, r);
    put(c, r, color);
  }

  void square(double x, double y, int side, std::uint8_t color) {
    int c = 0, r = 0;
    to_pixel(x, y, c, r);
    for (int dr = -side / 2; dr <= side / 2; ++dr) {
      for (int dc = -side / 2; dc <= side / 2; ++dc) put(c + dc, r + dr, color);
    }
  }

  // Bresenham's line between two world points.
  void line(double x0, double y0, double x1, double y1, std::uint8_t color) {
    int c0 = 0, r0 = 0, c1 = 0, r1 = 0;
    to_pixel(x0, y0, c0, r0);
    to_pixel(x1, y1, c1, r1);
    const int lim = 4 * static_cast<int>(std::max(img_.width, img_.height));
    if (std::abs(c0) > lim || std::abs(r0) > lim || std::abs(c1) > lim || std::abs(r1) > lim) return;
    const int dc = std::abs(c1 - c0), dr = -std::abs(r1 - r0);
    const int sc = c0 < c1 ? 1 : -1, sr = r0 < r1 ? 1 : -1;
    int err = dc + dr;
    for (;;) {
      put(c0, r0, color);
      if (c0 == c1 && r0 == r1) break;
      const int e2 = 2 * err;
      if (e2 >= dr) {
        err += dr;
        c0 += sc;
      }
      if (e2 <= dc) {
        err += dc;
        r0 += sr;
      }
    }
  }

  void polyline(const std::vector<Pose2>& poses, std::uint8_t color) {
    for (std::size_t i = 1; i < poses.size(); ++i) {
      line(poses[i - 1].x(), poses[i - 1].y(), poses[i].x(), poses[i].y(), color);
    }
  }

  const GrayImage& image() const noexcept { return img_; }

 private:
  const OccupancyGrid& grid_;
  int k_;
  GrayImage img_;
};

}  // namespace

void render_localization_png(const std::string& path, const OccupancyGrid& grid,
                             const std::vector<SE2d>& particles,
                             const std::vector<Pose2>& estimated_path,
                             const std::vector<Pose2>& ground_truth,
                             const LocalizationImageOptions& options) {
  ROVE_CHECK_GE(options.max_side, 16);
  ROVE_CHECK_MSG(options.marker >= 1 && options.marker % 2 == 1,
                 "marker must be an odd number of pixels, got {}", options.marker);
  ROVE_CHECK_MSG(grid.size_x() > 0 && grid.size_y() > 0, "the grid has no cells");
  const std::uint32_t side = std::max(grid.size_x(), grid.size_y());
  const int k = static_cast<int>((side + static_cast<std::uint32_t>(options.max_side) - 1) /
                                 static_cast<std::uint32_t>(options.max_side));
  Canvas canvas(grid, std::max(1, k));
  for (const SE2d& p : particles) canvas.point(p.translation().x(), p.translation().y(), kParticle);
  canvas.polyline(ground_truth, kTruth);
  canvas.polyline(estimated_path, kPath);
  if (!estimated_path.empty()) {
    canvas.square(estimated_path.front().x(), estimated_path.front().y(), options.marker, kStart);
    canvas.square(estimated_path.back().x(), estimated_path.back().y(), options.marker, kEnd);
  }
  PngEncoding encoding;
  encoding.palette = palette();
  encoding.fast = true;
  write_png(path, canvas.image(), encoding);
}

}  // namespace rove
