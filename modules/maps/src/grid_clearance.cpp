#include "rove/maps/grid_clearance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"

namespace rove {

namespace {

// Meijster's two-phase exact Euclidean distance transform of the cells
// below `occupied_below`, writing the squared distance (in cells²;
// UINT64_MAX without any occupied cell) and/or the index of a nearest
// occupied cell (kNoOccupiedCell without any) of every cell.
template <GridCell Cell>
void transform(const OccupancyGridT<Cell>& grid, Cell occupied_below, std::vector<std::uint64_t>* d2,
               std::vector<std::uint32_t>* site) {
  const std::int64_t nx = grid.size_x(), ny = grid.size_y();
  const auto n = static_cast<std::size_t>(nx * ny);
  if (d2) d2->assign(n, std::numeric_limits<std::uint64_t>::max());
  if (site) {
    ROVE_CHECK_LT(n, std::size_t{kNoOccupiedCell});
    site->assign(n, kNoOccupiedCell);
  }
  if (n == 0) return;
  const auto cells = grid.cells();
  const std::int64_t inf = nx + ny;
  // Phase 1: per column, the row of the nearest occupied cell and its
  // distance along y (upward pass, then downward; ties keep the upward's).
  std::vector<std::int64_t> gcol(n, inf), grow(n, -1);
  bool any = false;
  for (std::int64_t x = 0; x < nx; ++x) {
    std::int64_t last = -1;
    for (std::int64_t y = 0; y < ny; ++y) {
      const auto i = static_cast<std::size_t>(x + y * nx);
      if (cells[i] < occupied_below) {
        last = y;
        any = true;
      }
      if (last >= 0) {
        gcol[i] = y - last;
        grow[i] = last;
      }
    }
    last = -1;
    for (std::int64_t y = ny - 1; y >= 0; --y) {
      const auto i = static_cast<std::size_t>(x + y * nx);
      if (gcol[i] == 0) last = y;
      if (last >= 0 && last - y < gcol[i]) {
        gcol[i] = last - y;
        grow[i] = last;
      }
    }
  }
  if (!any) return;
  // Phase 2: per row, the lower envelope of (x − u)² + g(u)²; its minimizing
  // column u and that column's nearest row give the nearest occupied cell.
  std::vector<std::int64_t> s(static_cast<std::size_t>(nx)), t(static_cast<std::size_t>(nx));
  for (std::int64_t y = 0; y < ny; ++y) {
    const std::int64_t* g = &gcol[static_cast<std::size_t>(y * nx)];
    const std::int64_t* r = &grow[static_cast<std::size_t>(y * nx)];
    const auto f = [&](std::int64_t x, std::int64_t i) { return (x - i) * (x - i) + g[i] * g[i]; };
    const auto sep = [&](std::int64_t i, std::int64_t u) {
      return (u * u - i * i + g[u] * g[u] - g[i] * g[i]) / (2 * (u - i));
    };
    std::int64_t q = 0;
    s[0] = 0;
    t[0] = 0;
    for (std::int64_t u = 1; u < nx; ++u) {
      while (q >= 0 && f(t[static_cast<std::size_t>(q)], s[static_cast<std::size_t>(q)]) >
                           f(t[static_cast<std::size_t>(q)], u))
        --q;
      if (q < 0) {
        q = 0;
        s[0] = u;
      } else {
        const std::int64_t w = 1 + sep(s[static_cast<std::size_t>(q)], u);
        if (w < nx) {
          ++q;
          s[static_cast<std::size_t>(q)] = u;
          t[static_cast<std::size_t>(q)] = w;
        }
      }
    }
    for (std::int64_t x = nx - 1; x >= 0; --x) {
      const std::int64_t u = s[static_cast<std::size_t>(q)];
      const auto i = static_cast<std::size_t>(x + y * nx);
      if (d2) (*d2)[i] = static_cast<std::uint64_t>(f(x, u));
      if (site && r[u] >= 0) (*site)[i] = static_cast<std::uint32_t>(u + r[u] * nx);
      if (x == t[static_cast<std::size_t>(q)]) --q;
    }
  }
}

}  // namespace

template <GridCell Cell>
std::vector<std::uint64_t> squared_distance_to_occupied(const OccupancyGridT<Cell>& grid,
                                                        Cell occupied_below) {
  std::vector<std::uint64_t> d2;
  transform(grid, occupied_below, &d2, nullptr);
  return d2;
}

template <GridCell Cell>
std::vector<float> clearance_map(const OccupancyGridT<Cell>& grid, float occupied_threshold) {
  ROVE_CHECK_MSG(occupied_threshold >= 0.0f && occupied_threshold <= 1.0f,
                 "occupied_threshold {} is outside [0, 1]", occupied_threshold);
  // Raw values below p2l(threshold) have p(free) below the threshold.
  const Cell below = LogOddsLut<Cell>::instance().p2l(occupied_threshold);
  const auto d2 = squared_distance_to_occupied(grid, below);
  std::vector<float> out(d2.size());
  const double res = grid.resolution();
  for (std::size_t i = 0; i < d2.size(); ++i) {
    out[i] = d2[i] == std::numeric_limits<std::uint64_t>::max()
                 ? std::numeric_limits<float>::infinity()
                 : static_cast<float>(std::sqrt(static_cast<double>(d2[i])) * res);
  }
  return out;
}


template <GridCell Cell>
std::vector<std::uint32_t> nearest_occupied_cell(const OccupancyGridT<Cell>& grid,
                                                 Cell occupied_below) {
  std::vector<std::uint32_t> site;
  transform(grid, occupied_below, nullptr, &site);
  return site;
}

template <GridCell Cell>
VoronoiDiagram voronoi_diagram(const OccupancyGridT<Cell>& grid, const VoronoiOptions& o) {
  ROVE_CHECK_MSG(o.occupied_threshold >= 0.0f && o.occupied_threshold <= 1.0f,
                 "occupied_threshold {} is outside [0, 1]", o.occupied_threshold);
  ROVE_CHECK_MSG(o.min_clearance >= 0.0f && std::isfinite(o.min_clearance),
                 "min_clearance must be finite and >= 0, got {}", o.min_clearance);
  ROVE_CHECK_MSG(o.min_separation > 0.0f && std::isfinite(o.min_separation),
                 "min_separation must be finite and > 0, got {}", o.min_separation);
  const Cell below = LogOddsLut<Cell>::instance().p2l(o.occupied_threshold);
  VoronoiDiagram vd;
  vd.size_x = grid.size_x();
  vd.size_y = grid.size_y();
  const std::int64_t nx = vd.size_x, ny = vd.size_y;
  vd.clearance.assign(static_cast<std::size_t>(nx * ny), 0.0f);
  const std::vector<std::uint32_t> site = nearest_occupied_cell(grid, below);
  const auto cells = grid.cells();
  const double res = grid.resolution();
  const double min_clear = o.min_clearance / res;  // cells
  const auto dist = [&](std::int64_t i, std::uint32_t to) {
    const std::int64_t dx = i % nx - static_cast<std::int64_t>(to) % nx;
    const std::int64_t dy = i / nx - static_cast<std::int64_t>(to) / nx;
    return std::sqrt(static_cast<double>(dx * dx + dy * dy));
  };
  const auto mark = [&](std::int64_t i, double d) {
    float& c = vd.clearance[static_cast<std::size_t>(i)];
    if (c == 0.0f) {
      c = static_cast<float>(d * res);
      ++vd.cells;
    }
  };
  for (std::int64_t y = 0; y < ny; ++y) {
    for (std::int64_t x = 0; x < nx; ++x) {
      const std::int64_t a = x + y * nx;
      const std::uint32_t sa = site[static_cast<std::size_t>(a)];
      if (sa == kNoOccupiedCell || cells[static_cast<std::size_t>(a)] < below) continue;
      // Each 4-neighbour pair once: the right and the upper neighbour.
      for (int k = 0; k < 2; ++k) {
        const std::int64_t b = k == 0 ? (x + 1 < nx ? a + 1 : -1) : (y + 1 < ny ? a + nx : -1);
        if (b < 0 || cells[static_cast<std::size_t>(b)] < below) continue;
        const std::uint32_t sb = site[static_cast<std::size_t>(b)];
        if (sb == sa) continue;
        const double da = dist(a, sa), db = dist(b, sb);
        const std::int64_t ex = static_cast<std::int64_t>(sa % nx) - static_cast<std::int64_t>(sb % nx);
        const std::int64_t ey = static_cast<std::int64_t>(sa / nx) - static_cast<std::int64_t>(sb / nx);
        const double apart = std::sqrt(static_cast<double>(ex * ex + ey * ey));
        if (!(apart > o.min_separation * std::max(da, db))) continue;
        // The cell nearer to the bisector: smaller excess distance to the
        // other cell's obstacle (ties: a).
        const double excess_a = dist(a, sb) - da, excess_b = dist(b, sa) - db;
        if (excess_a <= excess_b) {
          if (da > min_clear) mark(a, da);
        } else if (db > min_clear) {
          mark(b, db);
        }
      }
    }
  }
  return vd;
}

template std::vector<std::uint64_t> squared_distance_to_occupied(const OccupancyGridT<std::int8_t>&,
                                                                 std::int8_t);
template std::vector<std::uint64_t> squared_distance_to_occupied(
    const OccupancyGridT<std::int16_t>&, std::int16_t);
template std::vector<float> clearance_map(const OccupancyGridT<std::int8_t>&, float);
template std::vector<float> clearance_map(const OccupancyGridT<std::int16_t>&, float);
template std::vector<std::uint32_t> nearest_occupied_cell(const OccupancyGridT<std::int8_t>&,
                                                          std::int8_t);
template std::vector<std::uint32_t> nearest_occupied_cell(const OccupancyGridT<std::int16_t>&,
                                                          std::int16_t);
template VoronoiDiagram voronoi_diagram(const OccupancyGridT<std::int8_t>&, const VoronoiOptions&);
template VoronoiDiagram voronoi_diagram(const OccupancyGridT<std::int16_t>&, const VoronoiOptions&);

}  // namespace rove
