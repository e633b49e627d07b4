#include "rove/maps/grid_clearance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/memory_budget.h"

namespace rove {

namespace {

// One row of Meijster's second phase: the lower envelope of the parabolas
// (x − u)² + g(u)² of the row's columns u.
class EnvelopeRow {
  using T = std::int64_t;

 public:
  explicit EnvelopeRow(std::size_t w) : gsq_(w), h_(w), s_(w), t_(w), arg_(w) {}
  // Writes min over u of (x − u)² + g(u)² to d2[x] and returns the
  // minimizing u of every x (valid until the next call).
  const std::int64_t* solve(const std::vector<std::int64_t>& g, std::vector<std::uint64_t>& d2) {
    const auto n = static_cast<T>(g.size());
    for (T u = 0; u < n; ++u) {
      const T gu = g[static_cast<std::size_t>(u)];
      gsq_[static_cast<std::size_t>(u)] = gu * gu;
      h_[static_cast<std::size_t>(u)] = u * u + gu * gu;
    }
    // f(x, i) = (x − i)² + g(i)²; u's parabola is below i's (i < u) from
    // x = 1 + (h(u) − h(i)) / (2(u − i)) on (Meijster's Sep, in integer
    // division).
    const auto f = [&](T x, T i) { return (x - i) * (x - i) + gsq_[static_cast<std::size_t>(i)]; };
    T q = 0;
    s_[0] = 0;
    t_[0] = 0;
    for (T u = 1; u < n; ++u) {
      while (q >= 0 && f(t_[static_cast<std::size_t>(q)], s_[static_cast<std::size_t>(q)]) >
                           f(t_[static_cast<std::size_t>(q)], u))
        --q;
      if (q < 0) {
        q = 0;
        s_[0] = u;
      } else {
        const T i = s_[static_cast<std::size_t>(q)];
        const T wq = 1 + (h_[static_cast<std::size_t>(u)] - h_[static_cast<std::size_t>(i)]) / (2 * (u - i));
        if (wq < n) {
          ++q;
          s_[static_cast<std::size_t>(q)] = u;
          t_[static_cast<std::size_t>(q)] = wq;
        }
      }
    }
    for (T x = n - 1; x >= 0; --x) {
      const T u = s_[static_cast<std::size_t>(q)];
      d2[static_cast<std::size_t>(x)] = static_cast<std::uint64_t>(f(x, u));
      arg_[static_cast<std::size_t>(x)] = u;
      if (x == t_[static_cast<std::size_t>(q)]) --q;
    }
    return arg_.data();
  }

 private:
  std::vector<T> gsq_, h_, s_, t_, arg_;
};

// Meijster's two-phase exact Euclidean distance transform of the cells
// below `occupied_below`, delivered row by row: sink(y, d2, site) for every
// row y from the top row (ny − 1) down, d2 the row's squared distances (in
// cells²; UINT64_MAX without any occupied cell) and site, when `sites`,
// the index of a nearest occupied cell of each (kNoOccupiedCell without
// any); both valid during the call.
//
// Memory: `up` holds 4 bytes per cell, besides a few rows of work space.
// Phase 1 runs up the rows from y = 0, all columns together (row-major:
// the cache lines are read in order): up[i] is the row of the nearest
// occupied cell at or below i in its column. Phase 2 comes back down from
// the top row, carries the nearest occupied row at or above in each
// column, takes the nearer of the two (ties: the lower one) and finds the
// row's lower envelope at once. Row y of `up` is read before the sink is called for
// row y, so the sink may write the sites of row y over it (the site output
// of nearest_occupied_cell holds phase 1's rows: 24 bytes per cell before,
// which made `rove map voronoi` on a 16000 × 16000 map need 6 GB).
template <GridCell Cell, typename Sink>
void transform(const OccupancyGridT<Cell>& grid, Cell occupied_below, bool sites,
               std::vector<std::uint32_t>& up, const Sink& sink) {
  const std::int64_t nx = grid.size_x(), ny = grid.size_y();
  const auto n = static_cast<std::size_t>(nx * ny);
  if (n == 0) return;
  ROVE_CHECK_LT(n, std::size_t{kNoOccupiedCell});
  constexpr std::uint32_t kNone = kNoOccupiedCell;
  const auto w = static_cast<std::size_t>(nx);
  up.resize(n);
  const auto cells = grid.cells();
  // Phase 1, first half: per column, the row of the nearest occupied cell
  // at or below each cell.
  bool any = false;
  for (std::int64_t y = 0; y < ny; ++y) {
    const Cell* row = cells.data() + static_cast<std::size_t>(y) * w;
    std::uint32_t* u = up.data() + static_cast<std::size_t>(y) * w;
    const std::uint32_t* below = y > 0 ? u - w : nullptr;
    const auto yy = static_cast<std::uint32_t>(y);
    for (std::size_t x = 0; x < w; ++x) {
      const bool occupied = row[x] < occupied_below;
      any |= occupied;
      u[x] = occupied ? yy : (below != nullptr ? below[x] : kNone);
    }
  }
  std::vector<std::uint64_t> d2(w, std::numeric_limits<std::uint64_t>::max());
  std::vector<std::uint32_t> site(sites ? w : 0, kNone);
  if (!any) {
    for (std::int64_t y = ny - 1; y >= 0; --y) sink(y, d2.data(), sites ? site.data() : nullptr);
    return;
  }
  // Phase 2 comes down from the top row: `above` is the row of the nearest
  // occupied cell at or above in each column; r the nearer of the two
  // (ties: the one below).
  std::vector<std::uint32_t> above(w, kNone), r(w);
  // Phase 2: per row, the lower envelope of (x − u)² + g(u)²; its minimizing
  // column u and that column's nearest row give the nearest occupied cell.
  const std::int64_t inf = nx + ny;
  std::vector<std::int64_t> g(w);
  EnvelopeRow envelope(w);
  for (std::int64_t y = ny - 1; y >= 0; --y) {
    const Cell* row = cells.data() + static_cast<std::size_t>(y) * w;
    const std::uint32_t* u_row = up.data() + static_cast<std::size_t>(y) * w;
    const auto yy = static_cast<std::uint32_t>(y);
    for (std::size_t x = 0; x < w; ++x) {
      if (row[x] < occupied_below) above[x] = yy;
      const std::uint32_t lo = u_row[x], hi = above[x];
      std::uint32_t best = lo;
      if (hi != kNone && (lo == kNone || hi - yy < yy - lo)) best = hi;
      r[x] = best;
      g[x] = best == kNone ? inf : std::abs(y - static_cast<std::int64_t>(best));
    }
    const std::int64_t* v = envelope.solve(g, d2);
    if (sites) {
      for (std::size_t x = 0; x < w; ++x) {
        const auto u = static_cast<std::size_t>(v[x]);
        site[x] = r[u] == kNone ? kNone : static_cast<std::uint32_t>(u + std::size_t{r[u]} * w);
      }
    }
    sink(y, d2.data(), sites ? site.data() : nullptr);
  }
}

}  // namespace

template <GridCell Cell>
std::vector<std::uint64_t> squared_distance_to_occupied(const OccupancyGridT<Cell>& grid,
                                                        Cell occupied_below) {
  std::vector<std::uint64_t> d2(grid.cells().size());
  std::vector<std::uint32_t> up;
  const std::size_t w = grid.size_x();
  transform(grid, occupied_below, false, up, [&](std::int64_t y, const std::uint64_t* row, const std::uint32_t*) {
    std::copy(row, row + w, d2.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * w));
  });
  return d2;
}

template <GridCell Cell>
void squared_distance_rows(const OccupancyGridT<Cell>& grid, Cell occupied_below,
                           const std::function<void(std::uint32_t, std::span<const std::uint64_t>)>& row) {
  std::vector<std::uint32_t> up;
  const std::size_t w = grid.size_x();
  transform(grid, occupied_below, false, up, [&](std::int64_t y, const std::uint64_t* d2, const std::uint32_t*) {
    row(static_cast<std::uint32_t>(y), std::span<const std::uint64_t>(d2, w));
  });
}

double SqrtTable::operator()(std::uint64_t k) const noexcept {
  return k < kSize ? values_[k] : std::sqrt(static_cast<double>(k));
}

const SqrtTable& SqrtTable::instance() {
  static const SqrtTable table;
  return table;
}

SqrtTable::SqrtTable() : values_(kSize) {
  for (std::size_t k = 0; k < kSize; ++k) values_[k] = std::sqrt(static_cast<double>(k));
}

template <GridCell Cell>
std::vector<float> clearance_map(const OccupancyGridT<Cell>& grid, float occupied_threshold) {
  ROVE_CHECK_MSG(occupied_threshold >= 0.0f && occupied_threshold <= 1.0f,
                 "occupied_threshold {} is outside [0, 1]", occupied_threshold);
  // Raw values below p2l(threshold) have p(free) below the threshold.
  const Cell below = LogOddsLut<Cell>::instance().p2l(occupied_threshold);
  std::vector<float> out(grid.cells().size());
  const double res = grid.resolution();
  const SqrtTable& root = SqrtTable::instance();
  const std::size_t w = grid.size_x();
  std::vector<std::uint32_t> up;
  transform(grid, below, false, up, [&](std::int64_t y, const std::uint64_t* d2, const std::uint32_t*) {
    float* o = out.data() + static_cast<std::size_t>(y) * w;
    for (std::size_t x = 0; x < w; ++x) {
      o[x] = d2[x] == std::numeric_limits<std::uint64_t>::max() ? std::numeric_limits<float>::infinity()
                                                                 : static_cast<float>(root(d2[x]) * res);
    }
  });
  return out;
}

template <GridCell Cell>
std::vector<std::uint32_t> nearest_occupied_cell(const OccupancyGridT<Cell>& grid,
                                                 Cell occupied_below) {
  // Phase 1's rows are kept in the output and overwritten by the sites.
  std::vector<std::uint32_t> site;
  const std::size_t w = grid.size_x();
  transform(grid, occupied_below, true, site, [&](std::int64_t y, const std::uint64_t*, const std::uint32_t* row) {
    std::copy(row, row + w, site.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * w));
  });
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
template void squared_distance_rows(const OccupancyGridT<std::int8_t>&, std::int8_t,
                                    const std::function<void(std::uint32_t, std::span<const std::uint64_t>)>&);
template void squared_distance_rows(const OccupancyGridT<std::int16_t>&, std::int16_t,
                                    const std::function<void(std::uint32_t, std::span<const std::uint64_t>)>&);
template std::vector<float> clearance_map(const OccupancyGridT<std::int8_t>&, float);
template std::vector<float> clearance_map(const OccupancyGridT<std::int16_t>&, float);
template std::vector<std::uint32_t> nearest_occupied_cell(const OccupancyGridT<std::int8_t>&,
                                                          std::int8_t);
template std::vector<std::uint32_t> nearest_occupied_cell(const OccupancyGridT<std::int16_t>&,
                                                          std::int16_t);
template VoronoiDiagram voronoi_diagram(const OccupancyGridT<std::int8_t>&, const VoronoiOptions&);
template VoronoiDiagram voronoi_diagram(const OccupancyGridT<std::int16_t>&, const VoronoiOptions&);

}  // namespace rove
