#include "rove/maps/grid_insertion.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/angle.h"
#include "grid_internal.h"

namespace rove {
namespace {

constexpr int kFrBits = 9;           // fixed-point fraction bits of the ray tracer
constexpr int kFrOne = 1 << kFrBits;  // 1.0 in fixed point

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

// std::round for the fixed-point steps (|v| <= kFrOne) without a libm call:
// v − trunc(v) is exact in float, so this rounds half away from zero as
// std::round does.
inline float float_round(float v) {
  const int t = static_cast<int>(v);
  const float frac = v - static_cast<float>(t);
  return static_cast<float>(t + (frac >= 0.5f) - (frac <= -0.5f));
}

// The free cells of one thin ray: n_steps fixed-point DDA steps from cell
// (cx, cy), each checked against the grid (the slow path: a ray that leaves
// the grid, e.g. from a sensor outside it; MRPT writes out of bounds there).
// Kept small and on locals: stores through Cell* (a char type) may alias
// anything, and the caller's many live values would spill otherwise.
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

// One thin ray of a scan, in MRPT's order: DDA steps and free update, then
// the occupied update of its end cell (occupied < 0: none).
struct ThinRay {
  int fr_dx = 0, fr_dy = 0, n_steps = 0, obs = 0;
  std::ptrdiff_t occupied = -1;
  std::ptrdiff_t occupied_block = -1;  // block of `occupied` in the saturation summary
};

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
constexpr int kLB = Summary::kLogBlock;
constexpr int kB = Summary::kBlock;
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

// The per-ray buffers of insert_impl, reused from scan to scan.
struct InsertScratch {
  std::vector<float> end_x, end_y;
  std::vector<std::uint8_t> ray_ok;
  std::vector<int> cell_x, cell_y, fr_dx, fr_dy, n_steps;
  std::vector<ThinRay> rays;
  void resize(std::size_t n) {
    for (auto* v : {&end_x, &end_y}) v->resize(n);
    for (auto* v : {&cell_x, &cell_y, &fr_dx, &fr_dy, &n_steps}) v->resize(n);
    ray_ok.resize(n);
    rays.reserve(n);
  }
};

struct LocalPoint {
  float x = 0, y = 0;
  int cx = 0, cy = 0;
};

template <GridCell Cell>
struct Inserter {
  OccupancyGridT<Cell>& grid;
  const RangeScan2D& scan;
  const GridInsertionOptions& opt;
  int obs_free = 0, obs_occupied = 0, obs_noecho_free = 0;
  int thres_free = 0, thres_occupied = 0;

  bool valid(std::size_t i) const {
    const float r = scan.ranges[i];
    return scan.valid[i] && std::isfinite(r) && r >= 0.0f;
  }

  // Free update of a cell given by index, bounds-checked (MRPT has no check;
  // for every ray MRPT handles, the cells are inside the grown grid).
  void free_cell(int cx, int cy, int obs) {
    if (!grid.contains(cx, cy)) return;
    Cell* c = grid_data + grid.index(cx, cy);
    update_free(c, obs, thres_free);
  }
  void occupied_cell(int cx, int cy) {
    if (!grid.contains(cx, cy)) return;
    update_occupied(grid_data + grid.index(cx, cy), obs_occupied, thres_occupied);
  }
  Cell* grid_data = nullptr;
};

}  // namespace

GridInsertionOptions GridInsertionOptions::from_config(const ConfigSection& config) {
  GridInsertionOptions o;
  const IniFile& ini = config.ini();
  const std::string_view section = config.name();
  const std::string sec(section);
  const auto read_float = [&](const char* key, float& v) {
    if (ini.has(section, key)) v = ini.get<float>(section, key);
  };
  const auto read_bool = [&](const char* key, bool& v) {
    if (ini.has(section, key)) v = ini.get<bool>(section, key);
  };
  read_float("mapAltitude", o.map_altitude);
  read_float("maxDistanceInsertion", o.max_distance_insertion);
  read_float("maxOccupancyUpdateCertainty", o.max_occupancy_update_certainty);
  read_float("maxFreenessUpdateCertainty", o.max_freeness_update_certainty);
  read_float("maxFreenessInvalidRanges", o.max_freeness_invalid_ranges);
  read_bool("useMapAltitude", o.use_map_altitude);
  read_bool("considerInvalidRangesAsFreeSpace", o.consider_invalid_ranges_as_free_space);
  if (ini.has(section, "decimation")) {
    const int d = ini.get<int>(section, "decimation");
    if (d < 1 || d > 65535) {
      throw ConfigError(ini.source(), sec, "decimation", "must be in [1, 65535]");
    }
    o.decimation = static_cast<std::uint16_t>(d);
  }
  if (ini.has(section, "horizontalTolerance")) {
    const float deg = ini.get<float>(section, "horizontalTolerance");
    o.horizontal_tolerance = static_cast<float>(deg * (kPi / 180.0));
  }
  read_float("CFD_features_gaussian_size", o.cfd_features_gaussian_size);
  read_float("CFD_features_median_size", o.cfd_features_median_size);
  read_bool("wideningBeamsWithDistance", o.widening_beams_with_distance);
  // Each value against its range, naming the key (check() below is the
  // precondition of the algorithms and stays the last line of defence).
  const auto need = [&](bool ok, const char* key, float v, std::string_view range) {
    if (!ok) {
      throw ConfigError(ini.source(), sec, key,
                        fmt::format("line {}: {} is outside {}", ini.line(section, key).value_or(0),
                                    v, range));
    }
  };
  const auto unit = [](float v) { return v >= 0.0f && v <= 1.0f; };
  need(std::isfinite(o.map_altitude), "mapAltitude", o.map_altitude, "the finite numbers");
  need(std::isfinite(o.max_distance_insertion) && o.max_distance_insertion > 0.0f,
       "maxDistanceInsertion", o.max_distance_insertion, "(0, inf) meters");
  need(unit(o.max_occupancy_update_certainty), "maxOccupancyUpdateCertainty",
       o.max_occupancy_update_certainty, "[0, 1]");
  need(unit(o.max_freeness_update_certainty), "maxFreenessUpdateCertainty",
       o.max_freeness_update_certainty, "[0, 1]");
  need(unit(o.max_freeness_invalid_ranges), "maxFreenessInvalidRanges", o.max_freeness_invalid_ranges,
       "[0, 1]");
  need(std::isfinite(o.horizontal_tolerance) && o.horizontal_tolerance >= 0.0f, "horizontalTolerance",
       static_cast<float>(o.horizontal_tolerance * (180.0 / kPi)), "[0, inf) degrees");
  need(std::isfinite(o.cfd_features_gaussian_size), "CFD_features_gaussian_size",
       o.cfd_features_gaussian_size, "the finite numbers");
  need(std::isfinite(o.cfd_features_median_size), "CFD_features_median_size",
       o.cfd_features_median_size, "the finite numbers");
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), sec, "", e.message());
  }
  return o;
}

void GridInsertionOptions::check() const {
  ROVE_CHECK_FINITE(map_altitude);
  ROVE_CHECK_FINITE(max_distance_insertion);
  ROVE_CHECK_GT(max_distance_insertion, 0.0f);
  ROVE_CHECK_MSG(max_occupancy_update_certainty >= 0.0f && max_occupancy_update_certainty <= 1.0f,
                 "maxOccupancyUpdateCertainty = {} is outside [0, 1]",
                 max_occupancy_update_certainty);
  ROVE_CHECK_MSG(max_freeness_update_certainty >= 0.0f && max_freeness_update_certainty <= 1.0f,
                 "maxFreenessUpdateCertainty = {} is outside [0, 1]",
                 max_freeness_update_certainty);
  ROVE_CHECK_MSG(max_freeness_invalid_ranges >= 0.0f && max_freeness_invalid_ranges <= 1.0f,
                 "maxFreenessInvalidRanges = {} is outside [0, 1]", max_freeness_invalid_ranges);
  ROVE_CHECK_GE(decimation, 1);
  ROVE_CHECK_FINITE(horizontal_tolerance);
  ROVE_CHECK_GE(horizontal_tolerance, 0.0f);
  ROVE_CHECK_FINITE(cfd_features_gaussian_size);
  ROVE_CHECK_FINITE(cfd_features_median_size);
}

bool is_horizontal(const Pose3& T_robot_sensor, double tolerance) {
  const auto ypr = T_robot_sensor.yaw_pitch_roll();
  return (std::fabs(ypr.pitch) <= tolerance || kPi - std::fabs(ypr.pitch) <= tolerance) &&
         (std::fabs(ypr.roll) <= tolerance || std::fabs(wrap_to_pi(ypr.roll - kPi)) <= tolerance);
}

namespace {

template <GridCell Cell>
GridInsertResult insert_impl(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                             const Pose3& T_map_robot, const GridInsertionOptions& opt,
                             bool mrpt_wrap) {
  scan.check();
  opt.check();
  using Traits = LogOddsTraits<Cell>;
  const auto& lut = LogOddsLut<Cell>::instance();
  GridInsertResult result;

  const Pose3 T_map_sensor = T_map_robot + scan.T_robot_sensor;
  if (!is_horizontal(scan.T_robot_sensor, opt.horizontal_tolerance)) {
    result.status = GridInsertStatus::kNotHorizontal;
    result.message = "the scan is not horizontal within horizontalTolerance";
    return result;
  }
  if (opt.use_map_altitude && std::fabs(opt.map_altitude - T_map_sensor.z()) > 0.001) {
    result.status = GridInsertStatus::kWrongAltitude;
    result.message = "the sensor is not at mapAltitude";
    return result;
  }
  result.message = "inserted";

  // Update strengths as MRPT: the occupied update counts three times.
  const float max_certainty = opt.max_occupancy_update_certainty;
  const float max_free =
      opt.max_freeness_update_certainty == 0.0f ? max_certainty : opt.max_freeness_update_certainty;
  const float max_noecho =
      opt.max_freeness_invalid_ranges == 0.0f ? max_certainty : opt.max_freeness_invalid_ranges;
  Inserter<Cell> ins{grid, scan, opt};
  ins.obs_free = std::max<int>(1, lut.p2l(max_free));
  // MRPT computes 3·L in the cell type, which overflows int8 above p ≈ 0.9;
  // rove saturates at the type's maximum instead.
  ins.obs_occupied = std::min(Traits::kMax, 3 * std::max<int>(1, lut.p2l(max_certainty)));
  ins.obs_noecho_free = std::max<int>(1, lut.p2l(max_noecho));
  ins.thres_occupied = Traits::kMin + ins.obs_occupied;
  if (mrpt_wrap) {
    // MRPT's arithmetic in the cell type (wraps around for int8).
    ins.obs_occupied = static_cast<Cell>(3 * std::max<int>(1, lut.p2l(max_certainty)));
    ins.thres_occupied = static_cast<Cell>(Traits::kMin + ins.obs_occupied);
  }
  ins.thres_free = Traits::kMax - std::max(ins.obs_noecho_free, ins.obs_free);

  const bool sensor_upside_down = T_map_sensor.rotation()(2, 2) < 0;
  const auto n_rays = static_cast<int>(scan.size());
  const int step = opt.decimation;
  const float aperture = static_cast<float>(scan.aperture);
  const double sensor_yaw = T_map_sensor.yaw();
  const float px = static_cast<float>(T_map_sensor.x());
  const float py = static_cast<float>(T_map_sensor.y());
  const float max_dist = opt.max_distance_insertion;
  const bool invalid_as_free = opt.consider_invalid_ranges_as_free_space;
  const bool ccw = scan.right_to_left != sensor_upside_down;
  const float d_angle = ccw ? static_cast<float>(step) * aperture / static_cast<float>(n_rays)
                            : -static_cast<float>(step) * aperture / static_cast<float>(n_rays);
  // Start angle: MRPT rounds differently in its two branches.
  float angle0;
  if (!opt.widening_beams_with_distance) {
    angle0 = static_cast<float>(ccw ? sensor_yaw - 0.5f * aperture : sensor_yaw + 0.5f * aperture);
  } else {
    angle0 = ccw ? static_cast<float>(sensor_yaw) - 0.5f * aperture
                 : static_cast<float>(sensor_yaw) + 0.5f * aperture;
  }

  // The saturation summary is right if nothing changed the grid since the
  // last insertion left it right.
  Summary& summary = grid.saturation_summary();
  bool summary_ok = summary.revision == grid.revision();

  // 1) End points (meters) and the bounding box to grow the grid to.
  // Per-ray scratch, kept per thread so that a scan allocates nothing.
  thread_local InsertScratch scratch;
  scratch.resize(scan.size());
  float* const end_x = scratch.end_x.data();
  float* const end_y = scratch.end_y.data();
  std::uint8_t* const ray_ok = scratch.ray_ok.data();  // ins.valid(i), read once
  if (step > 1) {  // rays that decimation skips end at the sensor
    std::fill(scratch.end_x.begin(), scratch.end_x.end(), px);
    std::fill(scratch.end_y.begin(), scratch.end_y.end(), py);
  }
  float bx_max = -std::numeric_limits<float>::max(), bx_min = std::numeric_limits<float>::max();
  float by_max = -std::numeric_limits<float>::max(), by_min = std::numeric_limits<float>::max();
  {
    float a = angle0;
    float last_valid_range = max_dist;
    for (int i = 0; i < n_rays; i += step) {
      float ex = px, ey = py;
      const bool ok = ins.valid(static_cast<std::size_t>(i));
      ray_ok[static_cast<std::size_t>(i)] = ok;
      float rr = -1.0f;  // the ray's length, if it has one
      if (ok) {
        const float r = scan.ranges[static_cast<std::size_t>(i)];
        rr = std::min(max_dist, r);
        last_valid_range = r;
      } else if (invalid_as_free) {
        rr = std::min(max_dist, 0.5f * last_valid_range);
      }
      if (rr >= 0.0f) {
        // One place for both, so that they become one sincosf call.
        const float c = std::cos(a), sn = std::sin(a);
        ex = px + c * rr;
        ey = py + sn * rr;
      }
      end_x[static_cast<std::size_t>(i)] = ex;
      end_y[static_cast<std::size_t>(i)] = ey;
      a += d_angle;
      bx_max = std::max(bx_max, ex);
      bx_min = std::min(bx_min, ex);
      by_max = std::max(by_max, ey);
      by_min = std::min(by_min, ey);
    }
  }
  {
    const float margin = 15.0f * grid.resolution();
    bx_max = bx_max > grid.x_max() - margin ? bx_max + 2 * margin : grid.x_max();
    bx_min = bx_min < grid.x_min() + margin ? bx_min - 2 : grid.x_min();
    by_max = by_max > grid.y_max() - margin ? by_max + 2 * margin : grid.y_max();
    by_min = by_min < grid.y_min() + margin ? by_min - 2 : grid.y_min();
    const std::uint64_t before = grid.revision();
    grid.resize(bx_min, bx_max, by_min, by_max, 0.5f, true);
    if (grid.revision() != before) summary_ok = false;  // grown: blocks moved
  }
  ins.grid_data = grid.mutable_cells().data();
  grid.set_empty(false);

  if (!opt.widening_beams_with_distance) {
    // 2a) Thin rays: fixed-point DDA from the sensor cell to the end cell.
    const int cx0 = grid.x_to_idx(px);
    const int cy0 = grid.y_to_idx(py);
    const auto sx = static_cast<std::int64_t>(grid.size_x());
    const auto sy = static_cast<std::int64_t>(grid.size_y());
    // The fast path needs every visited cell inside the grid and the
    // fixed-point accumulators far from overflow.
    bool fast = grid.contains(cx0, cy0) && sx < (1 << 21) && sy < (1 << 21);
    std::vector<ThinRay>& rays = scratch.rays;
    rays.clear();
    // End cells and DDA steps of every ray, in loops without branches that
    // the compiler vectorizes (same IEEE operations as per ray: MRPT's
    // x2idx division, and steps round(|d|·2^kFrBits · (1/n)) in float).
    {
      const auto n = scan.size();
      int* const tcx = scratch.cell_x.data();
      int* const tcy = scratch.cell_y.data();
      int* const fdx = scratch.fr_dx.data();
      int* const fdy = scratch.fr_dy.data();
      int* const nst = scratch.n_steps.data();
      for (std::size_t i = 0; i < n; ++i) {
        tcx[i] = grid.x_to_idx(end_x[i]);
        tcy[i] = grid.y_to_idx(end_y[i]);
      }
      for (std::size_t i = 0; i < n; ++i) {
        const int dx = tcx[i] - cx0, dy = tcy[i] - cy0;
        const int adx = dx < 0 ? -dx : dx, ady = dy < 0 ? -dy : dy;
        const int steps = adx > ady ? adx : ady;
        nst[i] = steps;
        const float inv_n = 1.0f / static_cast<float>(steps > 0 ? steps : 1);
        // The major axis (|d| = n) gives exactly kFrOne: n·fl(1/n) is
        // within 2^-23 of 1.
        const int mx = static_cast<int>(float_round(static_cast<float>(adx * kFrOne) * inv_n));
        const int my = static_cast<int>(float_round(static_cast<float>(ady * kFrOne) * inv_n));
        fdx[i] = dx < 0 ? -mx : mx;
        fdy[i] = dy < 0 ? -my : my;
      }
    }
    for (int i = 0; i < n_rays; i += step) {
      const auto si = static_cast<std::size_t>(i);
      const bool ok = ray_ok[si] != 0;
      if (!ok && !invalid_as_free) continue;
      const int trg_cx = scratch.cell_x[si];
      const int trg_cy = scratch.cell_y[si];
      ROVE_CHECK(grid.contains(trg_cx, trg_cy));
      const int n_steps = scratch.n_steps[si];
      if (n_steps == 0) continue;
      ThinRay r;
      r.fr_dx = scratch.fr_dx[si];
      r.fr_dy = scratch.fr_dy[si];
      r.n_steps = n_steps;
      r.obs = ok ? ins.obs_free : ins.obs_noecho_free;
      if (ok && scan.ranges[si] < max_dist) {
        r.occupied = static_cast<std::ptrdiff_t>(grid.index(trg_cx, trg_cy));
        r.occupied_block = (trg_cx >> kLB) +
                           static_cast<std::ptrdiff_t>(trg_cy >> kLB) * ((sx + kB - 1) >> kLB);
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
    result.rays_inserted = rays.size();
    if (fast) {
      if (!summary_ok) rebuild_summary(ins.grid_data, sx, sy, summary);
      trace_rays_summary(ins.grid_data, sx, sy, summary.blocks.data(), summary.blocks_x, cx0,
                         cy0, rays.data(), rays.size(), ins.thres_free, ins.obs_occupied,
                         ins.thres_occupied);
      summary.revision = grid.revision();
    } else {
      for (const ThinRay& r : rays) {
        trace_free(ins.grid_data, grid.size_x(), grid.size_y(), cx0, cy0, r.fr_dx, r.fr_dy,
                   r.n_steps, r.obs, ins.thres_free);
        if (r.occupied >= 0) {
          update_occupied(ins.grid_data + r.occupied, ins.obs_occupied, ins.thres_occupied);
          if (summary_ok) summary.blocks[static_cast<std::size_t>(r.occupied_block)] = 0;
        }
      }
      // Free updates keep flagged blocks at kMax; occupied ones cleared theirs.
      if (summary_ok) summary.revision = grid.revision();
    }
    return result;
  }

  // 2b) Widening beams: fill the triangle sensor–(range − 1 cell) of each
  // beam as free, then the arc at the range as occupied.
  const float res = grid.resolution();
  const float half_beam = 0.5f * aperture / static_cast<float>(n_rays);
  float a = angle0;
  float last_valid_range = max_dist;
  const auto row_free = [&](int y, int x_from, int x_to) {
    if (y < 0 || static_cast<unsigned>(y) >= grid.size_y()) return;
    x_from = std::max(x_from, 0);
    x_to = std::min(x_to, static_cast<int>(grid.size_x()) - 1);
    for (int x = x_from; x <= x_to; ++x) ins.free_cell(x, y, ins.obs_free);
  };
  const auto fr_round = [](int d, float inv_n) {
    return static_cast<int>(float_round(static_cast<float>(d * kFrOne) * inv_n));
  };
  for (int i = 0; i < n_rays; i += step, a += d_angle) {
    const auto si = static_cast<std::size_t>(i);
    float r;
    if (ins.valid(si)) {
      last_valid_range = scan.ranges[si];
      r = std::min(max_dist, scan.ranges[si]);
    } else if (invalid_as_free) {
      r = std::min(max_dist, 0.5f * last_valid_range);
    } else {
      continue;
    }
    if (r < res) continue;
    r -= res;
    ++result.rays_inserted;
    LocalPoint p0, p1, p2, p1b;
    p0.x = px;
    p0.y = py;
    p1.x = px + std::cos(a - half_beam) * r;
    p1.y = py + std::sin(a - half_beam) * r;
    p2.x = px + std::cos(a + half_beam) * r;
    p2.y = py + std::sin(a + half_beam) * r;
    if (p2.y < p1.y) std::swap(p2, p1);
    if (p2.y < p0.y) std::swap(p2, p0);
    if (p1.y < p0.y) std::swap(p1, p0);
    for (LocalPoint* p : {&p0, &p1, &p2}) {
      p->cx = grid.x_to_idx(p->x);
      p->cy = grid.y_to_idx(p->y);
    }
    if (p0.cy == p2.cy && p0.cy == p1.cy) {
      row_free(p0.cy, std::min({p0.cx, p1.cx, p2.cx}), std::max({p0.cx, p1.cx, p2.cx}));
    } else {
      // P1b: the point of edge P0–P2 at the height of P1.
      p1b.y = p1.y;
      p1b.x = p0.x + (p1.y - p0.y) * (p2.x - p0.x) / (p2.y - p0.y);
      p1b.cx = grid.x_to_idx(p1b.x);
      p1b.cy = grid.y_to_idx(p1b.y);
      struct Edge {
        int fx = 0, fy = 0, cx = 0, cy = 0;
      } e1, e2;
      // Lower sub-triangle P0–P1–P1b, scanned row by row between two edges.
      {
        const int dx01 = p1.cx - p0.cx, dy01 = p1.cy - p0.cy, dx01b = p1b.cx - p0.cx;
        const float inv_n =
            1.0f / static_cast<float>(std::max({std::abs(dx01), std::abs(dy01), std::abs(dx01b)}) + 1);
        const int fr_dx01 = fr_round(dx01, inv_n);
        int fr_dy01 = fr_round(dy01, inv_n);
        // MRPT loops forever when this rounds to 0 (beams wider than ~1000
        // cells); one fixed-point unit keeps the scan finite.
        if (dy01 > 0 && fr_dy01 == 0) fr_dy01 = 1;
        const int fr_dx01b = fr_round(dx01b, inv_n);
        e1.cx = p0.cx;
        e1.cy = p0.cy;
        e1.fx = p0.cx * kFrOne;
        e1.fy = p0.cy * kFrOne;
        int step_x1 = 0, step_x2 = 0;
        const int step_y1 = fr_dy01;
        if (p0.cy != p1.cy) {
          e2 = e1;
          if (p1.x < p1b.x) {
            step_x1 = fr_dx01;
            step_x2 = fr_dx01b;
          } else {
            step_x1 = fr_dx01b;
            step_x2 = fr_dx01;
          }
        } else {
          e2.cx = p1.cx;
          e2.cy = p1.cy;
          e2.fx = p1.cx * kFrOne;
        }
        int last_row = -1;
        do {
          if (last_row != e1.cy) {
            last_row = e1.cy;
            row_free(e1.cy, e1.cx, e2.cx);
          }
          e1.fx += step_x1;
          e1.fy += step_y1;
          e2.fx += step_x2;
          e1.cx = e1.fx >> kFrBits;
          e1.cy = e1.fy >> kFrBits;
          e2.cx = e2.fx >> kFrBits;
        } while (e1.cy < p1.cy);
      }
      // Upper sub-triangle P1–P1b–P2.
      {
        const int dx12 = p2.cx - p1.cx, dy12 = p2.cy - p1.cy, dx1b2 = p2.cx - p1b.cx;
        const float inv_n =
            1.0f / static_cast<float>(std::max({std::abs(dx12), std::abs(dy12), std::abs(dx1b2)}) + 1);
        const int fr_dx12 = fr_round(dx12, inv_n);
        const int fr_dy12 = fr_round(dy12, inv_n);
        const int fr_dx1b2 = fr_round(dx1b2, inv_n);
        // A zero vertical step ends the loop after one row (MRPT).
        const int step_y1 = fr_dy12 != 0 ? fr_dy12 : 2 * kFrOne;
        int step_x1, step_x2;
        if (p1.x < p1b.x) {
          e1.cx = p1.cx;
          e1.cy = p1.cy;
          e2.cx = p1b.cx;
          e2.cy = p1b.cy;
          step_x1 = fr_dx12;
          step_x2 = fr_dx1b2;
        } else {
          e1.cx = p1b.cx;
          e1.cy = p1b.cy;
          e2.cx = p1.cx;
          e2.cy = p1.cy;
          step_x1 = fr_dx1b2;
          step_x2 = fr_dx12;
        }
        e1.fx = e1.cx * kFrOne;
        e1.fy = e1.cy * kFrOne;
        e2.fx = e2.cx * kFrOne;
        e2.fy = e2.cy * kFrOne;
        int last_row = -100;
        do {
          if (last_row != e1.cy) {
            last_row = e1.cy;
            row_free(e1.cy, e1.cx, e2.cx);
          }
          e1.fx += step_x1;
          e1.fy += step_y1;
          e2.fx += step_x2;
          e1.cx = e1.fx >> kFrBits;
          e1.cy = e1.fy >> kFrBits;
          e2.cx = e2.fx >> kFrBits;
        } while (e1.cy <= p2.cy);
      }
    }
    // Occupied cells along the arc P1–P2 at the measured range, for a valid
    // ray that was not cut.
    if (ins.valid(si) && scan.ranges[si] < max_dist) {
      r += res;
      LocalPoint q1, q2;
      q1.x = px + std::cos(a - half_beam) * r;
      q1.y = py + std::sin(a - half_beam) * r;
      q2.x = px + std::cos(a + half_beam) * r;
      q2.y = py + std::sin(a + half_beam) * r;
      q1.cx = grid.x_to_idx(q1.x);
      q1.cy = grid.y_to_idx(q1.y);
      q2.cx = grid.x_to_idx(q2.x);
      q2.cy = grid.y_to_idx(q2.y);
      if (q1.cx == q2.cx && q1.cy == q2.cy) {
        ins.occupied_cell(q1.cx, q1.cy);
      } else {
        const int dx = q2.cx - q1.cx, dy = q2.cy - q1.cy;
        const int n_steps = std::max(std::abs(dx), std::abs(dy)) + 1;
        const float inv_n = 1.0f / static_cast<float>(n_steps);
        const int fr_dx = fr_round(dx, inv_n);
        const int fr_dy = fr_round(dy, inv_n);
        int fx = q1.cx * kFrOne, fy = q1.cy * kFrOne;
        int cx = q1.cx, cy = q1.cy;
        for (int s = 0; s <= n_steps; ++s) {
          ins.occupied_cell(cx, cy);
          fx += fr_dx;
          fy += fr_dy;
          cx = fx >> kFrBits;
          cy = fy >> kFrBits;
        }
      }
    }
  }
  return result;
}

}  // namespace

template <GridCell Cell>
GridInsertResult insert_scan(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                             const Pose3& T_map_robot, const GridInsertionOptions& opt) {
  return insert_impl(grid, scan, T_map_robot, opt, false);
}

namespace detail {

template <GridCell Cell>
GridInsertResult insert_scan_mrpt_overflow(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                                           const Pose3& T_map_robot,
                                           const GridInsertionOptions& opt) {
  return insert_impl(grid, scan, T_map_robot, opt, true);
}

template <GridCell Cell>
ScanInformation scan_information(const OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                                 const Pose3& T_map_robot, const GridInsertionOptions& opt,
                                 int ray_step) {
  scan.check();
  opt.check();
  ROVE_CHECK_GE(ray_step, 1);
  using Traits = LogOddsTraits<Cell>;
  const auto& lut = LogOddsLut<Cell>::instance();
  ScanInformation info;
  const Pose3 T_map_sensor = T_map_robot + scan.T_robot_sensor;
  const float max_certainty = opt.max_occupancy_update_certainty;
  const float max_free =
      opt.max_freeness_update_certainty == 0.0f ? max_certainty : opt.max_freeness_update_certainty;
  const float max_noecho =
      opt.max_freeness_invalid_ranges == 0.0f ? max_certainty : opt.max_freeness_invalid_ranges;
  const int obs_free = std::max<int>(1, lut.p2l(max_free));
  const int obs_noecho = std::max<int>(1, lut.p2l(max_noecho));
  const int obs_occ = std::min(Traits::kMax, 3 * std::max<int>(1, lut.p2l(max_certainty)));
  constexpr float kMaxH = 0.69314718055994531f;
  const auto entropy = [](float p) { return (p == 0.0f || p == 1.0f) ? 0.0f : -p * std::log(p); };
  // One visit: the Bayesian update of the cell by an observation of
  // probability-of-free v, scored by the information of the result (MRPT's
  // updateCell in its information-counting mode).
  const auto visit = [&](int cx, int cy, int obs_logodds) {
    const float old = grid.contains(cx, cy) ? lut.l2p(grid.cells()[grid.index(cx, cy)]) : 0.5f;
    const float v = lut.l2p(static_cast<Cell>(obs_logodds));
    const float nv = 1.0f / (1.0f + (1.0f - v) * (1.0f - old) / (old * v));
    info.information += 1.0f - (entropy(nv) + entropy(1.0f - nv)) / kMaxH;
    ++info.cells;
  };
  const auto n_rays = static_cast<int>(scan.size());
  if (n_rays == 0) return info;
  const bool upside_down = T_map_sensor.rotation()(2, 2) < 0;
  const bool ccw = scan.right_to_left != upside_down;
  const float aperture = static_cast<float>(scan.aperture);
  const float px = static_cast<float>(T_map_sensor.x());
  const float py = static_cast<float>(T_map_sensor.y());
  const float max_dist = opt.max_distance_insertion;
  // Keep every cell index representable (a pose far from the grid has no
  // cell of the grid within reach anyway).
  const double reach = (std::fabs(px - grid.x_min()) + std::fabs(py - grid.y_min()) + max_dist) /
                       grid.resolution();
  if (!(reach < 1e9)) return info;
  const float d_angle = (ccw ? 1.0f : -1.0f) * static_cast<float>(ray_step) * aperture /
                        static_cast<float>(n_rays);
  float a = static_cast<float>(ccw ? T_map_sensor.yaw() - 0.5f * aperture
                                   : T_map_sensor.yaw() + 0.5f * aperture);
  const int cx0 = grid.x_to_idx(px), cy0 = grid.y_to_idx(py);
  float last_valid_range = max_dist;
  for (int i = 0; i < n_rays; i += ray_step, a += d_angle) {
    const auto si = static_cast<std::size_t>(i);
    const float r = scan.ranges[si];
    const bool ok = scan.valid[si] && std::isfinite(r) && r >= 0.0f;
    float rr;
    if (ok) {
      rr = std::min(max_dist, r);
      last_valid_range = r;
    } else if (opt.consider_invalid_ranges_as_free_space) {
      rr = std::min(max_dist, 0.5f * last_valid_range);
    } else {
      continue;
    }
    const int tx = grid.x_to_idx(px + std::cos(a) * rr);
    const int ty = grid.y_to_idx(py + std::sin(a) * rr);
    const int dx = tx - cx0, dy = ty - cy0;
    const int n_steps = std::max(std::abs(dx), std::abs(dy));
    if (n_steps == 0) continue;
    const float inv_n = 1.0f / static_cast<float>(n_steps);
    const int fr_dx = static_cast<int>((dx < 0 ? -1.0f : 1.0f) *
                                       float_round(static_cast<float>(std::abs(dx) * kFrOne) * inv_n));
    const int fr_dy = static_cast<int>((dy < 0 ? -1.0f : 1.0f) *
                                       float_round(static_cast<float>(std::abs(dy) * kFrOne) * inv_n));
    int fx = cx0 * kFrOne, fy = cy0 * kFrOne, cx = cx0, cy = cy0;
    for (int k = 0; k < n_steps; ++k) {
      visit(cx, cy, ok ? obs_free : obs_noecho);
      fx += fr_dx;
      fy += fr_dy;
      cx = fx >> kFrBits;
      cy = fy >> kFrBits;
    }
    if (ok && r < max_dist) visit(tx, ty, -obs_occ);
  }
  return info;
}

template GridInsertResult insert_scan_mrpt_overflow(OccupancyGridT<std::int8_t>&,
                                                    const RangeScan2D&, const Pose3&,
                                                    const GridInsertionOptions&);
template GridInsertResult insert_scan_mrpt_overflow(OccupancyGridT<std::int16_t>&,
                                                    const RangeScan2D&, const Pose3&,
                                                    const GridInsertionOptions&);
template ScanInformation scan_information(const OccupancyGridT<std::int8_t>&, const RangeScan2D&,
                                          const Pose3&, const GridInsertionOptions&, int);
template ScanInformation scan_information(const OccupancyGridT<std::int16_t>&, const RangeScan2D&,
                                          const Pose3&, const GridInsertionOptions&, int);

}  // namespace detail

template GridInsertResult insert_scan(OccupancyGridT<std::int8_t>&, const RangeScan2D&,
                                      const Pose3&, const GridInsertionOptions&);
template GridInsertResult insert_scan(OccupancyGridT<std::int16_t>&, const RangeScan2D&,
                                      const Pose3&, const GridInsertionOptions&);

}  // namespace rove
