#pragma once
/// \file
/// NavigationGrid: what the planners and the simulator need to know about
/// an occupancy grid, computed once: which cells are obstacles, and every
/// cell's clearance (the exact Euclidean distance transform of the
/// obstacles, rove/maps/grid_clearance.h).
///
/// Frames and units: the map frame, meters. Cell (cx, cy) covers
/// [x_min + cx·res, x_min + (cx+1)·res) × [y_min + cy·res, y_min + (cy+1)·res)
/// as in the occupancy grid it was built from. A cell is an obstacle when
/// its probability of being free is at most the occupancy threshold (MRPT's
/// PlannerSimple2D rule: unknown cells, p = 0.5, are obstacles by default).
/// Everything outside the grid is an obstacle too: the clearance of a cell
/// is its distance to the nearest obstacle cell or to the ring of cells
/// just outside the grid, center to center.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/maps/occupancy_grid.h"

namespace rove {

/// Obstacles and clearances of a 2D grid. Immutable after construction;
/// thread-safe for concurrent const use.
class NavigationGrid {
 public:
  /// An empty grid (no cells; every query reads "outside").
  NavigationGrid() = default;

  /// From an occupancy grid: obstacles are the cells whose p(free) is at
  /// most `occupancy_threshold` (MRPT's `occupancyThreshold`, default 0.5).
  /// Preconditions (InvalidArgument): occupancy_threshold ∈ [0, 1]. Throws
  /// ResourceError when the work space (9 bytes per cell) exceeds the
  /// memory budget.
  template <GridCell Cell>
  static NavigationGrid from_occupancy(const OccupancyGridT<Cell>& grid,
                                       float occupancy_threshold = 0.5f);

  /// From an obstacle mask (row by row, nonzero = obstacle) and the grid's
  /// geometry. Preconditions (InvalidArgument): size_x, size_y ≥ 1,
  /// occupied.size() == size_x·size_y, finite x_min/y_min, resolution > 0.
  static NavigationGrid from_mask(std::uint32_t size_x, std::uint32_t size_y, double x_min,
                                  double y_min, double resolution,
                                  std::vector<std::uint8_t> occupied);

  /// Cells along x.
  std::uint32_t size_x() const noexcept { return size_x_; }
  /// Cells along y.
  std::uint32_t size_y() const noexcept { return size_y_; }
  /// Cell side, meters.
  double resolution() const noexcept { return resolution_; }
  /// Left edge, meters.
  double x_min() const noexcept { return x_min_; }
  /// Bottom edge, meters.
  double y_min() const noexcept { return y_min_; }
  /// Right edge, meters.
  double x_max() const noexcept { return x_min_ + size_x_ * resolution_; }
  /// Top edge, meters.
  double y_max() const noexcept { return y_min_ + size_y_ * resolution_; }

  /// Column of world x: floor((x − x_min) / res); may lie outside [0, size_x).
  /// Saturates far outside (and maps NaN to −1).
  int cell_x(double x) const noexcept { return to_cell((x - x_min_) / resolution_); }
  /// Row of world y (as cell_x).
  int cell_y(double y) const noexcept { return to_cell((y - y_min_) / resolution_); }
  /// Center of cell (cx, cy), meters (any cx, cy).
  Eigen::Vector2d cell_center(int cx, int cy) const noexcept {
    return {x_min_ + (cx + 0.5) * resolution_, y_min_ + (cy + 0.5) * resolution_};
  }
  /// True if (cx, cy) is a cell of the grid.
  bool contains(int cx, int cy) const noexcept {
    return static_cast<unsigned>(cx) < size_x_ && static_cast<unsigned>(cy) < size_y_;
  }
  /// True if world point p lies in the grid.
  bool contains(const Eigen::Vector2d& p) const noexcept { return contains(cell_x(p.x()), cell_y(p.y())); }
  /// Row-major index of a cell of the grid (no check).
  std::size_t index(int cx, int cy) const noexcept {
    return static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * size_x_;
  }

  /// True if (cx, cy) is an obstacle; every cell outside the grid is.
  bool occupied(int cx, int cy) const noexcept { return !contains(cx, cy) || occupied_[index(cx, cy)] != 0; }
  /// Clearance of cell (cx, cy), meters: distance from its center to the
  /// nearest obstacle center (0 for an obstacle or a cell outside).
  float clearance(int cx, int cy) const noexcept { return contains(cx, cy) ? clearance_[index(cx, cy)] : 0.0f; }
  /// Clearance of the cell holding world point p, meters.
  float clearance_at(const Eigen::Vector2d& p) const noexcept { return clearance(cell_x(p.x()), cell_y(p.y())); }
  /// All obstacle flags, row by row (1 = obstacle).
  std::span<const std::uint8_t> occupancy() const noexcept { return occupied_; }
  /// All clearances, row by row, meters.
  std::span<const float> clearances() const noexcept { return clearance_; }

  /// Exact distance, meters, from world point p to the nearest point of an
  /// obstacle cell (its square) or of the outside of the grid, when that
  /// distance is below `max_distance`; otherwise returns max_distance.
  /// 0 when p lies in an obstacle. Cost: the cells within max_distance of p
  /// that the clearance map cannot rule out. Precondition: max_distance ≥ 0.
  double distance_to_obstacle(const Eigen::Vector2d& p, double max_distance) const;

  /// The obstacle cell centers within `radius` meters of p (p included),
  /// appended to `out`; cells outside the grid are not listed.
  void obstacles_near(const Eigen::Vector2d& p, double radius, std::vector<Eigen::Vector2d>& out) const;

  /// Calls f(cx, cy) for every cell the segment a → b passes through
  /// (touching a corner counts), from a's cell to b's, in order; stops early
  /// when f returns false. Returns false if f stopped it. Cells outside the
  /// grid are visited too (f decides). Preconditions: finite a and b.
  bool visit_segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                     const std::function<bool(int, int)>& f) const;

  /// Distance from `origin` along the ray at `angle` (radians, map frame)
  /// to the first obstacle cell it enters, meters; +inf when it meets none
  /// within `max_range` or leaves the grid first (a lidar sees no echo
  /// there). 0 when origin lies in an obstacle. Precondition: finite origin
  /// and angle, max_range ≥ 0.
  double cast_ray(const Eigen::Vector2d& origin, double angle, double max_range) const;

  /// Smallest clearance over the cells the segment a → b passes through,
  /// meters (0 if it touches an obstacle or leaves the grid).
  float segment_clearance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;

  /// True when every cell the segment a → b passes through has a clearance
  /// greater than `radius` meters (the segment is safe for a disc robot of
  /// that radius centered on the cells). The radius is rounded to float,
  /// the clearances' precision, so a clearance equal to it is not greater.
  bool segment_free(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double radius) const;

 private:
  static int to_cell(double q) noexcept;
  // The clearances of row cy from its squared distances to an obstacle.
  void clearance_row(std::uint32_t cy, std::span<const std::uint64_t> d2);

  std::uint32_t size_x_ = 0, size_y_ = 0;
  double x_min_ = 0, y_min_ = 0, resolution_ = 1;
  std::vector<std::uint8_t> occupied_;
  std::vector<float> clearance_;
};

extern template NavigationGrid NavigationGrid::from_occupancy(const OccupancyGridT<std::int8_t>&, float);
extern template NavigationGrid NavigationGrid::from_occupancy(const OccupancyGridT<std::int16_t>&, float);

}  // namespace rove
