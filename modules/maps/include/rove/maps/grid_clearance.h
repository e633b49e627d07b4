#pragma once
/// \file
/// Distances from grid cells to the nearest occupied cell: an exact
/// Euclidean distance transform (Meijster, Roerdink, Hesselink, "A general
/// algorithm for computing distance transforms in linear time", 2000) and
/// the clearance map built on it.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "rove/maps/occupancy_grid.h"

namespace rove {

/// For every cell (row by row), the squared distance in cells to the
/// nearest cell whose raw value is below `occupied_below` (an occupied
/// cell); cells of a grid without occupied cells get UINT64_MAX. O(cells).
template <GridCell Cell>
std::vector<std::uint64_t> squared_distance_to_occupied(const OccupancyGridT<Cell>& grid,
                                                        Cell occupied_below);

/// squared_distance_to_occupied delivered row by row, without holding the
/// whole result: row(y, d2) for every row y (the top row first, then down),
/// d2 that row's squared distances, valid during the call. Memory: 4 bytes
/// per cell and a few rows.
template <GridCell Cell>
void squared_distance_rows(const OccupancyGridT<Cell>& grid, Cell occupied_below,
                           const std::function<void(std::uint32_t, std::span<const std::uint64_t>)>& row);

/// √k for the squared distances of a transform: a table of the small ones
/// (the same doubles as std::sqrt), std::sqrt beyond it.
class SqrtTable {
 public:
  static const SqrtTable& instance();
  double operator()(std::uint64_t k) const noexcept;

 private:
  SqrtTable();
  static constexpr std::size_t kSize = 4096;
  std::vector<double> values_;
};

/// Clearance map: distance in meters from each cell's center to the center
/// of the nearest occupied cell (p(free) < occupied_threshold), row by row;
/// +inf when the grid has no occupied cell. Precondition (InvalidArgument):
/// occupied_threshold ∈ [0, 1].
template <GridCell Cell>
std::vector<float> clearance_map(const OccupancyGridT<Cell>& grid, float occupied_threshold = 0.5f);

/// Marker of "no occupied cell" in nearest_occupied_cell.
inline constexpr std::uint32_t kNoOccupiedCell = 0xffffffffu;

/// For every cell (row by row), the index in grid.cells() of a nearest
/// cell whose raw value is below `occupied_below` (the feature transform
/// of the same algorithm; among cells tied at the nearest distance, one of
/// them), or kNoOccupiedCell when the grid has none. O(cells).
template <GridCell Cell>
std::vector<std::uint32_t> nearest_occupied_cell(const OccupancyGridT<Cell>& grid,
                                                 Cell occupied_below);

/// Options of voronoi_diagram.
struct VoronoiOptions {
  /// Cells with p(free) below this are obstacles (MRPT: 0.5). In [0, 1].
  float occupied_threshold = 0.5f;
  /// Cells whose clearance is at most this (meters) are left out (MRPT's
  /// robot_size). ≥ 0.
  float min_clearance = 0.0f;
  /// The two obstacles a diagram cell lies between must be more than this
  /// many times the clearance apart (the larger clearance of the two
  /// neighbouring cells that straddle the bisector; MRPT's basis-point
  /// test, 1.75: the obstacles are seen more than ≈ 122° apart), which keeps
  /// the diagram off the corners of a room and the steps of a wall. > 0.
  float min_separation = 1.75f;
};

/// The generalized Voronoi diagram of the free space (cells equidistant to
/// two obstacles), one cell thick, with each cell's clearance.
struct VoronoiDiagram {
  std::uint32_t size_x = 0, size_y = 0;
  /// Clearance in meters of the diagram's cells, 0 elsewhere; row by row as
  /// the grid's cells.
  std::vector<float> clearance;
  /// Number of diagram cells.
  std::size_t cells = 0;
  /// True if cell (cx, cy) is on the diagram (false outside the grid).
  bool on(int cx, int cy) const {
    return cx >= 0 && cy >= 0 && static_cast<std::uint32_t>(cx) < size_x &&
           static_cast<std::uint32_t>(cy) < size_y &&
           clearance[static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * size_x] > 0;
  }
};

/// Memory voronoi_diagram() takes for a grid of size_x × size_y cells (its
/// result and work space: 8 bytes per cell), in bytes.
std::uint64_t voronoi_diagram_bytes(std::uint32_t size_x, std::uint32_t size_y);

/// The Voronoi diagram of the free cells of `grid` (MRPT's
/// buildVoronoiDiagram, computed from the exact feature transform instead
/// of MRPT's growing circles): two 4-neighbouring free cells whose nearest
/// obstacles differ and lie more than min_separation × the larger of their
/// clearances apart straddle the bisector of those obstacles, and the one
/// nearer to it (the smaller excess distance to the other obstacle; a tie
/// goes to the left or lower cell) is on the diagram.
/// Preconditions (InvalidArgument): options in range. O(cells) time,
/// voronoi_diagram_bytes() of memory; throws ResourceError when that exceeds
/// the memory budget (rove/core/memory_budget.h).
template <GridCell Cell>
VoronoiDiagram voronoi_diagram(const OccupancyGridT<Cell>& grid, const VoronoiOptions& options = {});

}  // namespace rove
