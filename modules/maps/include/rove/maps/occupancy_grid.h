#pragma once
/// \file
/// OccupancyGrid: a 2D probabilistic occupancy grid with integer log-odds
/// cells (MRPT's COccupancyGridMap2D storage, cell values and geometry).
///
/// Frames and units: the grid lies in the map frame's XY plane, meters. Cell
/// (cx, cy) covers [x_min + cx·res, x_min + (cx+1)·res) × [y_min + cy·res,
/// y_min + (cy+1)·res); cells are stored row by row (index cx + cy·size_x),
/// cy growing with y. Each cell holds the log-odds of being FREE (see
/// grid_logodds.h): 1 = free, 0 = occupied, 0.5 = unknown, as in MRPT.
///
/// Limits and resolution are float, as in MRPT, so that world ↔ cell
/// conversions (x2idx, idx2x) give MRPT's indices exactly.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rove/maps/grid_logodds.h"

namespace rove {

/// Derived state that scan insertion keeps beside a grid so that rays can
/// skip, without reading them, blocks of cells that are all at the free
/// limit (a free update leaves such a cell unchanged). Not part of the
/// grid's value: copied with it, ignored by ==, and trusted only while
/// `revision` equals the grid's revision() (see grid_insertion.cpp).
struct GridSaturationSummary {
  /// Per block of kBlock × kBlock cells, row by row: kFull if every cell of
  /// the block is at the free limit, else the number of ray steps that
  /// reached the block since it was last checked.
  std::vector<std::uint8_t> blocks;
  /// Blocks along x and y (partial blocks at the high edges included).
  std::uint32_t blocks_x = 0, blocks_y = 0;
  /// Grid revision at which `blocks` was last known to be right.
  std::uint64_t revision = ~std::uint64_t{0};
  /// log2 of the block side, cells.
  static constexpr int kLogBlock = 4;
  /// Block side, cells.
  static constexpr int kBlock = 1 << kLogBlock;
  /// Marker of a saturated block in `blocks`.
  static constexpr std::uint8_t kFull = 0xff;
};

/// A 2D occupancy grid of log-odds cells of type Cell (int8 or int16).
/// Thread-safety: thread-compatible (concurrent const calls are safe).
template <GridCell Cell>
class OccupancyGridT {
 public:
  using CellType = Cell;
  using Traits = LogOddsTraits<Cell>;

  /// MRPT's default grid: [−20, 20] × [−20, 20] m, 5 cm cells, all unknown.
  OccupancyGridT();
  /// A grid covering [x_min, x_max] × [y_min, y_max] (meters) with square
  /// cells of `resolution` meters, every cell set to p_free (see set_size).
  OccupancyGridT(float x_min, float x_max, float y_min, float y_max, float resolution,
                 float p_free = 0.5f);

  /// Discards the content and sets the geometry as MRPT's setSize: each limit
  /// is snapped to a multiple of the resolution, size = round(extent / res).
  /// Preconditions (InvalidArgument): all finite, resolution > 0,
  /// x_max > x_min, y_max > y_min, p_free ∈ [0, 1], and at most 2^31 cells.
  void set_size(float x_min, float x_max, float y_min, float y_max, float resolution,
                float p_free = 0.5f);

  /// Grows the grid so that it covers [x_min, x_max] × [y_min, y_max],
  /// keeping every cell's content and world position; new cells get p_free
  /// (MRPT's resizeGrid). Never shrinks. With `additional_margin`, a side
  /// that grows is pushed out by 4 m more and rounded outward to whole
  /// meters. A call that needs no growth changes nothing.
  /// Preconditions (InvalidArgument): finite limits, x_min <= x_max,
  /// y_min <= y_max, p_free ∈ [0, 1], result at most 2^31 cells.
  void resize(float x_min, float x_max, float y_min, float y_max, float p_free = 0.5f,
              bool additional_margin = true);

  /// Cells along x.
  std::uint32_t size_x() const noexcept { return size_x_; }
  /// Cells along y.
  std::uint32_t size_y() const noexcept { return size_y_; }
  /// Left edge of the grid, meters.
  float x_min() const noexcept { return x_min_; }
  /// Right edge, meters.
  float x_max() const noexcept { return x_max_; }
  /// Bottom edge, meters.
  float y_min() const noexcept { return y_min_; }
  /// Top edge, meters.
  float y_max() const noexcept { return y_max_; }
  /// Cell side, meters.
  float resolution() const noexcept { return resolution_; }
  /// Covered area, square meters.
  double area() const noexcept {
    return static_cast<double>(size_x_) * size_y_ * resolution_ * resolution_;
  }

  /// Column of world x (MRPT's x2idx: truncation toward zero of
  /// (x − x_min) / res, so it may be negative or >= size_x outside).
  int x_to_idx(double x) const noexcept { return static_cast<int>((x - x_min_) / resolution_); }
  /// Row of world y (as x_to_idx).
  int y_to_idx(double y) const noexcept { return static_cast<int>((y - y_min_) / resolution_); }
  /// x_to_idx evaluated in float, as MRPT's x2idx(float) (scan insertion).
  int x_to_idx(float x) const noexcept { return static_cast<int>((x - x_min_) / resolution_); }
  /// y_to_idx evaluated in float.
  int y_to_idx(float y) const noexcept { return static_cast<int>((y - y_min_) / resolution_); }
  /// Column of world x, or −1 / size_x when x lies left / right of the grid
  /// (same as x_to_idx inside; safe for any finite or infinite x; NaN → −1).
  int x_to_idx_clamped(double x) const noexcept { return clamp_idx((x - x_min_) / resolution_, size_x_); }
  /// Row of world y, or −1 / size_y outside (see x_to_idx_clamped).
  int y_to_idx_clamped(double y) const noexcept { return clamp_idx((y - y_min_) / resolution_, size_y_); }
  /// x of the center of column cx, meters (float, as MRPT's idx2x).
  float idx_to_x(std::size_t cx) const noexcept {
    return x_min_ + (static_cast<float>(cx) + 0.5f) * resolution_;
  }
  /// y of the center of row cy, meters.
  float idx_to_y(std::size_t cy) const noexcept {
    return y_min_ + (static_cast<float>(cy) + 0.5f) * resolution_;
  }
  /// True if (cx, cy) is a cell of the grid.
  bool contains(int cx, int cy) const noexcept {
    return static_cast<unsigned>(cx) < size_x_ && static_cast<unsigned>(cy) < size_y_;
  }

  /// Raw log-odds value of a cell. Precondition (InvalidArgument): contains.
  Cell cell(int cx, int cy) const;
  /// Sets the raw log-odds value of a cell. Precondition: contains.
  void set_cell(int cx, int cy, Cell value);
  /// All cells, row by row.
  std::span<const Cell> cells() const noexcept { return cells_; }
  /// Mutable access to all cells (counts as a modification, see revision()).
  /// Write through the span only before the next call that modifies the
  /// grid (insert_scan relies on revision() to know what changed).
  std::span<Cell> mutable_cells() noexcept {
    ++revision_;
    return cells_;
  }

  /// Probability that cell (cx, cy) is free, in [0, 1]; 0.5 outside the
  /// grid (MRPT's getCell).
  float free_probability(int cx, int cy) const noexcept {
    if (!contains(cx, cy)) return 0.5f;
    return LogOddsLut<Cell>::instance().l2p(cells_[index(cx, cy)]);
  }
  /// Probability that the cell holding world point (x, y) is free; 0.5
  /// outside (MRPT's getPos).
  float free_probability_at(double x, double y) const noexcept {
    return free_probability(x_to_idx(x), y_to_idx(y));
  }
  /// 1 − free_probability: the probability the cell is occupied.
  float occupancy(int cx, int cy) const noexcept { return 1.0f - free_probability(cx, cy); }
  /// Sets cell (cx, cy) to probability-of-free p (MRPT's setCell); a cell
  /// outside the grid is ignored. Precondition (InvalidArgument): p ∈ [0, 1].
  void set_free_probability(int cx, int cy, float p);
  /// Sets every cell to probability-of-free p. Precondition: p ∈ [0, 1].
  void fill(float p);
  /// Bayesian fusion of an observation "free with probability p" into cell
  /// (cx, cy), with saturation (MRPT's updateCell); outside cells are
  /// ignored. Precondition (InvalidArgument): p ∈ [0, 1].
  void update_cell(int cx, int cy, float p);

  /// Counter incremented by every modification; caches derived from the
  /// grid (likelihood fields, clearance maps) compare it to detect staleness.
  std::uint64_t revision() const noexcept { return revision_; }
  /// True until something is inserted or loaded (MRPT's isEmpty).
  bool empty() const noexcept { return empty_; }
  /// Marks the grid as holding data (or not).
  void set_empty(bool empty) noexcept { empty_ = empty; }

  /// The saturation summary kept by scan insertion (internal; reading or
  /// changing it does not change the cells or the revision).
  GridSaturationSummary& saturation_summary() noexcept { return summary_; }

  /// Index of cell (cx, cy) in cells(). No bounds check.
  std::size_t index(int cx, int cy) const noexcept {
    return static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * size_x_;
  }

  /// Equal geometry and cells (the revision counter and the empty flag are
  /// not compared).
  friend bool operator==(const OccupancyGridT& a, const OccupancyGridT& b) {
    return a.size_x_ == b.size_x_ && a.size_y_ == b.size_y_ && a.x_min_ == b.x_min_ &&
           a.x_max_ == b.x_max_ && a.y_min_ == b.y_min_ && a.y_max_ == b.y_max_ &&
           a.resolution_ == b.resolution_ && a.cells_ == b.cells_;
  }

  /// Replaces the whole content with given geometry and cells, exactly as
  /// stored (no snapping); used by readers. Preconditions (InvalidArgument):
  /// finite limits, resolution > 0, cells.size() == size_x·size_y.
  void assign(float x_min, float x_max, float y_min, float y_max, float resolution,
              std::uint32_t size_x, std::uint32_t size_y, std::vector<Cell> cells);

 private:
  static int clamp_idx(double q, std::uint32_t n) noexcept {
    if (!(q > -1.0)) return -1;
    if (q >= static_cast<double>(n)) return static_cast<int>(n);
    return static_cast<int>(q);
  }

  std::vector<Cell> cells_;
  std::uint32_t size_x_ = 0, size_y_ = 0;
  float x_min_ = 0, x_max_ = 0, y_min_ = 0, y_max_ = 0;
  float resolution_ = 0;
  std::uint64_t revision_ = 0;
  bool empty_ = true;
  GridSaturationSummary summary_;
};

/// The default grid: 8-bit cells (as MRPT's default build).
using OccupancyGrid = OccupancyGridT<std::int8_t>;
/// A grid with 16-bit cells (finer log-odds steps, as MRPT built with
/// OCCUPANCY_GRIDMAP_CELL_SIZE_16BITS).
using OccupancyGrid16 = OccupancyGridT<std::int16_t>;

extern template class OccupancyGridT<std::int8_t>;
extern template class OccupancyGridT<std::int16_t>;

}  // namespace rove
