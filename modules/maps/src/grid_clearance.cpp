#include "rove/maps/grid_clearance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/memory_budget.h"

namespace rove {

namespace {

// Meijster's two-phase exact Euclidean distance transform of the cells
// below `occupied_below`, writing the squared distance (in cells²;
// UINT64_MAX without any occupied cell) and/or the index of a nearest
// occupied cell (kNoOccupiedCell without any) of every cell.
//
// Memory: 4 bytes per cell besides the outputs. Phase 1 keeps only the row
// of each cell's nearest occupied cell in its column (its distance along y
// follows from it); phase 2 reads that row by row into a one-row buffer, so
// the site output can hold phase 1's rows in place (24 bytes per cell
// before, which made `rove map voronoi` on a 16000 × 16000 map need 6 GB).
template <GridCell Cell>
void transform(const OccupancyGridT<Cell>& grid, Cell occupied_below, std::vector<std::uint64_t>* d2,
               std::vector<std::uint32_t>* site) {
  const std::int64_t nx = grid.size_x(), ny = grid.size_y();
  const auto n = static_cast<std::size_t>(nx * ny);
  if (d2) d2->assign(n, std::numeric_limits<std::uint64_t>::max());
  if (n == 0) {
    if (site) site->clear();
    return;
  }
  ROVE_CHECK_LT(n, std::size_t{kNoOccupiedCell});
  constexpr std::uint32_t kNone = kNoOccupiedCell;
  // nearest_row[i]: the row of the nearest occupied cell in i's column
  // (kNone: the column has none). Shares the site output when there is one.
  std::vector<std::uint32_t> own;
  std::vector<std::uint32_t>& nearest_row = site ? *site : own;
  nearest_row.assign(n, kNone);
  const auto cells = grid.cells();
  // Phase 1: per column, the row of the nearest occupied cell (upward pass,
  // then downward; ties keep the upward's).
  bool any = false;
  for (std::int64_t x = 0; x < nx; ++x) {
    std::int64_t last = -1;
    for (std::int64_t y = 0; y < ny; ++y) {
      const auto i = static_cast<std::size_t>(x + y * nx);
      if (cells[i] < occupied_below) {
        last = y;
        any = true;
      }
      if (last >= 0) nearest_row[i] = static_cast<std::uint32_t>(last);
    }
    last = -1;
    for (std::int64_t y = ny - 1; y >= 0; --y) {
      const auto i = static_cast<std::size_t>(x + y * nx);
      const std::uint32_t r = nearest_row[i];
      if (r == static_cast<std::uint32_t>(y)) last = y;
      if (last >= 0 && (r == kNone || last - y < y - static_cast<std::int64_t>(r))) {
        nearest_row[i] = static_cast<std::uint32_t>(last);
      }
    }
  }
  if (!any) {
    if (site) site->assign(n, kNone);
    return;
  }
  // Phase 2: per row, the lower envelope of (x − u)² + g(u)²; its minimizing
  // column u and that column's nearest row give the nearest occupied cell.
  const std::int64_t inf = nx + ny;
  std::vector<std::int64_t> s(static_cast<std::size_t>(nx)), t(static_cast<std::size_t>(nx));
  std::vector<std::int64_t> g(static_cast<std::size_t>(nx));
  std::vector<std::uint32_t> r(static_cast<std::size_t>(nx));
  for (std::int64_t y = 0; y < ny; ++y) {
    const std::uint32_t* row = &nearest_row[static_cast<std::size_t>(y * nx)];
    std::copy(row, row + nx, r.begin());
    for (std::int64_t u = 0; u < nx; ++u) {
      const std::uint32_t ru = r[static_cast<std::size_t>(u)];
      g[static_cast<std::size_t>(u)] = ru == kNone ? inf : std::abs(y - static_cast<std::int64_t>(ru));
    }
    const auto f = [&](std::int64_t x, std::int64_t i) {
      const std::int64_t gi = g[static_cast<std::size_t>(i)];
      return (x - i) * (x - i) + gi * gi;
    };
    const auto sep = [&](std::int64_t i, std::int64_t u) {
      const std::int64_t gi = g[static_cast<std::size_t>(i)], gu = g[static_cast<std::size_t>(u)];
      return (u * u - i * i + gu * gu - gi * gi) / (2 * (u - i));
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
      if (site) {
        const std::uint32_t ru = r[static_cast<std::size_t>(u)];
        (*site)[i] = ru == kNone ? kNone : static_cast<std::uint32_t>(u + static_cast<std::int64_t>(ru) * nx);
      }
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

std::uint64_t voronoi_diagram_bytes(std::uint32_t size_x, std::uint32_t size_y) {
  // The nearest-obstacle index and the clearance, 4 bytes each per cell.
  return checked_bytes(static_cast<std::uint64_t>(size_x) * size_y, 8);
}

template <GridCell Cell>
VoronoiDiagram voronoi_diagram(const OccupancyGridT<Cell>& grid, const VoronoiOptions& o) {
  ROVE_CHECK_MSG(o.occupied_threshold >= 0.0f && o.occupied_threshold <= 1.0f,
                 "occupied_threshold {} is outside [0, 1]", o.occupied_threshold);
  ROVE_CHECK_MSG(o.min_clearance >= 0.0f && std::isfinite(o.min_clearance),
                 "min_clearance must be finite and >= 0, got {}", o.min_clearance);
  ROVE_CHECK_MSG(o.min_separation > 0.0f && std::isfinite(o.min_separation),
                 "min_separation must be finite and > 0, got {}", o.min_separation);
  check_memory_budget(voronoi_diagram_bytes(grid.size_x(), grid.size_y()),
                      fmt::format("the Voronoi diagram of a {} \u00d7 {} grid", grid.size_x(),
                                  grid.size_y()));
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
