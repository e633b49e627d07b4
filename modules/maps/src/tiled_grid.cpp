#include "rove/maps/tiled_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <atomic>
#include <utility>

#include "rove/core/check.h"
#include "grid_insertion_rays.h"
#include "grid_internal.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"

namespace rove {
namespace {

constexpr int kSide = GridTile::kSide;
constexpr int kLog = GridTile::kLogSide;
constexpr int kMask = kSide - 1;
// Cell coordinates stay within ±2³⁰ so tile and window arithmetic cannot
// overflow an int.
constexpr int kCellLimit = TiledGrid::kCellLimit;

// A cell is occupied when its value is below this (p(free) < 0.5), as the
// likelihood field and the distance transform of the flat grid count it.
std::int8_t occupied_below() {
  static const std::int8_t v = LogOddsLut<std::int8_t>::instance().p2l(0.5f);
  return v;
}

std::uint32_t row_occupied(const std::int8_t* row, std::int8_t below) {
  std::uint32_t bits = 0;
  for (int x = 0; x < kSide; ++x) bits |= static_cast<std::uint32_t>(row[x] < below) << x;
  return bits;
}

const std::array<std::int8_t, GridTile::kCells>& unknown_cells() {
  static const std::array<std::int8_t, GridTile::kCells> zeros{};
  return zeros;
}

}  // namespace

bool GridTile::update_occupied() {
  const std::int8_t below = occupied_below();
  bool changed = false;
  for (int y = 0; y < kSide; ++y) {
    const std::uint32_t bits = row_occupied(cells.data() + y * kSide, below);
    changed = changed || bits != occupied[static_cast<std::size_t>(y)];
    occupied[static_cast<std::size_t>(y)] = bits;
  }
  return changed;
}

TiledGrid::TiledGrid(float resolution) : resolution_(resolution) {
  ROVE_CHECK_MSG(std::isfinite(resolution) && resolution > 0.0f,
                 "a tiled grid needs a finite resolution > 0, got {}", resolution);
  inv_resolution_ = 1.0 / static_cast<double>(resolution);
}

std::shared_ptr<GridTile>* TiledGrid::slot(int tx, int ty) noexcept {
  const int i = tx - tx0_, j = ty - ty0_;
  if (static_cast<unsigned>(i) >= static_cast<unsigned>(ntx_) ||
      static_cast<unsigned>(j) >= static_cast<unsigned>(nty_)) {
    return nullptr;
  }
  return &tiles_[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * static_cast<std::size_t>(ntx_)];
}

const std::shared_ptr<GridTile>* TiledGrid::slot(int tx, int ty) const noexcept {
  return const_cast<TiledGrid*>(this)->slot(tx, ty);
}

const GridTile* TiledGrid::tile_at(int cx, int cy) const noexcept {
  const auto* s = slot(tile_of(cx), tile_of(cy));
  return s != nullptr ? s->get() : nullptr;
}

std::int8_t TiledGrid::cell(int cx, int cy) const noexcept {
  const GridTile* t = tile_at(cx, cy);
  return t != nullptr ? t->cells[static_cast<std::size_t>((cx & kMask) + (cy & kMask) * kSide)] : 0;
}

bool TiledGrid::occupied(int cx, int cy) const noexcept {
  const GridTile* t = tile_at(cx, cy);
  return t != nullptr && ((t->occupied[static_cast<std::size_t>(cy & kMask)] >> (cx & kMask)) & 1u);
}

void TiledGrid::reserve_tiles(int tx0, int tx1, int ty0, int ty1) {
  if (ntx_ > 0 && tx0 >= tx0_ && tx1 < tx0_ + ntx_ && ty0 >= ty0_ && ty1 < ty0_ + nty_) return;
  // Grow with slack so that a robot exploring step by step rarely regrows.
  constexpr int kSlack = 4;
  int nx0 = tx0 - kSlack, nx1 = tx1 + kSlack, ny0 = ty0 - kSlack, ny1 = ty1 + kSlack;
  if (ntx_ > 0) {
    nx0 = std::min(nx0, tx0_);
    nx1 = std::max(nx1, tx0_ + ntx_ - 1);
    ny0 = std::min(ny0, ty0_);
    ny1 = std::max(ny1, ty0_ + nty_ - 1);
  }
  const int ntx = nx1 - nx0 + 1, nty = ny1 - ny0 + 1;
  std::vector<std::shared_ptr<GridTile>> tiles(static_cast<std::size_t>(ntx) * static_cast<std::size_t>(nty));
  for (int j = 0; j < nty_; ++j) {
    for (int i = 0; i < ntx_; ++i) {
      auto& src = tiles_[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * static_cast<std::size_t>(ntx_)];
      const int ni = tx0_ + i - nx0, nj = ty0_ + j - ny0;
      tiles[static_cast<std::size_t>(ni) + static_cast<std::size_t>(nj) * static_cast<std::size_t>(ntx)] = std::move(src);
    }
  }
  tiles_ = std::move(tiles);
  tx0_ = nx0;
  ty0_ = ny0;
  ntx_ = ntx;
  nty_ = nty;
}

void TiledGrid::reserve(double x0, double x1, double y0, double y1) {
  ROVE_CHECK_MSG(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(y0) && std::isfinite(y1) &&
                     x0 <= x1 && y0 <= y1,
                 "reserve needs finite bounds with x0 <= x1 and y0 <= y1, got [{}, {}] x [{}, {}]", x0, x1,
                 y0, y1);
  const int cx0 = to_idx(x0), cx1 = to_idx(x1), cy0 = to_idx(y0), cy1 = to_idx(y1);
  ROVE_CHECK_MSG(cx0 > -kCellLimit / 2 && cx1 < kCellLimit / 2 && cy0 > -kCellLimit / 2 && cy1 < kCellLimit / 2,
                 "[{}, {}] x [{}, {}] m reaches beyond the tiled grid's cells", x0, x1, y0, y1);
  reserve_tiles(tile_of(cx0), tile_of(cx1), tile_of(cy0), tile_of(cy1));
}

GridTile& TiledGrid::writable(int tx, int ty, bool* copied) {
  reserve_tiles(tx, tx, ty, ty);
  std::shared_ptr<GridTile>& s = *slot(tx, ty);
  if (copied != nullptr) *copied = false;
  if (!s) {
    s = std::make_shared<GridTile>();
  } else if (s.use_count() > 1) {
    // Only a grid holding a reference can raise the count, so a count of 1
    // seen here stays 1: writing in place is then safe.
    s = std::make_shared<GridTile>(*s);
    if (copied != nullptr) *copied = true;
  }
  empty_ = false;
  return *s;
}

void TiledGrid::set_cell(int cx, int cy, std::int8_t value) {
  ROVE_CHECK_MSG(cx > -kCellLimit && cx < kCellLimit && cy > -kCellLimit && cy < kCellLimit,
                 "cell ({}, {}) is beyond the tiled grid's ±2^30 cells", cx, cy);
  GridTile& t = writable(tile_of(cx), tile_of(cy));
  const int lx = cx & kMask, ly = cy & kMask;
  t.cells[static_cast<std::size_t>(lx + ly * kSide)] = value;
  std::uint32_t& row = t.occupied[static_cast<std::size_t>(ly)];
  row = (row & ~(1u << lx)) | (static_cast<std::uint32_t>(value < occupied_below()) << lx);
}

std::uint32_t TiledGrid::squared_distance_to_occupied(int cx, int cy, int max_cells) const {
  ROVE_CHECK_MSG(max_cells >= 0 && max_cells < kSide, "max_cells = {} is outside [0, 32)", max_cells);
  return squared_distance(cx, cy, max_cells);
}

std::vector<Eigen::Vector2d> TiledGrid::occupied_points(double x0, double x1, double y0,
                                                        double y1) const {
  ROVE_CHECK_MSG(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(y0) && std::isfinite(y1) &&
                     x0 <= x1 && y0 <= y1,
                 "bad box [{}, {}] x [{}, {}]", x0, x1, y0, y1);
  std::vector<Eigen::Vector2d> out;
  const double res = resolution_;
  // Cells whose centers ((c + 0.5)·res) lie in the box.
  const int cx0 = to_idx(x0 - 0.5 * res) + 1, cx1 = to_idx(x1 - 0.5 * res);
  const int cy0 = to_idx(y0 - 0.5 * res) + 1, cy1 = to_idx(y1 - 0.5 * res);
  for (int ty = tile_of(cy0); ty <= tile_of(cy1) && cy0 <= cy1; ++ty) {
    for (int tx = tile_of(cx0); tx <= tile_of(cx1) && cx0 <= cx1; ++tx) {
      const auto* s = slot(tx, ty);
      if (s == nullptr || !*s) continue;
      for (int ly = 0; ly < kSide; ++ly) {
        const int cy = ty * kSide + ly;
        std::uint32_t bits = (*s)->occupied[static_cast<std::size_t>(ly)];
        if (cy < cy0 || cy > cy1) continue;
        while (bits != 0) {
          const int lx = std::countr_zero(bits);
          bits &= bits - 1;
          const int cx = tx * kSide + lx;
          if (cx >= cx0 && cx <= cx1) out.emplace_back((cx + 0.5) * res, (cy + 0.5) * res);
        }
      }
    }
  }
  return out;
}

std::size_t TiledGrid::tile_count() const noexcept {
  return static_cast<std::size_t>(std::count_if(tiles_.begin(), tiles_.end(),
                                                [](const auto& t) { return t != nullptr; }));
}

std::size_t TiledGrid::distinct_tiles(std::span<const TiledGrid* const> grids) {
  // An open-addressing set of the pointers in one array (a hash set's node
  // per tile cost more than the particle filter's step it is counted for).
  std::size_t n = 0;
  for (const TiledGrid* g : grids) {
    ROVE_CHECK(g != nullptr);
    n += g->tiles_.size();
  }
  int log2 = 4;
  while ((std::size_t{1} << log2) < 2 * n) ++log2;
  std::vector<const GridTile*> seen(std::size_t{1} << log2, nullptr);
  const std::size_t mask = seen.size() - 1;
  std::size_t count = 0;
  for (const TiledGrid* g : grids) {
    for (const auto& t : g->tiles_) {
      const GridTile* p = t.get();
      if (p == nullptr) continue;
      const auto key = static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(p));
      // Fibonacci hashing, then linear probing.
      std::size_t i = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> (64 - log2));
      while (seen[i] != nullptr && seen[i] != p) i = (i + 1) & mask;
      if (seen[i] == nullptr) {
        seen[i] = p;
        ++count;
      }
    }
  }
  return count;
}

OccupancyGrid TiledGrid::to_occupancy_grid() const {
  int tx_min = std::numeric_limits<int>::max(), tx_max = std::numeric_limits<int>::min();
  int ty_min = tx_min, ty_max = tx_max;
  for (int j = 0; j < nty_; ++j) {
    for (int i = 0; i < ntx_; ++i) {
      if (!tiles_[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * static_cast<std::size_t>(ntx_)]) continue;
      tx_min = std::min(tx_min, tx0_ + i);
      tx_max = std::max(tx_max, tx0_ + i);
      ty_min = std::min(ty_min, ty0_ + j);
      ty_max = std::max(ty_max, ty0_ + j);
    }
  }
  if (tx_min > tx_max) tx_min = tx_max = ty_min = ty_max = 0;
  const auto sx = static_cast<std::uint32_t>((tx_max - tx_min + 1) * kSide);
  const auto sy = static_cast<std::uint32_t>((ty_max - ty_min + 1) * kSide);
  std::vector<std::int8_t> cells(static_cast<std::size_t>(sx) * sy, 0);
  for (int ty = ty_min; ty <= ty_max; ++ty) {
    for (int tx = tx_min; tx <= tx_max; ++tx) {
      const auto* s = slot(tx, ty);
      if (s == nullptr || !*s) continue;
      for (int ly = 0; ly < kSide; ++ly) {
        const std::size_t row = static_cast<std::size_t>((ty - ty_min) * kSide + ly) * sx +
                                static_cast<std::size_t>((tx - tx_min) * kSide);
        std::memcpy(cells.data() + row, (*s)->cells.data() + ly * kSide, kSide);
      }
    }
  }
  const float res = resolution_;
  const float x_min = static_cast<float>(tx_min * kSide) * res;
  const float y_min = static_cast<float>(ty_min * kSide) * res;
  OccupancyGrid grid;
  grid.assign(x_min, x_min + static_cast<float>(sx) * res, y_min, y_min + static_cast<float>(sy) * res,
              res, sx, sy, std::move(cells));
  grid.set_empty(empty_);
  return grid;
}

void TiledGrid::assign(const OccupancyGrid& grid) {
  ROVE_CHECK_MSG(grid.resolution() == resolution_,
                 "the grid's resolution {} differs from the tiled grid's {}", grid.resolution(),
                 resolution_);
  const double ox = static_cast<double>(grid.x_min()) / resolution_;
  const double oy = static_cast<double>(grid.y_min()) / resolution_;
  ROVE_CHECK_MSG(std::abs(ox - std::round(ox)) < 1e-3 && std::abs(oy - std::round(oy)) < 1e-3 &&
                     std::abs(ox) < kCellLimit / 2 && std::abs(oy) < kCellLimit / 2,
                 "the grid's limits ({}, {}) are not on the cell lattice of resolution {}",
                 grid.x_min(), grid.y_min(), resolution_);
  const int cx0 = static_cast<int>(std::lround(ox)), cy0 = static_cast<int>(std::lround(oy));
  for (std::uint32_t y = 0; y < grid.size_y(); ++y) {
    for (std::uint32_t x = 0; x < grid.size_x(); ++x) {
      const int cx = cx0 + static_cast<int>(x), cy = cy0 + static_cast<int>(y);
      const std::int8_t v = grid.cell(static_cast<int>(x), static_cast<int>(y));
      if (v != 0 || tile_at(cx, cy) != nullptr) set_cell(cx, cy, v);
    }
  }
}

bool operator==(const TiledGrid& a, const TiledGrid& b) {
  if (a.resolution_ != b.resolution_) return false;
  const auto cells_of = [](const TiledGrid& g, int tx, int ty) -> const std::int8_t* {
    const auto* s = g.slot(tx, ty);
    return (s != nullptr && *s) ? (*s)->cells.data() : unknown_cells().data();
  };
  const int x0 = std::min(a.tx0_, b.tx0_), x1 = std::max(a.tx0_ + a.ntx_, b.tx0_ + b.ntx_);
  const int y0 = std::min(a.ty0_, b.ty0_), y1 = std::max(a.ty0_ + a.nty_, b.ty0_ + b.nty_);
  for (int ty = y0; ty < y1; ++ty) {
    for (int tx = x0; tx < x1; ++tx) {
      if (std::memcmp(cells_of(a, tx, ty), cells_of(b, tx, ty), GridTile::kCells) != 0) return false;
    }
  }
  return true;
}

namespace {

// The box (meters) the scan's rays can reach, as insert_scan casts them.
struct ReachBox {
  double x0, x1, y0, y1;
  double longest = 0.0;
};

ReachBox scan_reach(const RangeScan2D& scan, const Pose3& T_map_sensor,
                    const GridInsertionOptions& opt) {
  ReachBox b{T_map_sensor.x(), T_map_sensor.x(), T_map_sensor.y(), T_map_sensor.y()};
  const double yaw = T_map_sensor.yaw();
  const double sign = T_map_sensor.rotation()(2, 2) < 0 ? -1.0 : 1.0;
  const double max_dist = opt.max_distance_insertion;
  double last_valid = max_dist;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const float r = scan.ranges[i];
    double len = -1.0;
    if (scan.valid[i] && std::isfinite(r) && r >= 0.0f) {
      last_valid = r;
      len = std::min<double>(max_dist, r);
    } else if (opt.consider_invalid_ranges_as_free_space) {
      len = std::min(max_dist, 0.5 * last_valid);
    }
    if (len < 0.0) continue;
    const double a = scan.size() >= 2 ? yaw + sign * scan.ray_angle(i) : yaw;
    const double ex = T_map_sensor.x() + std::cos(a) * len, ey = T_map_sensor.y() + std::sin(a) * len;
    b.x0 = std::min(b.x0, ex);
    b.x1 = std::max(b.x1, ex);
    b.y0 = std::min(b.y0, ey);
    b.y1 = std::max(b.y1, ey);
    b.longest = std::max(b.longest, len);
  }
  return b;
}

}  // namespace

// Cell updates of one insertion over the tiles: reads through the shared
// tiles, copies a tile only when an update changes one of its cells, and
// keeps the tiles it wrote for their occupied bits.
class TiledRayWriter {
 public:
  explicit TiledRayWriter(TiledGrid& grid) : grid_(grid) {
    static std::atomic<std::uint64_t> counter{0};
    stamp_ = ++counter;
  }
  // Applies v → update(v) to cell (cx, cy) when it changes the value.
  template <typename Update>
  void apply(int cx, int cy, const Update& update) {
    select(cx >> kLog, cy >> kLog);
    const std::size_t i = static_cast<std::size_t>((cx & kMask) + (cy & kMask) * kSide);
    const int v = tile_ != nullptr ? tile_->cells[i] : 0;
    const int nv = update(v);
    if (nv != v) write(cx, cy, i, nv);
  }
  // apply(cx0 + (f_x >> kFrBits), cy0 + (f_y >> kFrBits), update) for
  // f = 0, fr, 2·fr, ... (n_steps cells, a ray's fixed-point DDA), tile by
  // tile: within a tile the accumulators are kept relative to its corner,
  // so the cell's offset in the tile is the accumulator's integer part.
  template <int kFrBits, typename Update>
  [[gnu::noinline]] void trace(int cx0, int cy0, int fr_dx, int fr_dy, int n_steps, const Update& update) {
    int fx = 0, fy = 0;
    int cx = cx0, cy = cy0;
    const int below = below_;
    while (n_steps > 0) {
      const int tx = cx >> kLog, ty = cy >> kLog;
      select(tx, ty);
      // The tile's corner relative to the first cell, and the accumulators
      // relative to the corner (exact: the corner is a whole cell).
      const int bx = (tx << kLog) - cx0, by = (ty << kLog) - cy0;
      int lxf = fx - (bx << kFrBits), lyf = fy - (by << kFrBits);
      // Cells written only once the tile is this insertion's own (local
      // copies: the writes through int8_t would make members reload).
      GridTile* own = own_ ? const_cast<GridTile*>(tile_) : nullptr;
      const std::int8_t* cells = tile_ != nullptr ? tile_->cells.data() : unknown_cells().data();
      do {
        const int lx = lxf >> kFrBits, ly = lyf >> kFrBits;
        if (((lx | ly) & ~kMask) != 0) break;  // the ray left the tile
        const int i = lx | (ly << kLog);
        const int v = cells[i];
        const int nv = update(v);
        if (nv != v) {
          if (own == nullptr) {
            make_own();
            own = const_cast<GridTile*>(tile_);
            cells = own->cells.data();
          }
          own->cells[static_cast<std::size_t>(i)] = static_cast<std::int8_t>(nv);
          // The cell's occupied bit follows its value.
          if ((nv < below) != (v < below)) {
            std::uint32_t& row = own->occupied[static_cast<std::size_t>(ly)];
            row = (row & ~(1u << lx)) | (static_cast<std::uint32_t>(nv < below) << lx);
          }
        }
        lxf += fr_dx;
        lyf += fr_dy;
      } while (--n_steps > 0);
      fx = lxf + (bx << kFrBits);
      fy = lyf + (by << kFrBits);
      cx = cx0 + (fx >> kFrBits);
      cy = cy0 + (fy >> kFrBits);
    }
  }
  // Fills the counts.
  void finish(TiledInsertResult& r) {
    r.tiles_changed = written_.size();
    r.tiles_copied = copied_;
  }

 private:
  // Makes tile (tx, ty) the current one.
  void select(int tx, int ty) {
    if (tx != tx_ || ty != ty_) {
      tx_ = tx;
      ty_ = ty;
      const auto* s = std::as_const(grid_).slot(tx, ty);
      tile_ = (s != nullptr) ? s->get() : nullptr;
      own_ = tile_ != nullptr && tile_->stamp == stamp_;
    }
  }
  // Writes nv to cell (cx, cy), index i of the current tile (copied or
  // created first unless this insertion owns it).
  void write(int cx, int cy, std::size_t i, int nv) {
    if (!own_) make_own();
    GridTile& t = *const_cast<GridTile*>(tile_);
    t.cells[i] = static_cast<std::int8_t>(nv);
    // The cell's occupied bit follows its value (the rest of the tile's
    // bits are unchanged: no recomputation of the tile at the end).
    std::uint32_t& row = t.occupied[static_cast<std::size_t>(cy & kMask)];
    const int lx = cx & kMask;
    row = (row & ~(1u << lx)) | (static_cast<std::uint32_t>(nv < below_) << lx);
  }

  // Makes the current tile this insertion's own (created, or copied when
  // shared).
  [[gnu::noinline]] void make_own() {
    bool copied = false;
    GridTile& t = grid_.writable(tx_, ty_, &copied);
    if (t.stamp != stamp_) {
      t.stamp = stamp_;
      written_.push_back(&t);
      copied_ += copied ? 1 : 0;
    }
    tile_ = &t;
    own_ = true;
  }

  TiledGrid& grid_;
  std::uint64_t stamp_ = 0;
  int below_ = occupied_below();  // occupied: a value below this
  int tx_ = std::numeric_limits<int>::min(), ty_ = 0;
  const GridTile* tile_ = nullptr;
  bool own_ = false;
  std::vector<GridTile*> written_;
  std::size_t copied_ = 0;
};

namespace {

// Thin rays over the tiles: insert_thin_rays' ray geometry and trace_free's
// fixed-point DDA (relative to the sensor cell, which gives the same cells
// as the flat grid's absolute accumulator), then the occupied end cell.
template <typename Real>
std::size_t insert_thin_tiled(TiledGrid& grid, const RangeScan2D& scan,
                              const GridInsertionOptions& opt, const detail::InsertStrengths& st,
                              const detail::RayDirections<Real>& dir, TiledRayWriter& writer) {
  using detail::kFrBits;
  using Traits = LogOddsTraits<std::int8_t>;
  const detail::RayEnds<Real> ends = detail::ray_ends(scan, opt, dir);
  const int cx0 = grid.x_to_idx(dir.px), cy0 = grid.y_to_idx(dir.py);
  std::size_t rays = 0;
  for (std::size_t k = 0; k < ends.x.size(); ++k) {
    const bool ok = ends.ok[k] != 0;
    if (!ok && !opt.consider_invalid_ranges_as_free_space) continue;
    const int tx = grid.x_to_idx(ends.x[k]), ty = grid.y_to_idx(ends.y[k]);
    const int dx = tx - cx0, dy = ty - cy0;
    const int n_steps = std::max(dx < 0 ? -dx : dx, dy < 0 ? -dy : dy);
    if (n_steps == 0) continue;
    ++rays;
    const Real inv_n = Real(1) / static_cast<Real>(n_steps);
    const int fr_dx = detail::fixed_step(dx, inv_n), fr_dy = detail::fixed_step(dy, inv_n);
    const int obs = ok ? st.obs_free : st.obs_noecho_free;
    const int thres = st.thres_free;
    const auto free = [obs, thres](int v) { return v < thres ? v + obs : Traits::kMax; };
    writer.trace<kFrBits>(cx0, cy0, fr_dx, fr_dy, n_steps, free);
    const std::size_t i = k * static_cast<std::size_t>(dir.step);
    if (ok && scan.ranges[i] < opt.max_distance_insertion) {
      const int obs_occ = st.obs_occupied, thres_occ = st.thres_occupied;
      writer.apply(tx, ty, [&](int v) { return v > thres_occ ? v - obs_occ : Traits::kMin; });
    }
  }
  return rays;
}

}  // namespace

TiledInsertResult insert_scan(TiledGrid& grid, const RangeScan2D& scan, const SE2d& T_map_robot,
                              const GridInsertionOptions& opt) {
  scan.check();
  opt.check();
  TiledInsertResult result;
  const Eigen::Vector2d& t = T_map_robot.translation();
  const Pose3 pose(Pose2(t.x(), t.y(), T_map_robot.angle()));
  const Pose3 T_map_sensor = pose + scan.T_robot_sensor;
  const float res = grid.resolution();
  if (!is_horizontal(scan.T_robot_sensor, opt.horizontal_tolerance) ||
      (opt.use_map_altitude && std::fabs(opt.map_altitude - T_map_sensor.z()) > 0.001)) {
    // Declined: the flat insertion says why, on a grid it leaves unchanged.
    OccupancyGrid tiny(0.0f, res, 0.0f, res, res);
    result.insertion = insert_scan(tiny, scan, pose, opt);
    return result;
  }
  if (!opt.widening_beams_with_distance) {
    const ReachBox box = scan_reach(scan, T_map_sensor, opt);
    ROVE_CHECK_MSG(std::abs(box.x0) < kCellLimit / 4 * res && std::abs(box.x1) < kCellLimit / 4 * res &&
                       std::abs(box.y0) < kCellLimit / 4 * res && std::abs(box.y1) < kCellLimit / 4 * res,
                   "the scan reaches beyond the tiled grid's cells (box [{}, {}] x [{}, {}] m)",
                   box.x0, box.x1, box.y0, box.y1);
    const bool mrpt = opt.arithmetic == Arithmetic::Mrpt;
    const detail::InsertStrengths st = detail::insert_strengths<std::int8_t>(opt, mrpt);
    TiledRayWriter writer(grid);
    result.insertion.rays_inserted =
        mrpt ? insert_thin_tiled(grid, scan, opt, st, detail::mrpt_ray_directions(scan, T_map_sensor, opt.decimation, false), writer)
             : insert_thin_tiled(grid, scan, opt, st, detail::ray_directions(scan, T_map_sensor, opt.decimation), writer);
    result.insertion.message = "inserted";
    writer.finish(result);
    grid.empty_ = false;
    return result;
  }
  // The window: every cell the rays reach, with the 15-cell margin within
  // which the flat insertion would grow its grid, on tile boundaries.
  const ReachBox box = scan_reach(scan, T_map_sensor, opt);
  const double beam = scan.size() >= 2 ? scan.aperture / static_cast<double>(scan.size() - 1) : scan.aperture;
  const int margin = 18 + static_cast<int>(std::ceil(box.longest * beam / res));
  const int cx0 = grid.x_to_idx(box.x0) - margin, cx1 = grid.x_to_idx(box.x1) + margin;
  const int cy0 = grid.y_to_idx(box.y0) - margin, cy1 = grid.y_to_idx(box.y1) + margin;
  ROVE_CHECK_MSG(cx0 > -kCellLimit / 2 && cx1 < kCellLimit / 2 && cy0 > -kCellLimit / 2 &&
                     cy1 < kCellLimit / 2,
                 "the scan reaches beyond the tiled grid's cells (box [{}, {}] x [{}, {}] m)",
                 box.x0, box.x1, box.y0, box.y1);
  const int tx0 = TiledGrid::tile_of(cx0), tx1 = TiledGrid::tile_of(cx1);
  const int ty0 = TiledGrid::tile_of(cy0), ty1 = TiledGrid::tile_of(cy1);
  const auto sx = static_cast<std::uint32_t>((tx1 - tx0 + 1) * kSide);
  const auto sy = static_cast<std::uint32_t>((ty1 - ty0 + 1) * kSide);
  std::vector<std::int8_t> cells(static_cast<std::size_t>(sx) * sy, 0);
  const auto block = [&](int tx, int ty, int ly) {
    return cells.data() + static_cast<std::size_t>((ty - ty0) * kSide + ly) * sx +
           static_cast<std::size_t>((tx - tx0) * kSide);
  };
  for (int ty = ty0; ty <= ty1; ++ty) {
    for (int tx = tx0; tx <= tx1; ++tx) {
      const auto* s = std::as_const(grid).slot(tx, ty);
      if (s == nullptr || !*s) continue;
      for (int ly = 0; ly < kSide; ++ly) std::memcpy(block(tx, ty, ly), (*s)->cells.data() + ly * kSide, kSide);
    }
  }
  const float x_min = static_cast<float>(tx0 * kSide) * res;
  const float y_min = static_cast<float>(ty0 * kSide) * res;
  OccupancyGrid window;
  window.assign(x_min, x_min + static_cast<float>(sx) * res, y_min, y_min + static_cast<float>(sy) * res,
                res, sx, sy, std::move(cells));
  result.insertion = insert_scan(window, scan, pose, opt);
  ROVE_CHECK_MSG(window.size_x() == sx && window.size_y() == sy && window.x_min() == x_min &&
                     window.y_min() == y_min,
                 "the insertion window grew ({} x {} cells to {} x {})", sx, sy, window.size_x(),
                 window.size_y());
  // Write back the tiles whose cells changed.
  const std::int8_t* data = window.cells().data();
  for (int ty = ty0; ty <= ty1; ++ty) {
    for (int tx = tx0; tx <= tx1; ++tx) {
      const auto* s = std::as_const(grid).slot(tx, ty);
      const std::int8_t* old = (s != nullptr && *s) ? (*s)->cells.data() : unknown_cells().data();
      const auto row_of = [&](int ly) {
        return data + static_cast<std::size_t>((ty - ty0) * kSide + ly) * sx +
               static_cast<std::size_t>((tx - tx0) * kSide);
      };
      bool same = true;
      for (int ly = 0; ly < kSide && same; ++ly) same = std::memcmp(row_of(ly), old + ly * kSide, kSide) == 0;
      if (same) continue;
      bool copied = false;
      GridTile& tile = grid.writable(tx, ty, &copied);
      for (int ly = 0; ly < kSide; ++ly) std::memcpy(tile.cells.data() + ly * kSide, row_of(ly), kSide);
      tile.update_occupied();
      ++result.tiles_changed;
      result.tiles_copied += copied ? 1 : 0;
    }
  }
  grid.empty_ = false;
  return result;
}

TiledLikelihoodField::TiledLikelihoodField(float resolution, GridLikelihoodOptions options,
                                           GridInsertionOptions insertion)
    : resolution_(resolution), options_(std::move(options)), insertion_(std::move(insertion)) {
  options_.check();
  insertion_.check();
  ROVE_CHECK_MSG(std::isfinite(resolution) && resolution > 0.0f, "resolution must be > 0, got {}",
                 resolution);
  ROVE_CHECK_MSG(options_.method == GridLikelihoodMethod::LikelihoodFieldThrun,
                 "the tiled likelihood field implements likelihoodMethod = 4 "
                 "(lmLikelihoodField_Thrun) only, got {}",
                 static_cast<int>(options_.method));
  // GridLikelihoodModel's per-cell values (MRPT's float/double mix), per
  // squared distance in cells: d² in units of (cell/10)², capped at the
  // search radius, then zRandom/maxRange + zHit·exp(Q·d²) in float.
  const GridLikelihoodOptions& o = options_;
  const float z_random_term = o.lf_z_random / o.lf_max_range;
  const float q = -0.5f / (o.lf_std_hit * o.lf_std_hit);
  const double max_corr_sq = static_cast<double>(o.lf_max_corrs_distance) * o.lf_max_corrs_distance;
  const double res = resolution;
  const double units = 100.0 / (res * res);
  const auto cap = static_cast<std::uint64_t>(std::lrint(max_corr_sq * units));
  const std::uint64_t cap_cells = (cap + 99) / 100;  // first d² with d²·100 >= cap
  std::uint64_t radius = 0;
  while ((radius + 1) * (radius + 1) < cap_cells) ++radius;
  ROVE_CHECK_MSG(radius < static_cast<std::uint64_t>(kSide),
                 "LF_maxCorrsDistance = {} m spans {} cells of {} m; the tiled likelihood field "
                 "searches at most 31",
                 o.lf_max_corrs_distance, radius, resolution);
  radius_ = static_cast<int>(radius);
  cap_cells_ = static_cast<std::uint32_t>(cap_cells);
  const bool product = !o.lf_alternate_average_method;
  const auto value_of = [&](std::uint64_t units_int) {
    float dist = static_cast<float>(static_cast<double>(units_int) / units);
    if (o.lf_use_square_dist) dist *= dist;
    const float lik = z_random_term + o.lf_z_hit * std::exp(q * dist);
    return product ? std::log(static_cast<double>(lik)) : static_cast<double>(lik);
  };
  value_.resize(cap_cells_);
  for (std::uint32_t d2 = 0; d2 < cap_cells_; ++d2) value_[d2] = value_of(std::uint64_t{d2} * 100);
  capped_ = value_of(cap);
  best_value_ = capped_;
  for (const double v : value_) best_value_ = std::max(best_value_, v);
}

TiledScanPoints TiledLikelihoodField::prepare(const RangeScan2D& scan) const {
  scan.check();
  TiledScanPoints p;
  if (!is_horizontal(scan.T_robot_sensor, insertion_.horizontal_tolerance) ||
      (insertion_.use_map_altitude &&
       std::fabs(insertion_.map_altitude - scan.T_robot_sensor.z()) > 0.01)) {
    p.usable = false;
    return p;
  }
  std::vector<float> xs, ys;
  mrpt_scan_points(scan, resolution_ * 0.5f, xs, ys);
  const std::size_t step = xs.size() < 10 ? 1 : options_.lf_decimation;
  for (std::size_t j = 0; j < xs.size(); j += step) {
    p.xs.push_back(xs[j]);
    p.ys.push_back(ys[j]);
  }
  return p;
}

TiledDistanceMemo::TiledDistanceMemo(int capacity_log2) {
  ROVE_CHECK_MSG(capacity_log2 >= 4 && capacity_log2 <= 24, "capacity_log2 = {} is outside [4, 24]",
                 capacity_log2);
  const std::size_t n = std::size_t{1} << capacity_log2;
  slots_.assign(n, Slot{});
  shift_ = 64 - capacity_log2;
}

void TiledDistanceMemo::clear() noexcept {
  size_ = 0;
  if (++generation_ == 0) {  // after 2^32 clears: forget the stamps for real
    for (Slot& slot : slots_) slot.stamp = 0;
    for (Window& w : windows_) w.stamp = 0;
    generation_ = 1;
  }
}

void TiledDistanceMemo::reserve_points(std::size_t points) {
  if (points <= windows_.size()) return;
  windows_.resize(points);  // stamp 0: never current
  cells_.resize(points << (2 * kWindowLog));
}

[[gnu::noinline]] std::uint32_t TiledLikelihoodField::distance(const TiledGrid& grid, int cx, int cy,
                                                               TiledDistanceMemo* memo,
                                                               std::size_t j) const {
  if (memo == nullptr) return grid.squared_distance(cx, cy, radius_);
  TiledDistanceMemo& m = *memo;
  constexpr int kW = TiledDistanceMemo::kWindow, kLog = TiledDistanceMemo::kWindowLog;
  TiledDistanceMemo::Window& w = m.windows_[j];
  std::uint16_t* cells = m.cells_.data() + (j << (2 * kLog));
  if (w.stamp != m.generation_) {
    // Cell coordinates stay within ±2^30: these do not overflow.
    w = {cx - kW / 2, cy - kW / 2, m.generation_};
    std::fill_n(cells, kW * kW, TiledDistanceMemo::kUnknown);
  }
  // Offsets in the window, modulo 2^32 (no signed overflow however far apart).
  const unsigned ux = static_cast<unsigned>(cx) - static_cast<unsigned>(w.x0);
  const unsigned uy = static_cast<unsigned>(cy) - static_cast<unsigned>(w.y0);
  if ((ux | uy) < static_cast<unsigned>(kW)) {
    std::uint16_t& e = cells[(uy << kLog) | ux];
    if (e != TiledDistanceMemo::kUnknown) {
      ++m.window_hits_;
      return e;
    }
    ++m.misses_;
    // Beyond the radius (radius < 32: d² ≤ 961 within it) any value above
    // it says so; kUnknown − 1 fits.
    const std::uint32_t d2 = std::min<std::uint32_t>(grid.squared_distance(cx, cy, radius_),
                                                     TiledDistanceMemo::kUnknown - 1u);
    e = static_cast<std::uint16_t>(d2);
    return d2;
  }
  const std::uint64_t key = (std::uint64_t{static_cast<std::uint32_t>(cx)} << 32) |
                            std::uint64_t{static_cast<std::uint32_t>(cy)};
  // Fibonacci hashing, then linear probing.
  const std::size_t mask = m.slots_.size() - 1;
  std::size_t i = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> m.shift_);
  for (;; i = (i + 1) & mask) {
    const TiledDistanceMemo::Slot& slot = m.slots_[i];
    if (slot.stamp != m.generation_) break;
    if (slot.key == key) {
      ++m.hits_;
      return slot.value;
    }
  }
  ++m.misses_;
  const std::uint32_t d2 = grid.squared_distance(cx, cy, radius_);
  if (2 * (m.size_ + 1) <= m.slots_.size()) {
    m.slots_[i] = {key, d2, m.generation_};
    ++m.size_;
  }
  return d2;
}

double TiledLikelihoodField::point_sum(const TiledGrid& grid, const TiledScanPoints& scan,
                                       const SE2d& T_map_robot, double stop_below,
                                       TiledDistanceMemo* memo) const {
  const std::size_t n = scan.xs.size();
  if (memo != nullptr) memo->reserve_points(n);
  const Eigen::Vector2d cs = T_map_robot.rotation().unit_complex();
  const double c = cs.x(), s = cs.y();
  const double tx = T_map_robot.translation().x(), ty = T_map_robot.translation().y();
  const double* xs = scan.xs.data();
  const double* ys = scan.ys.data();
  const double* value = value_.data();
  // The memo's windows, read here without a call (distance() below fills
  // them and answers the rest); kept in locals, as is the hit count, so
  // that the loop does not reload them.
  constexpr int kW = TiledDistanceMemo::kWindow, kWLog = TiledDistanceMemo::kWindowLog;
  const TiledDistanceMemo::Window* windows = memo != nullptr ? memo->windows_.data() : nullptr;
  const std::uint16_t* window_cells = memo != nullptr ? memo->cells_.data() : nullptr;
  const std::uint32_t generation = memo != nullptr ? memo->generation_ : 0;
  std::size_t window_hits = 0;
  double sum = 0.0;
  std::size_t j = 0;
  for (; j < n; ++j) {
    const double wx = tx + xs[j] * c - ys[j] * s;
    const double wy = ty + xs[j] * s + ys[j] * c;
    const int cx = grid.to_idx(wx), cy = grid.to_idx(wy);
    std::uint32_t d2 = TiledDistanceMemo::kUnknown;
    if (windows != nullptr) {
      const TiledDistanceMemo::Window& w = windows[j];
      const unsigned ux = static_cast<unsigned>(cx) - static_cast<unsigned>(w.x0);
      const unsigned uy = static_cast<unsigned>(cy) - static_cast<unsigned>(w.y0);
      if (w.stamp == generation && (ux | uy) < static_cast<unsigned>(kW)) {
        d2 = window_cells[(j << (2 * kWLog)) | (uy << kWLog) | ux];
        window_hits += d2 != TiledDistanceMemo::kUnknown ? 1 : 0;
      }
    }
    if (d2 == TiledDistanceMemo::kUnknown) d2 = distance(grid, cx, cy, memo, j);
    sum += d2 < cap_cells_ ? value[d2] : capped_;
    // Checked every 8 points: the bound costs a multiplication.
    if ((j & 7u) == 7u) {
      const double bound = sum + static_cast<double>(n - 1 - j) * best_value_;
      if (bound < stop_below) {
        sum = bound;
        break;
      }
    }
  }
  if (memo != nullptr) memo->window_hits_ += window_hits;
  return sum;
}

double TiledLikelihoodField::log_likelihood(const TiledGrid& grid, const TiledScanPoints& scan,
                                            const SE2d& T_map_robot) const {
  ROVE_CHECK_MSG(grid.resolution() == resolution_,
                 "the grid's resolution {} is not the likelihood field's {}", grid.resolution(),
                 resolution_);
  if (!scan.usable) return -10.0;
  const std::size_t n = scan.xs.size();
  if (n == 0) return -100.0;
  const double sum =
      point_sum(grid, scan, T_map_robot, -std::numeric_limits<double>::infinity(), nullptr);
  return options_.lf_alternate_average_method ? std::log(sum / static_cast<double>(n)) : sum;
}

double TiledLikelihoodField::log_likelihood_above(const TiledGrid& grid, const TiledScanPoints& scan,
                                                  const SE2d& T_map_robot, double stop_below) const {
  if (options_.lf_alternate_average_method || !scan.usable || scan.xs.empty()) {
    return log_likelihood(grid, scan, T_map_robot);
  }
  ROVE_CHECK_MSG(grid.resolution() == resolution_,
                 "the grid's resolution {} is not the likelihood field's {}", grid.resolution(),
                 resolution_);
  return point_sum(grid, scan, T_map_robot, stop_below, nullptr);
}

double TiledLikelihoodField::log_likelihood_above(const TiledGrid& grid, const TiledScanPoints& scan,
                                                  const SE2d& T_map_robot, double stop_below,
                                                  TiledDistanceMemo& memo) const {
  if (options_.lf_alternate_average_method || !scan.usable || scan.xs.empty()) {
    return log_likelihood(grid, scan, T_map_robot);
  }
  ROVE_CHECK_MSG(grid.resolution() == resolution_,
                 "the grid's resolution {} is not the likelihood field's {}", grid.resolution(),
                 resolution_);
  return point_sum(grid, scan, T_map_robot, stop_below, &memo);
}

double TiledLikelihoodField::fit(const TiledGrid& grid, const TiledScanPoints& scan,
                                 const SE2d& T_map_robot) const {
  const std::size_t n = scan.xs.size();
  if (!scan.usable || n == 0) return 1.0;
  const Eigen::Vector2d cs = T_map_robot.rotation().unit_complex();
  const Eigen::Vector2d& t = T_map_robot.translation();
  std::size_t near = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const double wx = t.x() + scan.xs[j] * cs.x() - scan.ys[j] * cs.y();
    const double wy = t.y() + scan.xs[j] * cs.y() + scan.ys[j] * cs.x();
    near += grid.squared_distance(grid.to_idx(wx), grid.to_idx(wy), radius_) <
                    cap_cells_
                ? 1
                : 0;
  }
  return static_cast<double>(near) / static_cast<double>(n);
}

RaysThroughOccupied rays_through_occupied(const TiledGrid& grid, const RangeScan2D& scan,
                                          const SE2d& T_map_robot, double margin) {
  scan.check();
  ROVE_CHECK_MSG(std::isfinite(margin) && margin >= 0.0, "margin must be finite and >= 0, got {}", margin);
  ROVE_CHECK_MSG(T_map_robot.translation().allFinite() && std::isfinite(T_map_robot.angle()),
                 "the robot pose is not finite");
  RaysThroughOccupied out;
  const double inv = 1.0 / static_cast<double>(grid.resolution());
  const Eigen::Vector2d origin =
      T_map_robot * Eigen::Vector2d(scan.T_robot_sensor.x(), scan.T_robot_sensor.y());
  const double ux = origin.x() * inv, uy = origin.y() * inv;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kMaxCells = 1 << 20;
  for (const Eigen::Vector2d& p : scan.points_2d(ScanFrame::Robot)) {
    const Eigen::Vector2d d = T_map_robot * p - origin;
    const double length = d.norm();
    if (!(length > margin)) continue;
    // The segment's end, `margin` before the return, in cell units.
    const double k = (length - margin) / length;
    const double vx = ux + d.x() * k * inv, vy = uy + d.y() * k * inv;
    if (!(std::fabs(ux) < kMaxCells * 512 && std::fabs(uy) < kMaxCells * 512 &&
          std::fabs(vx - ux) + std::fabs(vy - uy) < kMaxCells)) {
      continue;
    }
    ++out.rays;
    // Amanatides & Woo's traversal: from the origin's cell to the end's, one
    // cell boundary at a time (t: the fraction of the segment done).
    auto cx = static_cast<std::int64_t>(std::floor(ux)), cy = static_cast<std::int64_t>(std::floor(uy));
    const auto ex = static_cast<std::int64_t>(std::floor(vx)), ey = static_cast<std::int64_t>(std::floor(vy));
    const double dx = vx - ux, dy = vy - uy;
    const std::int64_t sx = ex > cx ? 1 : -1, sy = ey > cy ? 1 : -1;
    const double tdx = dx != 0.0 ? std::fabs(1.0 / dx) : kInf, tdy = dy != 0.0 ? std::fabs(1.0 / dy) : kInf;
    double tx = ex == cx ? kInf : (sx > 0 ? (static_cast<double>(cx) + 1.0 - ux) : (ux - static_cast<double>(cx))) * tdx;
    double ty = ey == cy ? kInf : (sy > 0 ? (static_cast<double>(cy) + 1.0 - uy) : (uy - static_cast<double>(cy))) * tdy;
    std::int64_t steps = std::abs(ex - cx) + std::abs(ey - cy);
    // The tile under the ray, looked up again only when the ray leaves it.
    const GridTile* tile = nullptr;
    std::int64_t tile_x = 0, tile_y = 0;
    bool have_tile = false;
    const auto occupied = [&](std::int64_t x, std::int64_t y) {
      const std::int64_t tx = x >> GridTile::kLogSide, ty = y >> GridTile::kLogSide;
      if (!have_tile || tx != tile_x || ty != tile_y) {
        tile = grid.tile_at(static_cast<int>(x), static_cast<int>(y));
        tile_x = tx;
        tile_y = ty;
        have_tile = true;
      }
      return tile != nullptr && ((tile->occupied[static_cast<std::size_t>(y & kMask)] >> (x & kMask)) & 1u) != 0;
    };
    bool through = occupied(cx, cy);
    while (!through && steps > 0) {
      // Each axis stops at its end cell, whatever the rounding of t says.
      if ((tx < ty && cx != ex) || cy == ey) {
        cx += sx;
        tx += tdx;
      } else {
        cy += sy;
        ty += tdy;
      }
      --steps;
      through = occupied(cx, cy);
    }
    out.through += through ? 1 : 0;
  }
  return out;
}

}  // namespace rove
