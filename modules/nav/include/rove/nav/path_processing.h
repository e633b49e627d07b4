#pragma once
/// \file
/// Operations on a planned path given as points in the map frame (meters):
/// line-of-sight simplification, smoothing, thinning, and turning the
/// points into poses with clearances. Each operation keeps the first and
/// last points and keeps every segment safe for a disc robot of the given
/// radius when the input's segments were (NavigationGrid::segment_free).

#include <vector>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/nav/grid_planner.h"
#include "rove/nav/navigation_grid.h"

namespace rove {

/// A list of path points, map frame, meters.
using PathPoints = std::vector<Eigen::Vector2d>;

/// Sum of the segment lengths, meters.
double path_length(const PathPoints& points);

/// Greedy line of sight: from each kept point, the farthest later point
/// (scanning forward until the first one that cannot be seen) reachable by
/// a free segment is kept next. Precondition (InvalidArgument): radius ≥ 0.
PathPoints simplify_path(const NavigationGrid& grid, const PathPoints& points, double radius);

/// Inserts points so that no segment is longer than `spacing` meters, then
/// runs `iterations` smoothing passes: each interior point moves a quarter
/// of the way toward the midpoint of its neighbours when both its new
/// segments stay free. Preconditions: spacing > 0, 0 ≤ iterations ≤ 10000.
PathPoints smooth_path(const NavigationGrid& grid, const PathPoints& points, double radius,
                       int iterations, double spacing);

/// Keeps a point when it is more than `min_step` meters from the last kept
/// one (MRPT's minStepInReturnedPath), and also the point before one whose
/// segment from the last kept point would not be free. Precondition:
/// min_step ≥ 0.
PathPoints thin_path(const NavigationGrid& grid, const PathPoints& points, double radius,
                     double min_step);

/// Points evenly spaced along the polyline at most `step` meters apart
/// (the first and last points and every corner kept). Precondition: step > 0.
PathPoints resample_path(const PathPoints& points, double step);

/// The poses of a path through `points` (at least two): the first pose is
/// `start`, the last `goal` (positions replaced by the first and last
/// points), the others heading along their outgoing segment; with
/// clearances, length and the minimum clearance over the segments' cells.
GridPath make_grid_path(const NavigationGrid& grid, const PathPoints& points, const SE2d& start,
                        const SE2d& goal);

}  // namespace rove
