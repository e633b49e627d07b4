// The integer ray tracer of scan insertion: see grid_ray_trace.h.

#include "grid_ray_trace.h"

#include <algorithm>
#include <cstring>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rove::detail {

template <GridCell Cell>
[[gnu::noinline]] void trace_free(Cell* data, unsigned sx, unsigned sy, int cx, int cy, int fr_dx, int fr_dy,
                int n_steps, int obs, int thres) {
  int fx = cx * kFrOne, fy = cy * kFrOne;
  for (int s = 0; s < n_steps; ++s) {
    if (static_cast<unsigned>(cx) < sx && static_cast<unsigned>(cy) < sy) [[likely]] {
      Cell* c = data + static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * sx;
      const int v = *c;
      *c = static_cast<Cell>(v < thres ? v + obs : LogOddsTraits<Cell>::kMax);
    }
    fx += fr_dx;
    fy += fr_dy;
    cx = fx >> kFrBits;
    cy = fy >> kFrBits;
  }
}

namespace {

// The same cells and updates as trace_free for a ray known to stay inside
// the grid, without per-cell checks: the DDA moves exactly one cell per step
// along its major axis (|fr| = kFrOne there, see trace_rays_summary), so the
// major coordinate becomes a pointer stride and only the minor coordinate
// keeps a fixed-point accumulator.
template <GridCell Cell>
inline void free_run(Cell* data, std::ptrdiff_t major, std::ptrdiff_t major_stride,
                     std::ptrdiff_t minor_stride, int f, int fr_minor, int n_steps, int obs,
                     int thres) {
  constexpr int kMax = LogOddsTraits<Cell>::kMax;
#pragma GCC unroll 4
  for (int s = 0; s < n_steps; ++s) {
    Cell* p = data + major + static_cast<std::ptrdiff_t>(f >> kFrBits) * minor_stride;
    // v < thres ? v + obs : kMax without a branch: whether a cell is
    // saturated is data, and a mispredicted branch per cell costs more than
    // the whole update.
    const int v = *p;
    const int keep = -static_cast<int>(v < thres);  // all ones or zero
    *p = static_cast<Cell>(kMax + ((v + obs - kMax) & keep));
    major += major_stride;
    f += fr_minor;
  }
}

// free_run for the usual case obs == kMax − thres, where the free update
// v < thres ? v + obs : kMax is the saturating add min(v + obs, kMax). The
// minor coordinate is a 64-bit accumulator, so it indexes without a sign
// extension; kXMajor fixes the strides: x-major steps one column and moves
// rows (× sx), y-major steps one row (sx) and moves columns. For 8-bit
// cells the update is a lookup in `add` (the 256 results of the saturating
// add, by the cell's byte): a load instead of an add, a compare and a
// conditional move. Same cells, same values as free_run.
template <bool kXMajor, GridCell Cell>
inline void free_run_saturating(Cell* data, std::ptrdiff_t major, std::ptrdiff_t sx, int dir,
                                std::int64_t f, std::int64_t fr_minor, int n_steps, int obs,
                                const std::uint8_t* add) {
  constexpr int kMax = LogOddsTraits<Cell>::kMax;
  Cell* base = data + major;
  const std::ptrdiff_t major_stride = kXMajor ? dir : dir * sx;
  // Cell s is at base + s·major_stride + ((f + s·fr) >> kFrBits): one
  // accumulator q = (base << kFrBits) + f gives the address as q >> kFrBits,
  // since a multiple of 2^kFrBits added to f moves its floor by exactly
  // that multiple. q must not overflow: the grid (below 2^31 cells) must
  // lie below 2^53 (user addresses are below 2^47 on x86-64 Linux, 2^52 on
  // AArch64; the loop below serves any other).
  constexpr std::uintptr_t kAccumulatorLimit = std::uintptr_t{1} << 53;
  if (!kXMajor && sizeof(Cell) == 1 &&
      reinterpret_cast<std::uintptr_t>(base) < kAccumulatorLimit) {
    auto q = static_cast<std::int64_t>(reinterpret_cast<std::uintptr_t>(base) << kFrBits) + f;
    const std::int64_t dq = major_stride * kFrOne + fr_minor;
    const auto update = [add](std::int64_t at) {
      auto* b = reinterpret_cast<std::uint8_t*>(static_cast<std::uintptr_t>(at >> kFrBits));
      *b = add[*b];
    };
    // Four steps from one accumulator value (q + k·dq, k < 4, are address
    // computations the compiler can fold), then one add of 4·dq.
    const std::int64_t dq2 = 2 * dq, dq3 = 3 * dq, dq4 = 4 * dq;
    int s = 0;
    for (; s + 4 <= n_steps; s += 4) {
      update(q);
      update(q + dq);
      update(q + dq2);
      update(q + dq3);
      q += dq4;
    }
    for (; s < n_steps; ++s, q += dq) update(q);
    return;
  }
  if constexpr (kXMajor && sizeof(Cell) == 1) {
    // Four steps from one accumulator value, with the column steps as
    // constant offsets (one loop per direction).
    const auto run = [&]<int kDir>() {
      auto* b = reinterpret_cast<std::uint8_t*>(base);
      const std::int64_t fr2 = 2 * fr_minor, fr3 = 3 * fr_minor, fr4 = 4 * fr_minor;
      const auto update = [add](std::uint8_t* c) { *c = add[*c]; };
      int s = 0;
      for (; s + 4 <= n_steps; s += 4) {
        update(b + (f >> kFrBits) * sx);
        update(b + kDir + ((f + fr_minor) >> kFrBits) * sx);
        update(b + 2 * kDir + ((f + fr2) >> kFrBits) * sx);
        update(b + 3 * kDir + ((f + fr3) >> kFrBits) * sx);
        b += 4 * kDir;
        f += fr4;
      }
      for (; s < n_steps; ++s, b += kDir, f += fr_minor) update(b + (f >> kFrBits) * sx);
    };
    if (dir > 0) {
      run.template operator()<1>();
    } else {
      run.template operator()<-1>();
    }
    return;
  }
#pragma GCC unroll 4
  for (int s = 0; s < n_steps; ++s) {
    Cell* p = base + (kXMajor ? (f >> kFrBits) * sx : (f >> kFrBits));
    if constexpr (sizeof(Cell) == 1) {
      auto* b = reinterpret_cast<std::uint8_t*>(p);
      *b = add[*b];
    } else {
      const int v = *p + obs;
      *p = static_cast<Cell>(v < kMax ? v : kMax);
    }
    base += major_stride;
    f += fr_minor;
  }
}

#if defined(__SSE2__)
// Cells [0, len) at p, len <= 16 bytes' worth, get v ↦ min(v + obs, kMax):
// one 16-byte load, saturating add and store; the lanes past len add 0 and
// are written back unchanged. Precondition: p + 16 bytes is inside the grid.
template <GridCell Cell>
inline void add_saturating(Cell* p, int len, __m128i obs_lanes) {
  alignas(16) static constexpr std::int8_t kOnes[32] = {-1, -1, -1, -1, -1, -1, -1, -1,
                                                        -1, -1, -1, -1, -1, -1, -1, -1};
  const __m128i mask = _mm_loadu_si128(reinterpret_cast<const __m128i*>(
      kOnes + 16 - len * static_cast<int>(sizeof(Cell))));
  auto* q = reinterpret_cast<__m128i*>(p);
  const __m128i v = _mm_loadu_si128(q);
  const __m128i add = _mm_and_si128(mask, obs_lanes);
  if constexpr (sizeof(Cell) == 1) {
    _mm_storeu_si128(q, _mm_adds_epi8(v, add));
  } else {
    _mm_storeu_si128(q, _mm_adds_epi16(v, add));
  }
}

// A ray whose major axis is x, when its free update is a saturating add
// (obs == kMax − thres: v < thres ? v + obs : kMax is min(v + obs, kMax)).
// The DDA's cells form runs of consecutive columns in one row; each run is
// updated by 16-byte vector operations. The run length is the number of
// steps before the fixed-point row changes, ⌊x / |fr|⌋ + 1 with x the
// distance to the row boundary (0..511), computed as (x·M) >> 20 with
// M = ⌈2^20 / |fr|⌉: the error x·(M − 2^20/|fr|)/2^20 < 511/2^20 is below
// the 1/|fr| ≥ 1/512 gap between x/|fr| and the next integer, so the floor
// is exact. Same cells, same final values as free_run.
template <GridCell Cell>
void free_rows(Cell* data, std::ptrdiff_t n_cells, std::ptrdiff_t sx, std::ptrdiff_t cx, int dir,
               int f, int fr, int n_steps, int obs) {
  constexpr int kLanes = 16 / static_cast<int>(sizeof(Cell));
  const __m128i obs_lanes = sizeof(Cell) == 1 ? _mm_set1_epi8(static_cast<char>(obs))
                                              : _mm_set1_epi16(static_cast<short>(obs));
  const auto afr = static_cast<std::uint32_t>(fr < 0 ? -fr : fr);
  const std::uint32_t m = afr == 0 ? 0 : ((1u << 20) + afr - 1) / afr;
  for (int s = 0; s < n_steps;) {
    int len = n_steps - s;
    if (fr != 0) {
      const int frac = f & (kFrOne - 1);
      const auto x = static_cast<std::uint32_t>(fr > 0 ? kFrOne - 1 - frac : frac);
      len = std::min(len, static_cast<int>((x * m) >> 20) + 1);
    }
    const std::ptrdiff_t first =
        static_cast<std::ptrdiff_t>(f >> kFrBits) * sx + (dir > 0 ? cx : cx - (len - 1));
    for (int done = 0; done < len; done += kLanes) {
      const int l = std::min(kLanes, len - done);
      const std::ptrdiff_t at = first + done;
      if (at + kLanes <= n_cells) [[likely]] {
        add_saturating(data + at, l, obs_lanes);
      } else {
        for (int j = 0; j < l; ++j) {
          const int v = data[at + j] + obs;
          data[at + j] = static_cast<Cell>(v < LogOddsTraits<Cell>::kMax ? v : LogOddsTraits<Cell>::kMax);
        }
      }
    }
    s += len;
    f += len * fr;
    cx += dir * len;
  }
}
#endif

// The saturation summary (GridSaturationSummary): per block of kB × kB
// cells, a flag "every cell is at kMax" or a count of the ray steps that
// reached the block (as the first one a ray could not skip) since it was
// last checked. A free update leaves a cell at kMax unchanged (v < thres ?
// v + obs : kMax with thres < kMax), so a ray may skip a flagged block
// without reading it; an occupied update clears its block's flag. A block
// is checked when its count reaches kCheck (one compare of kB cells per
// row, stopping at the first row that differs). 16 × 16 blocks halve the
// prefix walk's chunks against 8 × 8 (measured: 6 % fewer instructions on
// the Telecom insertions), at the price of flags that need a larger area
// saturated.
using Summary = GridSaturationSummary;
constexpr int kCheck = 8 * kB;
static_assert(kCheck + kB < Summary::kFull, "a block's count must never read as kFull");

// True if every cell of block (bx, by) that lies inside the grid is kMax.
template <GridCell Cell>
bool block_saturated(const Cell* data, std::ptrdiff_t sx, std::ptrdiff_t sy, std::ptrdiff_t bx,
                     std::ptrdiff_t by) {
  constexpr Cell kMax = LogOddsTraits<Cell>::kMax;
  const std::ptrdiff_t x0 = bx * kB, y0 = by * kB;
  const std::ptrdiff_t nx = std::min<std::ptrdiff_t>(kB, sx - x0);
  const std::ptrdiff_t ny = std::min<std::ptrdiff_t>(kB, sy - y0);
  const Cell* row = data + x0 + y0 * sx;
  if (nx == kB) {
    Cell pattern[kB];
    for (auto& c : pattern) c = kMax;
    for (std::ptrdiff_t y = 0; y < ny; ++y, row += sx) {
      if (std::memcmp(row, pattern, sizeof pattern) != 0) return false;
    }
    return true;
  }
  for (std::ptrdiff_t y = 0; y < ny; ++y, row += sx) {
    for (std::ptrdiff_t x = 0; x < nx; ++x) {
      if (row[x] != kMax) return false;
    }
  }
  return true;
}

}  // namespace

// Recomputes every block's flag from the cells (counts start at 0).
template <GridCell Cell>
void rebuild_summary(const Cell* data, std::ptrdiff_t sx, std::ptrdiff_t sy, Summary& sum) {
  sum.blocks_x = static_cast<std::uint32_t>((sx + kB - 1) >> kLB);
  sum.blocks_y = static_cast<std::uint32_t>((sy + kB - 1) >> kLB);
  sum.blocks.assign(static_cast<std::size_t>(sum.blocks_x) * sum.blocks_y, 0);
  std::uint8_t* b = sum.blocks.data();
  for (std::ptrdiff_t by = 0; by < sum.blocks_y; ++by) {
    for (std::ptrdiff_t bx = 0; bx < sum.blocks_x; ++bx, ++b) {
      if (block_saturated(data, sx, sy, bx, by)) *b = Summary::kFull;
    }
  }
}

// All rays of a scan when every visited cell is inside the grid (checked by
// the caller), with a valid saturation summary. Same cells, same updates in
// the same order as trace_free + occupied update, except that free updates
// of cells in flagged blocks (which change nothing) are skipped where a ray
// starts: the sensor usually stands in space that many earlier scans have
// saturated, and skipping per block only while the ray's blocks are flagged
// keeps the branch predictable (measured on the Telecom rawlog: 84 % of the
// visits that fall in flagged blocks are in such a prefix; skipping every
// flagged block along the ray costs more in mispredicted branches than it
// saves). The rest of the ray is traced cell by cell as before.
//
// The prefix is walked in chunks of steps that share one block column along
// the major axis (kB steps, the first one up to the block edge). The DDA
// moves one cell per step along its major axis (|fr| = kFrOne there) and at
// most one cell per step along the minor one, so a chunk's cells lie in the
// at most two blocks that hold its first and last cells (minor coordinate
// monotone, spanning at most kB − 1 cells); both flagged means the whole
// chunk may be skipped. Each chunk is computed from its first step alone,
// so the walk carries no dependency from one chunk to the next but s.
// The first chunk that is not skipped counts its steps in its unflagged
// blocks, which are checked when their count reaches kCheck: this moves the
// frontier of flagged blocks outward as the map saturates.
template <GridCell Cell>
[[gnu::noinline]] void trace_rays_summary(Cell* data, std::ptrdiff_t sx, std::ptrdiff_t sy,
                                          std::uint8_t* blocks, std::ptrdiff_t bsx, int cx0,
                                          int cy0, const ThinRay* rays, std::size_t n_rays,
                                          int thres_free, int obs_occupied, int thres_occupied) {
  [[maybe_unused]] constexpr int kMax = LogOddsTraits<Cell>::kMax;
  // Vector runs pay off for rays within ~14° of the x axis (runs of >= 4).
  [[maybe_unused]] constexpr int kShallow = kFrOne / 4;
  // The saturating free update of an 8-bit cell, by the cell's byte.
  alignas(64) std::uint8_t add[256] = {};
  if constexpr (sizeof(Cell) == 1) {
    const int obs = kMax - thres_free;
    for (int u = 0; u < 256; ++u) {
      const int v = static_cast<std::int8_t>(static_cast<std::uint8_t>(u)) + obs;
      add[u] = static_cast<std::uint8_t>(static_cast<std::int8_t>(v < kMax ? v : kMax));
    }
  }
  for (std::size_t k = 0; k < n_rays; ++k) {
    const ThinRay& r = rays[k];
    const bool x_major = r.fr_dx == kFrOne || r.fr_dx == -kFrOne;
    // Major coordinate a0 (cells) and minor fixed-point accumulator f0 at
    // step 0: step s visits major a0 ± s, minor (f0 + s·fr) >> kFrBits.
    const int a0 = x_major ? cx0 : cy0;
    const int f0 = (x_major ? cy0 : cx0) * kFrOne;
    const int dir = (x_major ? r.fr_dx : r.fr_dy) > 0 ? 1 : -1;
    const int fr = x_major ? r.fr_dy : r.fr_dx;
    const std::ptrdiff_t ab_stride = x_major ? 1 : bsx, mb_stride = x_major ? bsx : 1;
    const int n_steps = r.n_steps;
    // A block the walk reached that is not flagged: count, maybe check.
    const auto frontier_full = [&](std::uint8_t& st, int len, int a, int m) {
      if (st == Summary::kFull) return true;
      st = static_cast<std::uint8_t>(st + len);
      if (st < kCheck) return false;
      const int bx = (x_major ? a : m) >> kLB, by = (x_major ? m : a) >> kLB;
      st = block_saturated(data, sx, sy, bx, by) ? Summary::kFull : 0;
      return st == Summary::kFull;
    };
    // The walk keeps the chunk's first minor accumulator and its block
    // column as running values (one add each per chunk).
    int s = 0;
    int chunk = dir > 0 ? kB - (a0 & (kB - 1)) : (a0 & (kB - 1)) + 1;
    std::int64_t f_first = f0;
    // An index, not a pointer: after the ray's last chunk it may point one
    // column outside the summary.
    std::ptrdiff_t column = static_cast<std::ptrdiff_t>(a0 >> kLB) * ab_stride;
    const std::ptrdiff_t column_step = dir * ab_stride;
    while (s < n_steps) {
      const int len = std::min(chunk, n_steps - s);
      const std::int64_t f_last = f_first + static_cast<std::int64_t>(len - 1) * fr;
      const auto m_first = static_cast<int>(f_first >> kFrBits);
      const auto m_last = static_cast<int>(f_last >> kFrBits);
      std::uint8_t& st_first = blocks[column + static_cast<std::ptrdiff_t>(m_first >> kLB) * mb_stride];
      std::uint8_t& st_last = blocks[column + static_cast<std::ptrdiff_t>(m_last >> kLB) * mb_stride];
      if ((st_first & st_last) != Summary::kFull) [[unlikely]] {
        const int a = a0 + dir * s;
        if (!frontier_full(st_first, len, a, m_first)) break;
        if (&st_last != &st_first && !frontier_full(st_last, len, a, m_last)) break;
      }
      s += len;
      f_first += static_cast<std::int64_t>(len) * fr;
      column += column_step;
      chunk = kB;
    }
    const int a = a0 + dir * s;
    const int f = f0 + s * fr;
    const int n = r.n_steps - s;
#if defined(__SSE2__)
    if (x_major && r.obs == kMax - thres_free && fr >= -kShallow && fr <= kShallow) {
      free_rows(data, sx * sy, sx, a, dir, f, fr, n, r.obs);
    } else
#endif
    if (r.obs == kMax - thres_free) {
      if (x_major) {
        free_run_saturating<true>(data, a, sx, dir, f, fr, n, r.obs, add);
      } else {
        free_run_saturating<false>(data, a * sx, sx, dir, f, fr, n, r.obs, add);
      }
    } else if (x_major) {
      // Major axis x: cell (a ± j, (f + j·fr) >> kFrBits).
      free_run(data, a, dir, sx, f, fr, n, r.obs, thres_free);
    } else {
      // Major axis y: cell ((f + j·fr) >> kFrBits, a ± j).
      free_run(data, a * sx, dir * sx, 1, f, fr, n, r.obs, thres_free);
    }
    if (r.occupied >= 0) {
      update_occupied(data + r.occupied, obs_occupied, thres_occupied);
      blocks[r.occupied_block] = 0;
    }
  }
}

template void trace_free(std::int8_t*, unsigned, unsigned, int, int, int, int, int, int, int);
template void trace_free(std::int16_t*, unsigned, unsigned, int, int, int, int, int, int, int);
template void rebuild_summary(const std::int8_t*, std::ptrdiff_t, std::ptrdiff_t,
                              GridSaturationSummary&);
template void rebuild_summary(const std::int16_t*, std::ptrdiff_t, std::ptrdiff_t,
                              GridSaturationSummary&);
template void trace_rays_summary(std::int8_t*, std::ptrdiff_t, std::ptrdiff_t, std::uint8_t*,
                                 std::ptrdiff_t, int, int, const ThinRay*, std::size_t, int, int,
                                 int);
template void trace_rays_summary(std::int16_t*, std::ptrdiff_t, std::ptrdiff_t, std::uint8_t*,
                                 std::ptrdiff_t, int, int, const ThinRay*, std::size_t, int, int,
                                 int);

}  // namespace rove::detail
