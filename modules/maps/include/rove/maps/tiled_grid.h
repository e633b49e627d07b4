#pragma once
/// \file
/// TiledGrid: an unbounded 2D occupancy grid stored as 32 × 32-cell tiles
/// shared copy-on-write, for filters that keep one map per hypothesis (a
/// Rao-Blackwellized particle filter's particles). Copying a TiledGrid
/// copies only its table of tile pointers; a write copies the one tile it
/// touches if another grid still shares it. Memory therefore grows with
/// what the copies change, not with copies × grid.
///
/// Cells hold the same 8-bit log-odds of being FREE as OccupancyGrid
/// (grid_logodds.h, MRPT's scale): 1 = free, 0 = occupied, 0.5 = unknown,
/// a cell never written reads as unknown. Cell (cx, cy) covers
/// [cx·res, (cx+1)·res) × [cy·res, (cy+1)·res) (meters, map frame): the
/// cell boundaries of an OccupancyGrid whose limits are multiples of the
/// resolution, as MRPT snaps them. Beside its cells each tile keeps one bit
/// per cell, set when the cell is occupied (p(free) < 0.5, as the
/// likelihood field counts it), from which distances to the nearest
/// occupied cell are found without a precomputed field.
///
/// Thread-safety: thread-compatible. Two grids that share tiles may be
/// read and written from different threads (a shared tile is never written
/// in place).

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/math/se2.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {

/// One tile of a TiledGrid: 32 × 32 cells row by row and their occupied bits.
struct GridTile {
  /// log2 of the tile side, cells.
  static constexpr int kLogSide = 5;
  /// Tile side, cells.
  static constexpr int kSide = 1 << kLogSide;
  /// Cells per tile.
  static constexpr int kCells = kSide * kSide;
  /// Log-odds cells (OccupancyGrid's values), index lx + ly·kSide.
  std::array<std::int8_t, kCells> cells{};
  /// Bit lx of occupied[ly] is set when cell (lx, ly) is occupied
  /// (its value is below the value of p = 0.5).
  std::array<std::uint32_t, kSide> occupied{};
  /// Recomputes `occupied` from `cells`; true if it changed.
  bool update_occupied();
  /// Internal: the insertion that last wrote the tile (bookkeeping of
  /// insert_scan; not part of the tile's value).
  std::uint64_t stamp = 0;
};

/// What insert_scan on a TiledGrid did.
struct TiledInsertResult {
  /// The insertion's own result (status, rays).
  GridInsertResult insertion;
  /// Tiles whose cells changed.
  std::size_t tiles_changed = 0;
  /// Of those, tiles that were shared with another grid and were copied.
  std::size_t tiles_copied = 0;
};

/// An unbounded occupancy grid of copy-on-write tiles (see the file comment).
class TiledGrid {
 public:
  /// An empty grid (every cell unknown) of square cells of `resolution`
  /// meters. Precondition (InvalidArgument): resolution finite and > 0.
  explicit TiledGrid(float resolution = 0.05f);

  /// Cell side, meters.
  float resolution() const noexcept { return resolution_; }
  /// Column of world x: ⌊x / res⌋ (any finite x; the result saturates at
  /// ±2³⁰).
  int x_to_idx(double x) const noexcept { return to_idx(x); }
  /// Row of world y: ⌊y / res⌋.
  int y_to_idx(double y) const noexcept { return to_idx(y); }
  /// True until a scan was inserted or a cell set.
  bool empty() const noexcept { return empty_; }

  /// The raw log-odds value of cell (cx, cy); 0 (unknown) where never written.
  std::int8_t cell(int cx, int cy) const noexcept;
  /// Probability that cell (cx, cy) is free (0.5 where never written).
  float free_probability(int cx, int cy) const noexcept {
    return LogOddsLut<std::int8_t>::instance().l2p(cell(cx, cy));
  }
  /// True if cell (cx, cy) is occupied (p(free) < 0.5).
  bool occupied(int cx, int cy) const noexcept;
  /// Sets cell (cx, cy) (copying its tile first if it is shared).
  /// Precondition (InvalidArgument): |cx|, |cy| < 2³⁰.
  void set_cell(int cx, int cy, std::int8_t value);

  /// Squared distance, in cells², from cell (cx, cy) to the nearest
  /// occupied cell (cell centers), if it is at most `max_cells`²; else
  /// a value above max_cells². Precondition (InvalidArgument):
  /// 0 ≤ max_cells < 32.
  std::uint32_t squared_distance_to_occupied(int cx, int cy, int max_cells) const;

  /// The centers (meters) of the occupied cells whose centers lie in
  /// [x0, x1] × [y0, y1], row by row of tiles. Precondition
  /// (InvalidArgument): finite bounds, x0 ≤ x1, y0 ≤ y1.
  std::vector<Eigen::Vector2d> occupied_points(double x0, double x1, double y0, double y1) const;

  /// The cells as an OccupancyGrid covering every tile written (limits on
  /// tile boundaries, so cell (cx, cy) of this grid is the same world cell
  /// there); an empty grid gives a 1-tile grid around the origin.
  OccupancyGrid to_occupancy_grid() const;
  /// The cells of `grid` (whose limits must be multiples of the
  /// resolution, as MRPT's are) written into this grid, which must have the
  /// same resolution. Precondition (InvalidArgument): same resolution,
  /// limits on the cell lattice within 10⁻³ cell.
  void assign(const OccupancyGrid& grid);

  /// Makes the tiles over [x0, x1] × [y0, y1] (meters) addressable at once:
  /// a grid that knows its extent beforehand does not regrow its table of
  /// tile pointers (16 bytes per tile of the bounding box, no tile storage)
  /// as scans reach farther. Precondition (InvalidArgument): finite bounds,
  /// x0 ≤ x1, y0 ≤ y1, within ±2²⁹ cells.
  void reserve(double x0, double x1, double y0, double y1);
  /// Tiles with storage (written at least once).
  std::size_t tile_count() const noexcept;
  /// The storage of the tile holding cell (cx, cy), or null if never
  /// written. Two grids sharing a tile return the same pointer.
  const GridTile* tile_at(int cx, int cy) const noexcept;
  /// The distinct tiles of all `grids` (shared tiles counted once) and
  /// their bytes: the memory the maps of a particle set really hold.
  static std::size_t distinct_tiles(std::span<const TiledGrid* const> grids);

  /// Exact equality of the cells (storage sharing is not compared; a tile
  /// of unknown cells equals a missing one).
  friend bool operator==(const TiledGrid& a, const TiledGrid& b);

  /// Cell coordinates stay within ±kCellLimit (2³⁰).
  static constexpr int kCellLimit = 1 << 30;
  /// Tile coordinates of a cell coordinate.
  static int tile_of(int c) noexcept { return c >> GridTile::kLogSide; }

 private:
  friend TiledInsertResult insert_scan(TiledGrid& grid, const RangeScan2D& scan,
                                       const SE2d& T_map_robot,
                                       const GridInsertionOptions& options);
  friend class TiledRayWriter;
  int to_idx(double v) const noexcept {
    const double q = v * inv_resolution_;
    if (!(q > -kCellLimitD)) return -kCellLimit;  // also NaN
    if (q >= kCellLimitD) return kCellLimit;
    const int i = static_cast<int>(q);
    return i - (q < static_cast<double>(i) ? 1 : 0);
  }
  // The tile at tile coordinates (tx, ty), or null.
  const GridTile* tile_ptr(int tx, int ty) const noexcept {
    const auto i = static_cast<unsigned>(tx - tx0_), j = static_cast<unsigned>(ty - ty0_);
    if (i >= static_cast<unsigned>(ntx_) || j >= static_cast<unsigned>(nty_)) return nullptr;
    return tiles_[i + static_cast<std::size_t>(j) * static_cast<std::size_t>(ntx_)].get();
  }
  // squared_distance_to_occupied without its precondition check.
  inline std::uint32_t squared_distance(int cx, int cy, int max_cells) const noexcept;
  friend class TiledLikelihoodField;
  static constexpr double kCellLimitD = static_cast<double>(1 << 30);
  // Makes tiles [tx0, tx1] × [ty0, ty1] addressable (growing the table).
  void reserve_tiles(int tx0, int tx1, int ty0, int ty1);
  std::shared_ptr<GridTile>* slot(int tx, int ty) noexcept;
  const std::shared_ptr<GridTile>* slot(int tx, int ty) const noexcept;
  // The tile at (tx, ty) ready for writing: created, or copied when shared.
  GridTile& writable(int tx, int ty, bool* copied = nullptr);

  float resolution_;
  double inv_resolution_;
  // Tile table: tiles (tx0_ + i, ty0_ + j) at i + j·ntx_.
  int tx0_ = 0, ty0_ = 0, ntx_ = 0, nty_ = 0;
  std::vector<std::shared_ptr<GridTile>> tiles_;
  bool empty_ = true;
};

std::uint32_t TiledGrid::squared_distance(int cx, int cy, int max_cells) const noexcept {
  constexpr int kSide = GridTile::kSide, kMask = kSide - 1, kLog = GridTile::kLogSide;
  static constexpr std::array<std::uint32_t, kSide> kNoRows{};
  const int tx = cx >> kLog, lx = cx & kMask, ty0 = cy >> kLog;
  if (const int ly = cy & kMask;
      lx >= max_cells && lx + max_cells <= kMask && ly >= max_cells && ly + max_cells <= kMask) {
    // Every cell within max_cells rows and columns lies in the cell's own
    // tile: its rows alone give every distance ≤ max_cells exactly (and
    // any other value found is above max_cells²).
    const GridTile* tile = tile_ptr(tx, ty0);
    if (tile == nullptr) return 0xffffffffu;
    const std::uint32_t* rows = tile->occupied.data();
    std::uint32_t best = 0xffffffffu;
    for (int k = 0; k <= max_cells; ++k) {
      if (static_cast<std::uint32_t>(k * k) >= best) break;
      for (int side = 0; side < (k == 0 ? 1 : 2); ++side) {
        const std::uint32_t row = rows[static_cast<std::size_t>(side == 0 ? ly + k : ly - k)];
        // 32: none in the row on that side.
        const int dx = std::min(std::countr_zero(row >> lx), std::countl_zero(row << (kMask - lx)));
        best = std::min(best, static_cast<std::uint32_t>(dx * dx + k * k));
      }
    }
    return best;
  }
  // The occupied bits of the tiles left of, at and right of the cell's
  // column in the tile rows ty0 − 1, ty0, ty0 + 1 (rows within 31 cells
  // reach no farther; a missing tile has none), fetched when first needed.
  const std::uint32_t* near[3][3];
  bool fetched[3] = {false, false, false};
  std::uint32_t best = 0xffffffffu;
  for (int k = 0; k <= max_cells; ++k) {
    if (static_cast<std::uint32_t>(k * k) >= best) break;
    for (int side = 0; side < (k == 0 ? 1 : 2); ++side) {
      const int y = side == 0 ? cy + k : cy - k;
      const int t = (y >> kLog) - ty0 + 1;
      if (!fetched[t]) {
        for (int c = 0; c < 3; ++c) {
          const GridTile* tile = tile_ptr(tx - 1 + c, ty0 + t - 1);
          near[t][c] = tile != nullptr ? tile->occupied.data() : kNoRows.data();
        }
        fetched[t] = true;
      }
      const std::size_t ly = static_cast<std::size_t>(y & kMask);
      const std::uint64_t centre = near[t][1][ly];
      // The row's columns cx, cx + 1, ... from bit 0 up, and cx, cx − 1, ...
      // from bit 63 down, over the centre tile and its neighbour; the
      // nearest occupied cell either way (64: none within 32 columns).
      const std::uint64_t right = (centre | (std::uint64_t{near[t][2][ly]} << kSide)) >> lx;
      const std::uint64_t left = (std::uint64_t{near[t][0][ly]} | (centre << kSide)) << (kMask - lx);
      const int dx = std::min(std::countr_zero(right), std::countl_zero(left));
      best = std::min(best, static_cast<std::uint32_t>(dx * dx + k * k));
    }
  }
  return best;
}

/// Inserts `scan`, taken with the robot at T_map_robot, into `grid` with
/// MRPT's ray casting and options, giving the cells insert_scan
/// (grid_insertion.h) gives on a flat grid on the same cell lattice. Thin
/// rays are traced over the tiles directly (the same ray ends, fixed-point
/// DDA and updates, each ray's free cells then its occupied end); a tile is
/// copied only when an update changes one of its cells while another grid
/// shares it, so rays through saturated free space keep tiles shared.
/// Widening beams run insert_scan unchanged on an OccupancyGrid window of
/// the cells the scan reaches, and the tiles whose cells changed are
/// written back. Throws InvalidArgument if scan.check() or options.check()
/// fails or the scan reaches beyond ±2³⁰ cells.
TiledInsertResult insert_scan(TiledGrid& grid, const RangeScan2D& scan, const SE2d& T_map_robot,
                              const GridInsertionOptions& options = {});

/// How many of a scan's rays cross walls of a grid (rays_through_occupied).
struct RaysThroughOccupied {
  /// Returns longer than the margin: the rays looked at.
  std::size_t rays = 0;
  /// Of those, the rays that pass through an occupied cell before the margin.
  std::size_t through = 0;
  /// through / rays, 0 without rays.
  double fraction() const noexcept {
    return rays == 0 ? 0.0 : static_cast<double>(through) / static_cast<double>(rays);
  }
};

/// Where a scan contradicts a grid: of the scan's returns (the rays that
/// yield a point) with the robot at T_map_robot, the rays whose straight
/// path from the sensor to `margin` meters before the return passes through
/// an occupied cell (p(free) < 0.5; every cell the segment enters, exact
/// traversal). The scan saw free space where the grid holds a wall: a map
/// built by two passes that disagree (a loop closed wrong, a corridor
/// doubled) does this where the passes overlap; walls met at a grazing
/// angle and moving objects do it a little anywhere, hence the margin.
/// Returns shorter than the margin are not counted, nor rays spanning more
/// than 2²⁰ cells. Preconditions (InvalidArgument): scan.check(), margin
/// finite and ≥ 0, T_map_robot finite.
RaysThroughOccupied rays_through_occupied(const TiledGrid& grid, const RangeScan2D& scan,
                                          const SE2d& T_map_robot, double margin);

/// The squared distances to the nearest occupied cell already found in one
/// state of one TiledGrid, for many likelihood evaluations of nearby poses
/// against it (a particle filter's proposal): the points of neighbouring
/// poses fall in the same cells again and again. Each scan point has a
/// window of 16 × 16 cells, placed around the cell it first falls in after
/// a clear() (a direct lookup: the poses of one proposal move a point by a
/// few cells); cells outside it go to an open-addressing table of
/// 2^capacity_log2 cells, which once half full computes further cells
/// without keeping them. The values are exactly those computed without it
/// (distances beyond the search radius may be given as another value
/// beyond it).
/// clear() before using it with another grid, another state of the same
/// grid (after an insertion) or another search radius: it cannot tell; and
/// for another scan, whose points would otherwise miss the old windows.
/// Not thread-safe: one per thread.
class TiledDistanceMemo {
 public:
  /// Precondition (InvalidArgument): 4 <= capacity_log2 <= 24.
  explicit TiledDistanceMemo(int capacity_log2 = 14);
  /// Forgets every cell, in O(1).
  void clear() noexcept;
  /// Lookups answered from the points' windows, from the table, and cells
  /// computed, since construction.
  std::size_t window_hits() const noexcept { return window_hits_; }
  std::size_t hits() const noexcept { return hits_; }
  std::size_t misses() const noexcept { return misses_; }

 private:
  friend class TiledLikelihoodField;
  struct Slot {
    std::uint64_t key = 0;    // the cell (x in the high half, y in the low)
    std::uint32_t value = 0;  // its squared distance
    std::uint32_t stamp = 0;  // the slot holds a cell when this is generation_
  };
  std::vector<Slot> slots_;  // one cache line holds four
  std::uint32_t generation_ = 1;
  std::size_t size_ = 0;
  int shift_ = 0;
  std::size_t window_hits_ = 0, hits_ = 0, misses_ = 0;
  // The points' windows: point j's cells (x0 + i, y0 + k) at
  // cells_[j·256 + 16·k + i], kUnknown until computed; a window whose stamp
  // is not generation_ is placed afresh when the point is next looked up.
  static constexpr int kWindowLog = 4, kWindow = 1 << kWindowLog;
  static constexpr std::uint16_t kUnknown = 0xffff;
  struct Window {
    int x0 = 0, y0 = 0;
    std::uint32_t stamp = 0;
  };
  std::vector<Window> windows_;
  std::vector<std::uint16_t> cells_;
  // Windows for `points` points.
  void reserve_points(std::size_t points);
};

/// A scan's points ready for repeated likelihood evaluation in tiled grids:
/// the points of MRPT's likelihood-field method (mrpt_scan_points with half
/// a cell of minimum spacing, then one in LF_decimation when there are 10
/// or more), robot frame, meters.
struct TiledScanPoints {
  /// x and y of the points, robot frame, meters.
  std::vector<double> xs, ys;
  /// False when the scan is not horizontal or not at the map altitude
  /// (MRPT then gives every pose the same value, −10).
  bool usable = true;
};

/// MRPT's likelihood field (Thrun, Burgard, Fox, "Probabilistic Robotics",
/// 2005, §6.4, Table 6.3; likelihoodMethod = 4) over a TiledGrid: the
/// values of GridLikelihoodModel's LikelihoodFieldThrun for the same cells
/// (per point ln(zRandom/maxRange + zHit·exp(−d²/(2σ²))), d the distance
/// between the point's cell and the nearest occupied cell, capped at
/// LF_maxCorrsDistance), but found per point from the tiles' occupied bits
/// instead of a field precomputed over the whole grid, so a grid changed by
/// an insertion needs no refresh. Unlike the flat grid's last row and
/// column, every cell is inside. Immutable; thread-safe.
class TiledLikelihoodField {
 public:
  /// The model for grids of `resolution` meters. Throws InvalidArgument if
  /// options.check() fails, the method is not LikelihoodFieldThrun, or
  /// LF_maxCorrsDistance spans 32 cells or more.
  TiledLikelihoodField(float resolution, GridLikelihoodOptions options,
                       GridInsertionOptions insertion = {});

  /// The scan's points (see TiledScanPoints). Throws InvalidArgument if
  /// scan.check() fails.
  TiledScanPoints prepare(const RangeScan2D& scan) const;
  /// Log-likelihood of the prepared scan with the robot at T_map_robot.
  /// Precondition (InvalidArgument): grid.resolution() is this model's.
  double log_likelihood(const TiledGrid& grid, const TiledScanPoints& scan,
                        const SE2d& T_map_robot) const;
  /// As log_likelihood, but gives up once the result is sure to be below
  /// `stop_below` (the points left could not lift it there even at the
  /// best value a point can have): then returns that upper bound, which is
  /// ≥ the log-likelihood and < stop_below. The same value as
  /// log_likelihood otherwise. With LF_alternateAverageMethod (a log of a
  /// mean, no running bound) it never stops early.
  double log_likelihood_above(const TiledGrid& grid, const TiledScanPoints& scan,
                              const SE2d& T_map_robot, double stop_below) const;
  /// As above, with the distances looked up in and added to `memo`, which
  /// must hold only distances of `grid` in its present state (see
  /// TiledDistanceMemo). The same value as without it.
  double log_likelihood_above(const TiledGrid& grid, const TiledScanPoints& scan,
                              const SE2d& T_map_robot, double stop_below,
                              TiledDistanceMemo& memo) const;
  /// Fraction of the prepared points within LF_maxCorrsDistance of an
  /// occupied cell with the robot at T_map_robot (1 for no points).
  double fit(const TiledGrid& grid, const TiledScanPoints& scan, const SE2d& T_map_robot) const;
  /// The options.
  const GridLikelihoodOptions& options() const noexcept { return options_; }
  /// The search radius, cells.
  int radius_cells() const noexcept { return radius_; }

 private:
  // Sum of the points' values, or its upper bound once below stop_below.
  double point_sum(const TiledGrid& grid, const TiledScanPoints& scan, const SE2d& T_map_robot,
                   double stop_below, TiledDistanceMemo* memo) const;
  // The squared distance of cell (cx, cy), through `memo` when given
  // (point j's window, then its table).
  std::uint32_t distance(const TiledGrid& grid, int cx, int cy, TiledDistanceMemo* memo,
                         std::size_t j) const;
  float resolution_;
  GridLikelihoodOptions options_;
  GridInsertionOptions insertion_;
  int radius_ = 0;
  std::uint32_t cap_cells_ = 0;     // d² (cells²) at or above which the value is capped
  std::vector<double> value_;       // per d² < cap_cells_
  double capped_ = 0.0;
  double best_value_ = 0.0;          // the largest value a point can have (d = 0)
};

}  // namespace rove
