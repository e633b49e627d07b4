#pragma once
/// \file
/// ProbabilityGrid: the occupancy grid of one submap of lidar SLAM
/// (lidar_slam.h). Each cell holds the probability that it is occupied,
/// quantized to 15 bits over [kMinProbability, kMaxProbability], or
/// "unknown" (read as kMinProbability by the matchers). Scans are inserted
/// by GridScanInserter with the odds update of Hess et al., "Real-Time Loop
/// Closure in 2D LIDAR SLAM" (ICRA 2016), Sec. IV-B, Eqs. (2)–(3):
/// odds(p) = p / (1 − p), M_new = clamp(odds⁻¹(odds(M_old)·odds(p_hit|miss))),
/// an unknown cell taking p_hit or p_miss itself, every cell updated at
/// most once per scan (a hit wins over a miss).
///
/// Geometry: square cells of `resolution` meters on a lattice fixed in the
/// grid's frame: lattice cell (i, j) covers [i·r, (i+1)·r) × [j·r, (j+1)·r).
/// The grid stores the lattice cells [offset.x, offset.x + size_x) ×
/// [offset.y, offset.y + size_y) row by row (x fastest) and grows, keeping
/// every cell where it is, when a scan reaches outside.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"

namespace rove {

/// A growable 2D grid of occupancy probabilities. See the file comment.
/// Thread-safety: thread-compatible (concurrent const calls are safe).
class ProbabilityGrid {
 public:
  /// The probability an unknown cell reads as, and the lowest a cell holds.
  static constexpr float kMinProbability = 0.1f;
  /// The highest probability a cell holds.
  static constexpr float kMaxProbability = 0.9f;
  /// The stored value of an unknown cell.
  static constexpr std::uint16_t kUnknown = 0;
  /// The largest stored value (kMaxProbability); kMinProbability is 1.
  static constexpr std::uint16_t kMaxValue = 32767;
  /// Bit set on a cell while a scan insertion has updated it (internal to
  /// GridScanInserter; never set between insertions).
  static constexpr std::uint16_t kUpdateMarker = 32768;

  /// An empty grid (no cells) of square cells of `resolution` meters.
  /// Precondition (InvalidArgument): resolution finite and > 0.
  explicit ProbabilityGrid(double resolution);

  /// Cell side, meters.
  double resolution() const noexcept { return resolution_; }
  /// Cells along x.
  int size_x() const noexcept { return size_x_; }
  /// Cells along y.
  int size_y() const noexcept { return size_y_; }
  /// Lattice index of the stored cell (0, 0).
  const Eigen::Vector2i& offset() const noexcept { return offset_; }
  /// Lower-left corner of the stored cell (0, 0), meters.
  Eigen::Vector2d min_corner() const { return offset_.cast<double>() * resolution_; }
  /// True if (cx, cy) is a stored cell.
  bool contains(int cx, int cy) const noexcept {
    return static_cast<unsigned>(cx) < static_cast<unsigned>(size_x_) &&
           static_cast<unsigned>(cy) < static_cast<unsigned>(size_y_);
  }
  /// The stored cell holding point p (meters; may lie outside the stored
  /// cells). Precondition: p finite and within ±2^30 cells.
  Eigen::Vector2i cell_of(const Eigen::Vector2d& p) const;
  /// Center of stored cell (cx, cy), meters.
  Eigen::Vector2d cell_center(int cx, int cy) const {
    return {(offset_.x() + cx + 0.5) * resolution_, (offset_.y() + cy + 0.5) * resolution_};
  }
  /// Stored value of a cell; kUnknown outside the grid.
  std::uint16_t value(int cx, int cy) const noexcept {
    return contains(cx, cy) ? cells_[index(cx, cy)] : kUnknown;
  }
  /// Probability that a cell is occupied; kMinProbability when unknown or
  /// outside the grid.
  float probability(int cx, int cy) const noexcept { return value_to_probability(value(cx, cy)); }
  /// True if the cell is stored and not unknown.
  bool known(int cx, int cy) const noexcept { return value(cx, cy) != kUnknown; }
  /// Sets a cell to probability p (clamped to [kMinProbability,
  /// kMaxProbability]). Preconditions (InvalidArgument): contains(cx, cy),
  /// p finite.
  void set_probability(int cx, int cy, float p);
  /// Grows the grid (never shrinks) so that the box [lo, hi] (meters) is
  /// covered, with at least `margin` meters to spare on each side that
  /// grows; new cells are unknown. Preconditions (InvalidArgument): finite,
  /// lo <= hi, margin >= 0, at most 2^28 cells after growing.
  void grow_to_include(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double margin = 2.0);
  /// The stored values, row by row.
  std::span<const std::uint16_t> values() const noexcept { return cells_; }
  /// Mutable stored values (GridScanInserter).
  std::span<std::uint16_t> mutable_values() noexcept { return cells_; }
  /// Index of stored cell (cx, cy) in values(). No bounds check.
  std::size_t index(int cx, int cy) const noexcept {
    return static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * static_cast<std::size_t>(size_x_);
  }
  /// Number of known cells.
  std::size_t known_cells() const noexcept;
  /// Bytes held by the cells.
  std::size_t memory_bytes() const noexcept { return cells_.capacity() * sizeof(std::uint16_t); }

  /// Probability of a stored value (the update marker ignored): kUnknown
  /// gives kMinProbability.
  static float value_to_probability(std::uint16_t value) noexcept {
    const unsigned v = value & (kUpdateMarker - 1u);
    return v == 0 ? kMinProbability
                  : kMinProbability + static_cast<float>(v - 1u) *
                                          ((kMaxProbability - kMinProbability) / (kMaxValue - 1));
  }
  /// The stored value nearest to probability p (clamped to the range).
  /// Precondition (InvalidArgument): p finite.
  static std::uint16_t probability_to_value(float p);

 private:
  double resolution_;
  int size_x_ = 0, size_y_ = 0;
  Eigen::Vector2i offset_ = Eigen::Vector2i::Zero();
  std::vector<std::uint16_t> cells_;
};

/// How scans update a ProbabilityGrid (Hess et al. 2016, Sec. IV-B).
struct GridInsertionOdds {
  /// (hit_probability) probability a hit cell is occupied, in (0.5, 1).
  /// Default 0.55.
  double hit_probability = 0.55;
  /// (miss_probability) probability a cell a ray crossed is occupied, in
  /// (0, 0.5). Default 0.49.
  double miss_probability = 0.49;
  /// (insert_free_space) apply the miss update along the rays. Default true.
  bool insert_free_space = true;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The keys above from `section` over the defaults. Throws ConfigError
  /// naming file, section and key for a malformed or out-of-range value.
  static GridInsertionOdds from_config(const ConfigSection& section);
};

/// Inserts scans into probability grids. Holds the update tables of one
/// GridInsertionOdds. Thread-safety: immutable after construction.
class GridScanInserter {
 public:
  /// Precondition (InvalidArgument): odds.check() passes.
  explicit GridScanInserter(const GridInsertionOdds& odds = {});
  /// Inserts one scan seen from `origin` (the sensor, grid frame, meters):
  /// each cell holding a point of `hits` gets the hit update; with
  /// insert_free_space, every cell the segment from `origin` to a hit or to
  /// a point of `misses` (free space without an echo) crosses gets the miss
  /// update, except cells holding a hit. Each cell is updated at most once.
  /// The grid grows to hold everything. Non-finite points are skipped.
  /// Returns the number of cells updated.
  std::size_t insert(ProbabilityGrid& grid, const Eigen::Vector2d& origin,
                     std::span<const Eigen::Vector2d> hits,
                     std::span<const Eigen::Vector2d> misses = {}) const;
  /// The odds the tables were built from.
  const GridInsertionOdds& odds() const noexcept { return odds_; }

 private:
  GridInsertionOdds odds_;
  std::vector<std::uint16_t> hit_table_, miss_table_;
};

}  // namespace rove
