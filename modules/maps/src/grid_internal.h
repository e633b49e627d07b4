#pragma once
// Internal helpers shared by the grid's insertion and likelihood code.

#include <cstddef>

#include "rove/maps/grid_insertion.h"
#include "rove/maps/occupancy_grid.h"

namespace rove::detail {

/// Sum of the information 1 − H(p')/ln 2 of each cell update that inserting
/// the scan (thin rays, one in `ray_step`) would make, p' the updated
/// probability of each visited cell taken alone; the grid is not changed and
/// cells outside it count as unknown. The ray geometry and the arithmetic
/// are those of options.arithmetic (as insert_scan).
struct ScanInformation {
  double information = 0.0;
  std::size_t cells = 0;
};
template <GridCell Cell>
ScanInformation scan_information(const OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                                 const Pose3& T_map_robot, const GridInsertionOptions& options,
                                 int ray_step);

/// The update strengths of an insertion; with `mrpt_wrap` the occupied one
/// is computed in the cell type as MRPT does (it wraps around for int8 above
/// p ≈ 0.9), else it saturates.
struct InsertStrengths;
template <GridCell Cell>
InsertStrengths insert_strengths(const GridInsertionOptions& options, bool mrpt_wrap);

template <typename Real>
struct RayDirections;
/// rove's ray directions in double: the scan's own ray angles
/// (RangeScan2D::ray_angle) about the sensor's heading, mirrored for a
/// sensor mounted upside down, one ray in `step`; a beam is as wide as the
/// spacing. A single ray points along the sensor's heading.
RayDirections<double> ray_directions(const RangeScan2D& scan, const Pose3& T_map_sensor, int step);
/// MRPT's ray directions (grid_insertion_mrpt.cpp): the angle accumulated in
/// float from the first ray in steps of step·aperture / N (N rays, not
/// N − 1 as the scan's own angles), the first angle rounded as MRPT's thin
/// (`widening` false) or widening-beam branch rounds it, beams
/// aperture / N wide.
RayDirections<float> mrpt_ray_directions(const RangeScan2D& scan, const Pose3& T_map_sensor,
                                         int step, bool widening);

}  // namespace rove::detail
