#pragma once
// Internal helpers shared by the grid's insertion and likelihood code.

#include <cstddef>

#include "rove/maps/grid_insertion.h"
#include "rove/maps/occupancy_grid.h"

namespace rove::detail {

/// insert_scan with MRPT's int8 arithmetic for the occupied update
/// (3·L computed in the cell type, wrapping above p ≈ 0.9), as MRPT's
/// cells-difference likelihood builds its comparison grid with p = 0.95.
template <GridCell Cell>
GridInsertResult insert_scan_mrpt_overflow(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                                           const Pose3& T_map_robot,
                                           const GridInsertionOptions& options);

/// Sum of the information 1 − H(p')/ln 2 of each cell update that inserting
/// the scan (thin rays, one in `ray_step`) would make, p' the updated
/// probability of each visited cell taken alone; the grid is not changed and
/// cells outside it count as unknown.
struct ScanInformation {
  double information = 0.0;
  std::size_t cells = 0;
};
template <GridCell Cell>
ScanInformation scan_information(const OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                                 const Pose3& T_map_robot, const GridInsertionOptions& options,
                                 int ray_step);

}  // namespace rove::detail
