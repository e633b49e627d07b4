#pragma once
// The integer ray tracer of scan insertion (grid_insertion.cpp,
// grid_insertion_mrpt.cpp): MRPT's fixed-point DDA (9 fractional bits) and
// the cell updates of its CLogOddsGridMap2D, with the fast paths that skip
// saturated blocks. Pure integer code: the arithmetic strategy of the
// insertion decides only where each ray ends.

#include <cstddef>
#include <cstdint>

#include "rove/maps/grid_logodds.h"
#include "rove/maps/occupancy_grid.h"

namespace rove::detail {

inline constexpr int kFrBits = 9;           // fixed-point fraction bits of the ray tracer
inline constexpr int kFrOne = 1 << kFrBits;  // 1.0 in fixed point

// std::round for the fixed-point steps (|v| <= kFrOne) without a libm call:
// v − trunc(v) is exact, so this rounds half away from zero as std::round.
template <typename Real>
inline Real fixed_round(Real v) {
  const int t = static_cast<int>(v);
  const Real frac = v - static_cast<Real>(t);
  return static_cast<Real>(t + (frac >= Real(0.5)) - (frac <= Real(-0.5)));
}

/// MRPT's DDA step along one axis: round(d·2^kFrBits · inv_n) in Real, inv_n
/// = 1/n of the ray's n steps (the major axis, |d| = n, gives exactly
/// ±kFrOne: n·fl(1/n) is within one ulp of 1).
template <typename Real>
inline int fixed_step(int d, Real inv_n) {
  const int m = static_cast<int>(fixed_round(static_cast<Real>((d < 0 ? -d : d) * kFrOne) * inv_n));
  return d < 0 ? -m : m;
}

// The cell updates of MRPT's CLogOddsGridMap2D, saturating at the type's
// limits. `thres` is kMax − obs (free) or kMin + obs (occupied).
template <GridCell Cell>
inline void update_free(Cell* c, int obs, int thres) {
  *c = static_cast<Cell>(*c < thres ? *c + obs : LogOddsTraits<Cell>::kMax);
}
template <GridCell Cell>
inline void update_occupied(Cell* c, int obs, int thres) {
  *c = static_cast<Cell>(*c > thres ? *c - obs : LogOddsTraits<Cell>::kMin);
}

// One thin ray of a scan, in MRPT's order: DDA steps and free update, then
// the occupied update of its end cell (occupied < 0: none).
struct ThinRay {
  int fr_dx = 0, fr_dy = 0, n_steps = 0, obs = 0;
  std::ptrdiff_t occupied = -1;
  std::ptrdiff_t occupied_block = -1;  // block of `occupied` in the saturation summary
};

/// The saturation summary's block geometry (GridSaturationSummary).
inline constexpr int kLB = GridSaturationSummary::kLogBlock;
inline constexpr int kB = GridSaturationSummary::kBlock;

/// The free cells of one thin ray: n_steps fixed-point DDA steps from cell
/// (cx, cy), each checked against the grid (the slow path: a ray that leaves
/// the grid, e.g. from a sensor outside it; MRPT writes out of bounds there).
template <GridCell Cell>
void trace_free(Cell* data, unsigned sx, unsigned sy, int cx, int cy, int fr_dx, int fr_dy,
                int n_steps, int obs, int thres);

/// Recomputes every block's flag of the saturation summary from the cells.
template <GridCell Cell>
void rebuild_summary(const Cell* data, std::ptrdiff_t sx, std::ptrdiff_t sy,
                     GridSaturationSummary& sum);

/// All rays of a scan when every visited cell is inside the grid, with a
/// valid saturation summary: the same cells and updates, in the same order,
/// as trace_free + the occupied update of each ray (see grid_ray_trace.cpp).
template <GridCell Cell>
void trace_rays_summary(Cell* data, std::ptrdiff_t sx, std::ptrdiff_t sy, std::uint8_t* blocks,
                        std::ptrdiff_t bsx, int cx0, int cy0, const ThinRay* rays,
                        std::size_t n_rays, int thres_free, int obs_occupied, int thres_occupied);

}  // namespace rove::detail
