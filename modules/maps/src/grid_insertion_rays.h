#pragma once
// Scan insertion and the information of a scan, generic over the arithmetic
// of the ray geometry (Real): double for rove's default (grid_insertion.cpp),
// float for MRPT's (grid_insertion_mrpt.cpp, Arithmetic::Mrpt). Where each
// ray points comes from the caller (RayDirections); from there on both run
// MRPT's algorithm: end points and the grid's growth, then the fixed-point
// DDA of thin rays (grid_ray_trace.h) or the triangles and arcs of widening
// beams.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "grid_internal.h"
#include "grid_ray_trace.h"
#include "rove/core/check.h"
#include "rove/maps/grid_insertion.h"

namespace rove::detail {

/// The update strengths of one insertion (log-odds units of the cell type).
struct InsertStrengths {
  int obs_free = 0, obs_occupied = 0, obs_noecho_free = 0;
  int thres_free = 0, thres_occupied = 0;
};

/// Where the inserted rays point: ray k is the scan's ray k·step.
template <typename Real>
struct RayDirections {
  Real px = 0, py = 0;      // the sensor's position in the map, meters
  std::vector<Real> angle;  // world angle of each inserted ray, radians
  Real half_beam = 0;       // half the angular width of a beam (widening beams)
  int step = 1;             // insert one ray in this many
};

/// Whether ray i has a usable range.
inline bool ray_valid(const RangeScan2D& scan, std::size_t i) {
  const float r = scan.ranges[i];
  return scan.valid[i] && std::isfinite(r) && r >= 0.0f;
}

/// The length of inserted ray i (max_dist cuts it; a ray without echo is
/// half the last valid range when invalid_as_free), or −1 for none.
/// `last_valid_range` carries the last valid range from ray to ray.
template <typename Real>
Real ray_length(const RangeScan2D& scan, std::size_t i, Real max_dist, bool invalid_as_free,
                Real& last_valid_range) {
  if (ray_valid(scan, i)) {
    const Real r = scan.ranges[i];
    last_valid_range = r;
    return std::min(max_dist, r);
  }
  return invalid_as_free ? std::min(max_dist, Real(0.5) * last_valid_range) : Real(-1);
}

/// Per inserted ray: its end point (the sensor when it has no length), and
/// whether its range was valid.
template <typename Real>
struct RayEnds {
  std::vector<Real> x, y;
  std::vector<std::uint8_t> ok;
  Real x_min = std::numeric_limits<Real>::max(), x_max = -std::numeric_limits<Real>::max();
  Real y_min = std::numeric_limits<Real>::max(), y_max = -std::numeric_limits<Real>::max();
};

template <typename Real>
RayEnds<Real> ray_ends(const RangeScan2D& scan, const GridInsertionOptions& opt,
                       const RayDirections<Real>& dir) {
  RayEnds<Real> e;
  const std::size_t n = dir.angle.size();
  e.x.resize(n);
  e.y.resize(n);
  e.ok.resize(n);
  const Real max_dist = opt.max_distance_insertion;
  Real last_valid_range = max_dist;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = k * static_cast<std::size_t>(dir.step);
    e.ok[k] = ray_valid(scan, i);
    const Real rr = ray_length(scan, i, max_dist, opt.consider_invalid_ranges_as_free_space,
                               last_valid_range);
    Real ex = dir.px, ey = dir.py;
    if (rr >= Real(0)) {
      // One place for both, so that they become one sincos call.
      const Real c = std::cos(dir.angle[k]), sn = std::sin(dir.angle[k]);
      ex = dir.px + c * rr;
      ey = dir.py + sn * rr;
    }
    e.x[k] = ex;
    e.y[k] = ey;
    e.x_max = std::max(e.x_max, ex);
    e.x_min = std::min(e.x_min, ex);
    e.y_max = std::max(e.y_max, ey);
    e.y_min = std::min(e.y_min, ey);
  }
  return e;
}

/// Grows the grid to hold the box [x_min, x_max] × [y_min, y_max] as MRPT
/// does (a side within 15 cells of the edge grows by 30 cells or 2 m);
/// returns whether it changed.
template <typename Real, GridCell Cell>
bool grow_to(OccupancyGridT<Cell>& grid, Real x_min, Real x_max, Real y_min, Real y_max) {
  const Real margin = Real(15) * grid.resolution();
  const Real gx_min = grid.x_min(), gx_max = grid.x_max(), gy_min = grid.y_min(), gy_max = grid.y_max();
  x_max = x_max > gx_max - margin ? x_max + 2 * margin : gx_max;
  x_min = x_min < gx_min + margin ? x_min - 2 : gx_min;
  y_max = y_max > gy_max - margin ? y_max + 2 * margin : gy_max;
  y_min = y_min < gy_min + margin ? y_min - 2 : gy_min;
  const std::uint64_t before = grid.revision();
  grid.resize(static_cast<float>(x_min), static_cast<float>(x_max), static_cast<float>(y_min),
              static_cast<float>(y_max), 0.5f, true);
  return grid.revision() != before;
}

/// Thin rays: a fixed-point DDA from the sensor cell to each end cell.
template <typename Real, GridCell Cell>
std::size_t insert_thin_rays(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                             const GridInsertionOptions& opt, const InsertStrengths& st,
                             const RayDirections<Real>& dir, const RayEnds<Real>& ends,
                             bool summary_ok) {
  Cell* const data = grid.mutable_cells().data();
  GridSaturationSummary& summary = grid.saturation_summary();
  const int cx0 = grid.x_to_idx(dir.px);
  const int cy0 = grid.y_to_idx(dir.py);
  const auto sx = static_cast<std::int64_t>(grid.size_x());
  const auto sy = static_cast<std::int64_t>(grid.size_y());
  // The fast path needs every visited cell inside the grid and the
  // fixed-point accumulators far from overflow.
  bool fast = grid.contains(cx0, cy0) && sx < (1 << 21) && sy < (1 << 21);
  thread_local std::vector<ThinRay> rays;
  rays.clear();
  const std::size_t n = ends.x.size();
  for (std::size_t k = 0; k < n; ++k) {
    const bool ok = ends.ok[k] != 0;
    if (!ok && !opt.consider_invalid_ranges_as_free_space) continue;
    const int tx = grid.x_to_idx(ends.x[k]), ty = grid.y_to_idx(ends.y[k]);
    ROVE_CHECK(grid.contains(tx, ty));
    const int dx = tx - cx0, dy = ty - cy0;
    const int n_steps = std::max(dx < 0 ? -dx : dx, dy < 0 ? -dy : dy);
    if (n_steps == 0) continue;
    const Real inv_n = Real(1) / static_cast<Real>(n_steps);
    ThinRay r;
    r.fr_dx = fixed_step(dx, inv_n);
    r.fr_dy = fixed_step(dy, inv_n);
    r.n_steps = n_steps;
    r.obs = ok ? st.obs_free : st.obs_noecho_free;
    const std::size_t i = k * static_cast<std::size_t>(dir.step);
    if (ok && scan.ranges[i] < opt.max_distance_insertion) {
      r.occupied = static_cast<std::ptrdiff_t>(grid.index(tx, ty));
      r.occupied_block = (tx >> kLB) + static_cast<std::ptrdiff_t>(ty >> kLB) * ((sx + kB - 1) >> kLB);
    }
    if (fast) {
      // Each coordinate of the DDA is monotone in the step, so the ray
      // stays inside the grid if its first and last cells do.
      const std::int64_t last = n_steps - 1;
      const std::int64_t lx = (std::int64_t{cx0} * kFrOne + last * r.fr_dx) >> kFrBits;
      const std::int64_t ly = (std::int64_t{cy0} * kFrOne + last * r.fr_dy) >> kFrBits;
      fast = lx >= 0 && lx < sx && ly >= 0 && ly < sy &&
             (std::abs(r.fr_dx) == kFrOne || std::abs(r.fr_dy) == kFrOne);
    }
    rays.push_back(r);
  }
  if (fast) {
    if (!summary_ok) rebuild_summary(data, sx, sy, summary);
    trace_rays_summary(data, sx, sy, summary.blocks.data(), summary.blocks_x, cx0, cy0, rays.data(),
                       rays.size(), st.thres_free, st.obs_occupied, st.thres_occupied);
    summary.revision = grid.revision();
    return rays.size();
  }
  for (const ThinRay& r : rays) {
    trace_free(data, grid.size_x(), grid.size_y(), cx0, cy0, r.fr_dx, r.fr_dy, r.n_steps, r.obs,
               st.thres_free);
    if (r.occupied >= 0) {
      update_occupied(data + r.occupied, st.obs_occupied, st.thres_occupied);
      if (summary_ok) summary.blocks[static_cast<std::size_t>(r.occupied_block)] = 0;
    }
  }
  // Free updates keep flagged blocks at kMax; occupied ones cleared theirs.
  if (summary_ok) summary.revision = grid.revision();
  return rays.size();
}

/// A corner of a beam's triangle: meters and cell.
template <typename Real>
struct BeamPoint {
  Real x = 0, y = 0;
  int cx = 0, cy = 0;
};

/// The free cells of a triangle's rows, bounds-checked (MRPT has none).
template <GridCell Cell>
struct RowFiller {
  const OccupancyGridT<Cell>& grid;
  Cell* data;  // grid.mutable_cells().data()
  int obs = 0, thres = 0;
  void operator()(int y, int x_from, int x_to) const {
    if (y < 0 || static_cast<unsigned>(y) >= grid.size_y()) return;
    x_from = std::max(x_from, 0);
    x_to = std::min(x_to, static_cast<int>(grid.size_x()) - 1);
    Cell* row = data + grid.index(0, y);
    for (int x = x_from; x <= x_to; ++x) update_free(row + x, obs, thres);
  }
};

/// Scans one sub-triangle row by row between two fixed-point edges that
/// start at (e1x, e1y) and (e2x, ·) and step (step_x1, step_y) and step_x2
/// per row; `last_row` is where MRPT's loop starts counting and `upper` its
/// loop test (e1.cy < y_end for the lower half, <= for the upper one).
template <GridCell Cell>
void fill_rows(const RowFiller<Cell>& fill, int e1x, int e1y, int e2x, int step_x1, int step_y,
               int step_x2, int y_end, int last_row, bool upper) {
  int f1x = e1x * kFrOne, f1y = e1y * kFrOne, f2x = e2x * kFrOne;
  int c1x = e1x, c1y = e1y, c2x = e2x;
  do {
    if (last_row != c1y) {
      last_row = c1y;
      fill(c1y, c1x, c2x);
    }
    f1x += step_x1;
    f1y += step_y;
    f2x += step_x2;
    c1x = f1x >> kFrBits;
    c1y = f1y >> kFrBits;
    c2x = f2x >> kFrBits;
  } while (upper ? c1y <= y_end : c1y < y_end);
}

/// The free triangle sensor–(range − 1 cell) of one widening beam, split at
/// the middle corner's height into two triangles scanned row by row.
template <typename Real, GridCell Cell>
void beam_triangle(const OccupancyGridT<Cell>& grid, const RowFiller<Cell>& fill,
                   BeamPoint<Real> p0, BeamPoint<Real> p1, BeamPoint<Real> p2) {
  if (p2.y < p1.y) std::swap(p2, p1);
  if (p2.y < p0.y) std::swap(p2, p0);
  if (p1.y < p0.y) std::swap(p1, p0);
  for (BeamPoint<Real>* p : {&p0, &p1, &p2}) {
    p->cx = grid.x_to_idx(p->x);
    p->cy = grid.y_to_idx(p->y);
  }
  if (p0.cy == p2.cy && p0.cy == p1.cy) {
    fill(p0.cy, std::min({p0.cx, p1.cx, p2.cx}), std::max({p0.cx, p1.cx, p2.cx}));
    return;
  }
  // P1b: the point of edge P0–P2 at the height of P1.
  BeamPoint<Real> p1b;
  p1b.y = p1.y;
  p1b.x = p0.x + (p1.y - p0.y) * (p2.x - p0.x) / (p2.y - p0.y);
  p1b.cx = grid.x_to_idx(p1b.x);
  p1b.cy = grid.y_to_idx(p1b.y);
  const bool p1_left = p1.x < p1b.x;
  {  // Lower sub-triangle P0–P1–P1b.
    const int dx01 = p1.cx - p0.cx, dy01 = p1.cy - p0.cy, dx01b = p1b.cx - p0.cx;
    const Real inv_n =
        Real(1) / static_cast<Real>(std::max({std::abs(dx01), std::abs(dy01), std::abs(dx01b)}) + 1);
    const int fr_dx01 = fixed_step(dx01, inv_n), fr_dx01b = fixed_step(dx01b, inv_n);
    int fr_dy01 = fixed_step(dy01, inv_n);
    // MRPT loops forever when this rounds to 0 (beams wider than ~1000
    // cells); one fixed-point unit keeps the scan finite.
    if (dy01 > 0 && fr_dy01 == 0) fr_dy01 = 1;
    if (p0.cy != p1.cy) {
      fill_rows(fill, p0.cx, p0.cy, p0.cx, p1_left ? fr_dx01 : fr_dx01b, fr_dy01,
                p1_left ? fr_dx01b : fr_dx01, p1.cy, -1, false);
    } else {
      fill_rows(fill, p0.cx, p0.cy, p1.cx, 0, fr_dy01, 0, p1.cy, -1, false);
    }
  }
  {  // Upper sub-triangle P1–P1b–P2.
    const int dx12 = p2.cx - p1.cx, dy12 = p2.cy - p1.cy, dx1b2 = p2.cx - p1b.cx;
    const Real inv_n =
        Real(1) / static_cast<Real>(std::max({std::abs(dx12), std::abs(dy12), std::abs(dx1b2)}) + 1);
    const int fr_dx12 = fixed_step(dx12, inv_n), fr_dx1b2 = fixed_step(dx1b2, inv_n);
    const int fr_dy12 = fixed_step(dy12, inv_n);
    // A zero vertical step ends the loop after one row (MRPT).
    const int step_y = fr_dy12 != 0 ? fr_dy12 : 2 * kFrOne;
    const BeamPoint<Real>& left = p1_left ? p1 : p1b;
    const BeamPoint<Real>& right = p1_left ? p1b : p1;
    fill_rows(fill, left.cx, left.cy, right.cx, p1_left ? fr_dx12 : fr_dx1b2, step_y,
              p1_left ? fr_dx1b2 : fr_dx12, p2.cy, -100, true);
  }
}

/// The occupied cells along the arc q1–q2 at a beam's measured range.
template <typename Real, GridCell Cell>
void beam_arc(const OccupancyGridT<Cell>& grid, Cell* data, const InsertStrengths& st,
              const BeamPoint<Real>& q1, const BeamPoint<Real>& q2) {
  const auto occupied = [&](int cx, int cy) {
    if (grid.contains(cx, cy))
      update_occupied(data + grid.index(cx, cy), st.obs_occupied, st.thres_occupied);
  };
  if (q1.cx == q2.cx && q1.cy == q2.cy) {
    occupied(q1.cx, q1.cy);
    return;
  }
  const int dx = q2.cx - q1.cx, dy = q2.cy - q1.cy;
  const int n_steps = std::max(std::abs(dx), std::abs(dy)) + 1;
  const Real inv_n = Real(1) / static_cast<Real>(n_steps);
  const int fr_dx = fixed_step(dx, inv_n), fr_dy = fixed_step(dy, inv_n);
  int fx = q1.cx * kFrOne, fy = q1.cy * kFrOne;
  int cx = q1.cx, cy = q1.cy;
  for (int s = 0; s <= n_steps; ++s) {
    occupied(cx, cy);
    fx += fr_dx;
    fy += fr_dy;
    cx = fx >> kFrBits;
    cy = fy >> kFrBits;
  }
}

/// Widening beams: the triangle sensor–(range − 1 cell) of each beam as
/// free, then the arc at the range as occupied.
template <typename Real, GridCell Cell>
std::size_t insert_wide_beams(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                              const GridInsertionOptions& opt, const InsertStrengths& st,
                              const RayDirections<Real>& dir) {
  const Real res = grid.resolution();
  const Real max_dist = opt.max_distance_insertion;
  Real last_valid_range = max_dist;
  Cell* const data = grid.mutable_cells().data();
  const RowFiller<Cell> fill{grid, data, st.obs_free, st.thres_free};
  const auto corner = [&](Real angle, Real r) {
    BeamPoint<Real> p;
    p.x = dir.px + std::cos(angle) * r;
    p.y = dir.py + std::sin(angle) * r;
    p.cx = grid.x_to_idx(p.x);
    p.cy = grid.y_to_idx(p.y);
    return p;
  };
  std::size_t inserted = 0;
  for (std::size_t k = 0; k < dir.angle.size(); ++k) {
    const std::size_t i = k * static_cast<std::size_t>(dir.step);
    Real r = ray_length(scan, i, max_dist, opt.consider_invalid_ranges_as_free_space,
                        last_valid_range);
    if (r < res) continue;  // also a ray without length (−1)
    r -= res;
    ++inserted;
    const Real a = dir.angle[k];
    BeamPoint<Real> p0;
    p0.x = dir.px;
    p0.y = dir.py;
    beam_triangle(grid, fill, p0, corner(a - dir.half_beam, r), corner(a + dir.half_beam, r));
    // Occupied cells along the arc at the measured range, for a valid ray
    // that was not cut.
    if (ray_valid(scan, i) && scan.ranges[i] < opt.max_distance_insertion) {
      r += res;
      beam_arc(grid, data, st, corner(a - dir.half_beam, r), corner(a + dir.half_beam, r));
    }
  }
  return inserted;
}

/// Inserts the scan along the given ray directions (see the file comment).
template <typename Real, GridCell Cell>
GridInsertResult insert_rays(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                             const GridInsertionOptions& opt, const InsertStrengths& st,
                             const RayDirections<Real>& dir) {
  GridInsertResult result;
  result.message = "inserted";
  // The saturation summary is right if nothing changed the grid since the
  // last insertion left it right.
  bool summary_ok = grid.saturation_summary().revision == grid.revision();
  // End points and the box to grow the grid to.
  const RayEnds<Real> ends = ray_ends(scan, opt, dir);
  if (grow_to(grid, ends.x_min, ends.x_max, ends.y_min, ends.y_max)) summary_ok = false;
  grid.set_empty(false);
  result.rays_inserted = opt.widening_beams_with_distance
                             ? insert_wide_beams(grid, scan, opt, st, dir)
                             : insert_thin_rays(grid, scan, opt, st, dir, ends, summary_ok);
  return result;
}

/// The information of inserting the scan (thin rays along `dir`), the grid
/// unchanged: see scan_information in grid_internal.h. Probabilities and
/// entropies in Real.
template <typename Real, GridCell Cell>
ScanInformation scan_information_rays(const OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                                      const GridInsertionOptions& opt, const InsertStrengths& st,
                                      const RayDirections<Real>& dir) {
  const auto& lut = LogOddsLut<Cell>::instance();
  ScanInformation info;
  const Real max_h = std::log(Real(2));
  const auto entropy = [](Real p) { return (p == Real(0) || p == Real(1)) ? Real(0) : -p * std::log(p); };
  // One visit: the Bayesian update of the cell by an observation of
  // probability-of-free v, scored by the information of the result (MRPT's
  // updateCell in its information-counting mode).
  const auto visit = [&](int cx, int cy, int obs_logodds) {
    const Real old = grid.contains(cx, cy) ? Real(lut.l2p(grid.cells()[grid.index(cx, cy)])) : Real(0.5);
    const Real v = lut.l2p(static_cast<Cell>(obs_logodds));
    const Real nv = Real(1) / (Real(1) + (Real(1) - v) * (Real(1) - old) / (old * v));
    info.information += Real(1) - (entropy(nv) + entropy(Real(1) - nv)) / max_h;
    ++info.cells;
  };
  // Keep every cell index representable (a pose far from the grid has no
  // cell of the grid within reach anyway).
  const Real max_dist = opt.max_distance_insertion;
  const double reach = (std::fabs(dir.px - grid.x_min()) + std::fabs(dir.py - grid.y_min()) + max_dist) /
                       grid.resolution();
  if (!(reach < 1e9)) return info;
  const int cx0 = grid.x_to_idx(dir.px), cy0 = grid.y_to_idx(dir.py);
  Real last_valid_range = max_dist;
  for (std::size_t k = 0; k < dir.angle.size(); ++k) {
    const std::size_t i = k * static_cast<std::size_t>(dir.step);
    const bool ok = ray_valid(scan, i);
    const Real rr = ray_length(scan, i, max_dist, opt.consider_invalid_ranges_as_free_space,
                               last_valid_range);
    if (rr < Real(0)) continue;
    const int tx = grid.x_to_idx(dir.px + std::cos(dir.angle[k]) * rr);
    const int ty = grid.y_to_idx(dir.py + std::sin(dir.angle[k]) * rr);
    const int dx = tx - cx0, dy = ty - cy0;
    const int n_steps = std::max(std::abs(dx), std::abs(dy));
    if (n_steps == 0) continue;
    const Real inv_n = Real(1) / static_cast<Real>(n_steps);
    const int fr_dx = fixed_step(dx, inv_n), fr_dy = fixed_step(dy, inv_n);
    int fx = cx0 * kFrOne, fy = cy0 * kFrOne, cx = cx0, cy = cy0;
    for (int s = 0; s < n_steps; ++s) {
      visit(cx, cy, ok ? st.obs_free : st.obs_noecho_free);
      fx += fr_dx;
      fy += fr_dy;
      cx = fx >> kFrBits;
      cy = fy >> kFrBits;
    }
    if (ok && scan.ranges[i] < opt.max_distance_insertion) visit(tx, ty, -st.obs_occupied);
  }
  return info;
}

}  // namespace rove::detail
