#pragma once
/// \file
/// How far two occupancy grids of the same place agree, cell by cell: the
/// check that a map is consistent with a reference map of the same data
/// (a SLAM result against another method's map of the same loop; a doubled
/// wall shows as occupied cells where the reference is free).

#include <cstddef>

#include "rove/maps/occupancy_grid.h"

namespace rove {

/// Options of grid_agreement.
struct GridAgreementOptions {
  /// A cell is known when |p(free) − 0.5| exceeds this, in [0, 0.5).
  /// Default 0.1.
  double known_margin = 0.1;
  /// Occupied cells of `grid` count as matched when the reference has an
  /// occupied cell within this many cells (Chebyshev), ≥ 0. Default 1.
  int wall_tolerance_cells = 1;
};

/// The agreement of `grid` with `reference` (both in the same map frame;
/// cells are compared at `grid`'s cell centers).
struct GridAgreement {
  /// Cells known in both.
  std::size_t compared = 0;
  /// Of those, cells both call free or both call occupied.
  std::size_t agreeing = 0;
  /// Occupied cells of `grid` (p(free) < 0.5 − known_margin).
  std::size_t occupied = 0;
  /// Of those, cells with an occupied reference cell within
  /// wall_tolerance_cells.
  std::size_t occupied_matched = 0;
  /// Occupied cells of `grid` whose reference cell is known (seen by the
  /// reference: a wall there can be judged), and of those the matched ones.
  std::size_t occupied_known = 0, occupied_known_matched = 0;
  /// agreeing / compared (1 when nothing was compared).
  double agreement() const noexcept {
    return compared ? static_cast<double>(agreeing) / static_cast<double>(compared) : 1.0;
  }
  /// occupied_matched / occupied (1 when `grid` has no occupied cell).
  double wall_agreement() const noexcept {
    return occupied ? static_cast<double>(occupied_matched) / static_cast<double>(occupied) : 1.0;
  }
  /// occupied_known_matched / occupied_known (1 when there is none): the
  /// walls of `grid` where the reference saw something, within the
  /// tolerance of a reference wall. A doubled wall lowers it; walls the
  /// reference never saw (a sparser reference) do not.
  double known_wall_agreement() const noexcept {
    return occupied_known ? static_cast<double>(occupied_known_matched) / static_cast<double>(occupied_known)
                          : 1.0;
  }
};

/// Compares `grid` with `reference` (see GridAgreement). Precondition
/// (InvalidArgument): options in range.
GridAgreement grid_agreement(const OccupancyGrid& grid, const OccupancyGrid& reference,
                             const GridAgreementOptions& options = {});

}  // namespace rove
