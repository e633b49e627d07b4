#include "rove/nav/navigation_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/memory_budget.h"
#include "rove/maps/grid_clearance.h"

namespace rove {

namespace {

// Work space of a build per cell: the obstacle flag, the clearance and the
// transform's column pass (its squared distances come a row at a time).
constexpr std::uint64_t kBytesPerCell = 1 + 4 + 4;

void check_budget(std::uint32_t size_x, std::uint32_t size_y) {
  check_memory_budget(checked_bytes(static_cast<std::uint64_t>(size_x) * size_y, kBytesPerCell),
                      fmt::format("the navigation grid of a {} \u00d7 {} map", size_x, size_y));
}

}  // namespace

int NavigationGrid::to_cell(double q) noexcept {
  constexpr double kLimit = 1 << 30;
  if (!(q > -kLimit)) return -(1 << 30);
  if (q >= kLimit) return 1 << 30;
  return static_cast<int>(std::floor(q));
}

template <GridCell Cell>
NavigationGrid NavigationGrid::from_occupancy(const OccupancyGridT<Cell>& grid,
                                              float occupancy_threshold) {
  ROVE_CHECK_MSG(occupancy_threshold >= 0.0f && occupancy_threshold <= 1.0f,
                 "occupancy_threshold {} is outside [0, 1]", occupancy_threshold);
  ROVE_CHECK_MSG(grid.size_x() > 0 && grid.size_y() > 0, "the occupancy grid has no cells");
  check_budget(grid.size_x(), grid.size_y());
  // p(free) grows with the raw value: the obstacles are the raw values
  // below the first one whose p(free) exceeds the threshold (MRPT's
  // `getCell(x, y) > occupancyThreshold` is a free cell).
  using Traits = LogOddsTraits<Cell>;
  const auto& lut = LogOddsLut<Cell>::instance();
  int first_free = Traits::kMax + 1;
  for (int v = Traits::kMin; v <= Traits::kMax; ++v) {
    if (lut.l2p(static_cast<Cell>(v)) > occupancy_threshold) {
      first_free = v;
      break;
    }
  }
  NavigationGrid g;
  g.size_x_ = grid.size_x();
  g.size_y_ = grid.size_y();
  g.x_min_ = grid.x_min();
  g.y_min_ = grid.y_min();
  g.resolution_ = grid.resolution();
  const auto cells = grid.cells();
  g.occupied_.resize(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) g.occupied_[i] = cells[i] < first_free ? 1 : 0;
  g.clearance_.resize(cells.size());
  if (first_free > Traits::kMax) {
    // Every cell is an obstacle.
    std::fill(g.clearance_.begin(), g.clearance_.end(), 0.0f);
  } else {
    // The most negative raw value is never produced and reads as kMin, so
    // kMin as the bound means "no obstacle" for the transform too.
    squared_distance_rows(grid, static_cast<Cell>(std::max(first_free, Traits::kMin)),
                          [&g](std::uint32_t cy, std::span<const std::uint64_t> d2) { g.clearance_row(cy, d2); });
  }
  return g;
}

NavigationGrid NavigationGrid::from_mask(std::uint32_t size_x, std::uint32_t size_y, double x_min,
                                         double y_min, double resolution,
                                         std::vector<std::uint8_t> occupied) {
  ROVE_CHECK_MSG(size_x > 0 && size_y > 0, "a navigation grid needs cells, got {} x {}", size_x, size_y);
  ROVE_CHECK_EQ(occupied.size(), static_cast<std::size_t>(size_x) * size_y);
  ROVE_CHECK_FINITE(x_min);
  ROVE_CHECK_FINITE(y_min);
  ROVE_CHECK_MSG(std::isfinite(resolution) && resolution > 0, "resolution must be > 0, got {}",
                 resolution);
  check_budget(size_x, size_y);
  // The transform runs on an 8-bit grid holding the mask: obstacles at the
  // lowest value, free cells at the highest.
  OccupancyGrid tmp;
  std::vector<std::int8_t> cells(occupied.size());
  for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = occupied[i] ? -127 : 127;
  const auto fx = static_cast<float>(x_min), fy = static_cast<float>(y_min);
  const auto fr = static_cast<float>(resolution);
  tmp.assign(fx, fx + fr * static_cast<float>(size_x), fy, fy + fr * static_cast<float>(size_y), fr,
             size_x, size_y, std::move(cells));
  NavigationGrid g;
  g.size_x_ = size_x;
  g.size_y_ = size_y;
  g.x_min_ = x_min;
  g.y_min_ = y_min;
  g.resolution_ = resolution;
  g.occupied_ = std::move(occupied);
  for (auto& o : g.occupied_) o = o ? 1 : 0;
  g.clearance_.resize(g.occupied_.size());
  squared_distance_rows(tmp, std::int8_t{0},
                        [&g](std::uint32_t cy, std::span<const std::uint64_t> d2) { g.clearance_row(cy, d2); });
  return g;
}

void NavigationGrid::clearance_row(std::uint32_t cy, std::span<const std::uint64_t> d2) {
  const std::int64_t nx = size_x_, ny = size_y_, y = cy;
  const std::int64_t ring_y = std::min(y + 1, ny - y);
  const SqrtTable& root = SqrtTable::instance();
  float* out = clearance_.data() + static_cast<std::size_t>(y * nx);
  const std::uint8_t* occupied = occupied_.data() + static_cast<std::size_t>(y * nx);
  for (std::int64_t cx = 0; cx < nx; ++cx) {
    const auto i = static_cast<std::size_t>(cx);
    // The ring of outside cells is at ring distance along one axis.
    const auto ring = static_cast<double>(std::min({cx + 1, nx - cx, ring_y}));
    const double d = d2[i] == std::numeric_limits<std::uint64_t>::max() ? ring : std::min(ring, root(d2[i]));
    out[i] = occupied[i] ? 0.0f : static_cast<float>(d * resolution_);
  }
}

double NavigationGrid::distance_to_obstacle(const Eigen::Vector2d& p, double max_distance) const {
  ROVE_CHECK_MSG(max_distance >= 0, "max_distance must be >= 0, got {}", max_distance);
  const int cx = cell_x(p.x()), cy = cell_y(p.y());
  if (occupied(cx, cy)) return 0.0;
  // The nearest obstacle's center is at least clearance − res/√2 from p,
  // and its square reaches res/√2 closer.
  const double res = resolution_;
  if (clearance(cx, cy) - res * std::numbers::sqrt2 >= max_distance) return max_distance;
  double best = std::min({max_distance, p.x() - x_min_, x_max() - p.x(), p.y() - y_min_, y_max() - p.y()});
  const int r = static_cast<int>(std::ceil(best / res));
  const int x0 = std::max(0, cx - r), x1 = std::min<int>(static_cast<int>(size_x_) - 1, cx + r);
  const int y0 = std::max(0, cy - r), y1 = std::min<int>(static_cast<int>(size_y_) - 1, cy + r);
  for (int y = y0; y <= y1; ++y) {
    const double ly = y_min_ + y * res;
    const double dy = std::max({ly - p.y(), 0.0, p.y() - (ly + res)});
    if (dy >= best) continue;
    const std::uint8_t* row = &occupied_[index(0, y)];
    for (int x = x0; x <= x1; ++x) {
      if (!row[x]) continue;
      const double lx = x_min_ + x * res;
      const double dx = std::max({lx - p.x(), 0.0, p.x() - (lx + res)});
      best = std::min(best, std::hypot(dx, dy));
    }
  }
  return best;
}

void NavigationGrid::obstacles_near(const Eigen::Vector2d& p, double radius,
                                    std::vector<Eigen::Vector2d>& out) const {
  if (!(radius >= 0)) return;
  const int cx = cell_x(p.x()), cy = cell_y(p.y());
  if (contains(cx, cy) && clearance(cx, cy) - resolution_ * std::numbers::sqrt2 > radius) return;
  const int r = static_cast<int>(std::ceil(radius / resolution_)) + 1;
  const int x0 = std::max(0, cx - r), x1 = std::min<int>(static_cast<int>(size_x_) - 1, cx + r);
  const int y0 = std::max(0, cy - r), y1 = std::min<int>(static_cast<int>(size_y_) - 1, cy + r);
  const double r2 = radius * radius;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if (!occupied_[index(x, y)]) continue;
      const Eigen::Vector2d c = cell_center(x, y);
      if ((c - p).squaredNorm() <= r2) out.push_back(c);
    }
  }
}

bool NavigationGrid::visit_segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                   const std::function<bool(int, int)>& f) const {
  ROVE_CHECK_FINITE(a);
  ROVE_CHECK_FINITE(b);
  // Amanatides & Woo, "A fast voxel traversal algorithm for ray tracing"
  // (1987), in cell units; a crossing exactly through a corner visits both
  // cells beside it (supercover), so no diagonal step skips an obstacle.
  const double ux = (a.x() - x_min_) / resolution_, uy = (a.y() - y_min_) / resolution_;
  const double vx = (b.x() - x_min_) / resolution_, vy = (b.y() - y_min_) / resolution_;
  int cx = to_cell(ux), cy = to_cell(uy);
  const int ex = to_cell(vx), ey = to_cell(vy);
  const double dx = vx - ux, dy = vy - uy;
  const int sx = ex > cx ? 1 : -1, sy = ey > cy ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double tdx = dx != 0 ? std::abs(1.0 / dx) : kInf, tdy = dy != 0 ? std::abs(1.0 / dy) : kInf;
  double tx = ex == cx ? kInf : (sx > 0 ? (cx + 1 - ux) : (ux - cx)) * tdx;
  double ty = ey == cy ? kInf : (sy > 0 ? (cy + 1 - uy) : (uy - cy)) * tdy;
  std::int64_t steps = std::abs(static_cast<std::int64_t>(ex) - cx) + std::abs(static_cast<std::int64_t>(ey) - cy);
  if (!f(cx, cy)) return false;
  while (steps > 0) {
    if (std::abs(tx - ty) <= 1e-12 && cx != ex && cy != ey) {
      // Through a corner: both side cells, then the diagonal one.
      if (!f(cx + sx, cy) || !f(cx, cy + sy)) return false;
      cx += sx;
      cy += sy;
      tx += tdx;
      ty += tdy;
      steps -= 2;
    } else if ((tx < ty && cx != ex) || cy == ey) {
      cx += sx;
      tx += tdx;
      --steps;
    } else {
      cy += sy;
      ty += tdy;
      --steps;
    }
    if (!f(cx, cy)) return false;
  }
  return true;
}

double NavigationGrid::cast_ray(const Eigen::Vector2d& origin, double angle, double max_range) const {
  ROVE_CHECK_FINITE(angle);
  ROVE_CHECK_MSG(max_range >= 0 && std::isfinite(max_range), "max_range must be finite and >= 0, got {}",
                 max_range);
  const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d end = origin + dir * max_range;
  double hit = std::numeric_limits<double>::infinity();
  visit_segment(origin, end, [&](int x, int y) {
    if (!contains(x, y)) return false;
    if (!occupied_[index(x, y)]) return true;
    // Where the ray enters the cell's square (slab method).
    double t0 = 0;
    for (int k = 0; k < 2; ++k) {
      if (dir[k] == 0) continue;
      const double lo = (k == 0 ? x_min_ + x * resolution_ : y_min_ + y * resolution_);
      const double t_lo = (lo - origin[k]) / dir[k], t_hi = (lo + resolution_ - origin[k]) / dir[k];
      t0 = std::max(t0, std::min(t_lo, t_hi));
    }
    hit = t0;
    return false;
  });
  return hit <= max_range ? hit : std::numeric_limits<double>::infinity();
}

float NavigationGrid::segment_clearance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  float lowest = std::numeric_limits<float>::infinity();
  visit_segment(a, b, [&](int x, int y) {
    lowest = std::min(lowest, clearance(x, y));
    return lowest > 0.0f;
  });
  return lowest;
}

bool NavigationGrid::segment_free(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                  double radius) const {
  const auto r = static_cast<float>(radius);
  return visit_segment(a, b, [&](int x, int y) { return clearance(x, y) > r; });
}

template NavigationGrid NavigationGrid::from_occupancy(const OccupancyGridT<std::int8_t>&, float);
template NavigationGrid NavigationGrid::from_occupancy(const OccupancyGridT<std::int16_t>&, float);

}  // namespace rove
