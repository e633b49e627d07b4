#include "rove/maps/grid_clearance.h"

#include <cmath>
#include <limits>

#include "rove/core/check.h"

namespace rove {

template <GridCell Cell>
std::vector<std::uint64_t> squared_distance_to_occupied(const OccupancyGridT<Cell>& grid,
                                                        Cell occupied_below) {
  const std::int64_t nx = grid.size_x(), ny = grid.size_y();
  const auto n = static_cast<std::size_t>(nx * ny);
  std::vector<std::uint64_t> out(n, std::numeric_limits<std::uint64_t>::max());
  if (n == 0) return out;
  const auto cells = grid.cells();
  const std::int64_t inf = nx + ny;  // larger than any in-grid distance
  // Phase 1: per column, distance along y to the nearest occupied cell.
  std::vector<std::int64_t> gcol(n);
  bool any = false;
  for (std::int64_t x = 0; x < nx; ++x) {
    std::int64_t d = inf;
    for (std::int64_t y = 0; y < ny; ++y) {
      const auto i = static_cast<std::size_t>(x + y * nx);
      if (cells[i] < occupied_below) {
        d = 0;
        any = true;
      } else if (d < inf) {
        ++d;
      }
      gcol[i] = d;
    }
    d = inf;
    for (std::int64_t y = ny - 1; y >= 0; --y) {
      const auto i = static_cast<std::size_t>(x + y * nx);
      if (gcol[i] == 0) {
        d = 0;
      } else if (d < inf) {
        ++d;
      }
      if (d < gcol[i]) gcol[i] = d;
    }
  }
  if (!any) return out;
  // Phase 2: per row, lower envelope of the parabolas (x − i)² + g(i)².
  std::vector<std::int64_t> s(static_cast<std::size_t>(nx)), t(static_cast<std::size_t>(nx));
  for (std::int64_t y = 0; y < ny; ++y) {
    const std::int64_t* g = &gcol[static_cast<std::size_t>(y * nx)];
    const auto f = [&](std::int64_t x, std::int64_t i) { return (x - i) * (x - i) + g[i] * g[i]; };
    const auto sep = [&](std::int64_t i, std::int64_t u) {
      return (u * u - i * i + g[u] * g[u] - g[i] * g[i]) / (2 * (u - i));
    };
    std::int64_t q = 0;
    s[0] = 0;
    t[0] = 0;
    for (std::int64_t u = 1; u < nx; ++u) {
      while (q >= 0 && f(t[static_cast<std::size_t>(q)], s[static_cast<std::size_t>(q)]) > f(t[static_cast<std::size_t>(q)], u)) --q;
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
      const std::int64_t d2 = f(x, s[static_cast<std::size_t>(q)]);
      out[static_cast<std::size_t>(x + y * nx)] = static_cast<std::uint64_t>(d2);
      if (x == t[static_cast<std::size_t>(q)]) --q;
    }
  }
  return out;
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

template std::vector<std::uint64_t> squared_distance_to_occupied(const OccupancyGridT<std::int8_t>&,
                                                                 std::int8_t);
template std::vector<std::uint64_t> squared_distance_to_occupied(
    const OccupancyGridT<std::int16_t>&, std::int16_t);
template std::vector<float> clearance_map(const OccupancyGridT<std::int8_t>&, float);
template std::vector<float> clearance_map(const OccupancyGridT<std::int16_t>&, float);

}  // namespace rove
