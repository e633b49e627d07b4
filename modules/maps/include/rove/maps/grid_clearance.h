#pragma once
/// \file
/// Distances from grid cells to the nearest occupied cell: an exact
/// Euclidean distance transform (Meijster, Roerdink, Hesselink, "A general
/// algorithm for computing distance transforms in linear time", 2000) and
/// the clearance map built on it.

#include <cstdint>
#include <vector>

#include "rove/maps/occupancy_grid.h"

namespace rove {

/// For every cell (row by row), the squared distance in cells to the
/// nearest cell whose raw value is below `occupied_below` (an occupied
/// cell); cells of a grid without occupied cells get UINT64_MAX. O(cells).
template <GridCell Cell>
std::vector<std::uint64_t> squared_distance_to_occupied(const OccupancyGridT<Cell>& grid,
                                                        Cell occupied_below);

/// Clearance map: distance in meters from each cell's center to the center
/// of the nearest occupied cell (p(free) < occupied_threshold), row by row;
/// +inf when the grid has no occupied cell. Precondition (InvalidArgument):
/// occupied_threshold ∈ [0, 1].
template <GridCell Cell>
std::vector<float> clearance_map(const OccupancyGridT<Cell>& grid, float occupied_threshold = 0.5f);

}  // namespace rove
