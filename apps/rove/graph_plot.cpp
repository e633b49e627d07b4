// Pose-graph plots rasterized as palette indices and written by the maps
// module's PNG writer.
#include "graph_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "canvas.h"
#include "rove/core/check.h"
#include "rove/io/gray_image.h"

namespace rove::cli {
namespace {

// Palette indices; kPalette holds their colors.
using Gray = std::uint8_t;
constexpr Gray kBackground = 0, kSeparator = 1, kLoopClosure = 2, kOdometry = 3, kVertex = 4,
               kAnchor = 5;
const std::vector<PaletteColor> kPalette = {
    {255, 255, 255},  // background
    {200, 200, 200},  // separator between the panels
    {240, 150, 150},  // loop closures
    {40, 80, 220},    // odometry
    {0, 0, 0},        // vertices
    {0, 160, 0},      // anchors
};


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
  Canvas canvas(2 * panel_px + gap, panel_px, kBackground);
  canvas.fill(panel_px, 0, panel_px + gap, panel_px, kSeparator);
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
        canvas.line(x0, y0, x1, y1, odometry ? kOdometry : kLoopClosure);
      }
    }
    for (const auto& [id, v] : g->vertices()) {
      int x, y;
      to_px(v.pose, x, y);
      if (v.fixed) {
        canvas.dot(x, y, 4, kAnchor);
      } else {
        canvas.set(x, y, kVertex);
      }
    }
  }
  PngEncoding encoding;
  encoding.palette = kPalette;
  write_png(path, canvas.image(), encoding);
}

}  // namespace rove::cli
