// ATE plots rasterized as palette indices.
#include "eval_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "canvas.h"
#include "rove/core/check.h"

namespace rove::cli {

namespace {

constexpr std::uint8_t kBackground = 0, kSeparator = 1, kError = 2, kReference = 3, kEstimate = 4,
                       kAxis = 5;
const std::vector<PaletteColor> kPalette = {
    {255, 255, 255},  // background
    {200, 200, 200},  // separator between the panels
    {245, 170, 170},  // error of each pair
    {90, 90, 90},     // reference
    {40, 80, 220},    // estimate
    {0, 0, 0},        // axes
};

}  // namespace

void write_ate_plot(const std::vector<Eigen::Vector3d>& reference,
                    const std::vector<Eigen::Vector3d>& estimate, const std::vector<double>& times,
                    const std::vector<double>& errors, const std::string& path, int panel_px) {
  ROVE_CHECK_MSG(panel_px >= 64 && panel_px <= 8192, "panel size {} outside [64, 8192]",
                 panel_px);
  const std::size_t n = reference.size();
  ROVE_CHECK_MSG(n >= 1 && estimate.size() == n && times.size() == n && errors.size() == n,
                 "plot of {} reference, {} estimate, {} times, {} errors", n, estimate.size(),
                 times.size(), errors.size());
  const int margin = 20, gap = 10, inner = panel_px - 2 * margin;
  Canvas canvas(2 * panel_px + gap, panel_px, kBackground);
  canvas.fill(panel_px, 0, panel_px + gap, panel_px, kSeparator);

  // Left: x-y, one scale for both trajectories.
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
  for (const auto* set : {&reference, &estimate})
    for (const auto& p : *set) {
      lo_x = std::min(lo_x, p.x()), hi_x = std::max(hi_x, p.x());
      lo_y = std::min(lo_y, p.y()), hi_y = std::max(hi_y, p.y());
    }
  const double span = std::max({hi_x - lo_x, hi_y - lo_y, 1e-9});
  const double scale = inner / span, cx = 0.5 * (lo_x + hi_x), cy = 0.5 * (lo_y + hi_y);
  auto px = [&](const Eigen::Vector3d& p) {
    return std::pair<int, int>(
        panel_px / 2 + static_cast<int>(std::lround((p.x() - cx) * scale)),
        panel_px / 2 - static_cast<int>(std::lround((p.y() - cy) * scale)));
  };
  for (std::size_t k = 0; k < n; ++k) {
    const auto [x0, y0] = px(reference[k]);
    const auto [x1, y1] = px(estimate[k]);
    canvas.line(x0, y0, x1, y1, kError);
  }
  for (const auto* set : {&reference, &estimate}) {
    const std::uint8_t c = set == &reference ? kReference : kEstimate;
    for (std::size_t k = 1; k < n; ++k) {
      const auto [x0, y0] = px((*set)[k - 1]);
      const auto [x1, y1] = px((*set)[k]);
      canvas.line(x0, y0, x1, y1, c);
    }
    const auto [x, y] = px((*set)[0]);
    canvas.dot(x, y, 2, c);
  }

  // Right: error over time, from 0 (bottom) to the largest error (top).
  const int ox = panel_px + gap, bottom = panel_px - margin, top = margin;
  canvas.line(ox + margin, top, ox + margin, bottom, kAxis);
  canvas.line(ox + margin, bottom, ox + margin + inner, bottom, kAxis);
  const double t0 = *std::min_element(times.begin(), times.end());
  const double t_span = std::max(*std::max_element(times.begin(), times.end()) - t0, 1e-9);
  const double e_max = std::max(*std::max_element(errors.begin(), errors.end()), 1e-12);
  auto ex = [&](std::size_t k) {
    return std::pair<int, int>(
        ox + margin + static_cast<int>(std::lround((times[k] - t0) / t_span * inner)),
        bottom - static_cast<int>(std::lround(errors[k] / e_max * (bottom - top))));
  };
  for (std::size_t k = 1; k < n; ++k) {
    const auto [x0, y0] = ex(k - 1);
    const auto [x1, y1] = ex(k);
    canvas.line(x0, y0, x1, y1, kEstimate);
  }
  const auto [x, y] = ex(0);
  canvas.set(x, y, kEstimate);
  PngEncoding encoding;
  encoding.palette = kPalette;
  write_png(path, canvas.image(), encoding);
}

}  // namespace rove::cli
