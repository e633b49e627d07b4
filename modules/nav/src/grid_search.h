#pragma once
// Internal: what the grid searches (value iteration, A*) share: the eight
// moves, traversability for a disc robot, and the cell path type.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rove/core/interrupt.h"
#include "rove/nav/grid_planner.h"
#include "rove/nav/navigation_grid.h"

namespace rove::detail {

/// The 8 moves: the four sides first (−x, +x, −y, +y), then the diagonals,
/// in the order MRPT's planner scans a cell's neighbours.
inline constexpr std::array<int, 8> kMoveDx = {-1, 1, 0, 0, -1, 1, -1, 1};
inline constexpr std::array<int, 8> kMoveDy = {0, 0, -1, 1, -1, -1, 1, 1};

/// A cell of the grid.
struct GridCellIndex {
  int x = 0, y = 0;
  friend bool operator==(const GridCellIndex&, const GridCellIndex&) = default;
};

/// Traversability for a disc robot: a cell is free when its clearance
/// exceeds the radius; a diagonal move also needs both cells beside it
/// free, so no move cuts the corner of a blocked cell. The radius is
/// compared in float, the clearances' precision (NavigationGrid::segment_free).
class GridSearchSpace {
 public:
  GridSearchSpace(const NavigationGrid& grid, double radius) : g_(grid) {
    const auto r = static_cast<float>(radius);
    const auto c = grid.clearances();
    free_.resize(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) free_[i] = c[i] > r ? 1 : 0;
  }

  bool free(int x, int y) const { return g_.contains(x, y) && free_[g_.index(x, y)] != 0; }
  bool can_move(int x, int y, int k) const {
    const int nx = x + kMoveDx[k], ny = y + kMoveDy[k];
    if (!free(nx, ny)) return false;
    return k < 4 || (free(nx, y) && free(x, ny));
  }
  const NavigationGrid& grid() const { return g_; }

 private:
  const NavigationGrid& g_;
  std::vector<std::uint8_t> free_;  // per cell, row by row
};

/// Polls for Ctrl-C every 65536 calls.
inline void poll_interrupt(std::size_t& counter) {
  if ((++counter & 0xffff) == 0) throw_if_interrupted();
}

/// MRPT's PlannerSimple2D search (value_iteration.cpp): the cells from
/// start to goal, empty when none; sets r.termination to TooLong when the
/// length limit stopped it and counts r.expanded_cells.
std::vector<GridCellIndex> value_iteration_search(const GridSearchSpace& s, GridCellIndex start,
                                                  GridCellIndex goal, double max_path_length,
                                                  GridPlanResult& r);

/// A* (grid_planner.cpp), same contract.
std::vector<GridCellIndex> astar_search(const GridSearchSpace& s, GridCellIndex start,
                                        GridCellIndex goal, const GridPlannerOptions& o,
                                        GridPlanResult& r);

}  // namespace rove::detail
