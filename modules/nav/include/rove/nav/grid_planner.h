#pragma once
/// \file
/// Path planning for a circular robot on a NavigationGrid: MRPT's value-
/// iteration planner (PlannerSimple2D) and A* with a clearance cost, both
/// on the 8-connected grid of cells, followed by optional simplification
/// and smoothing; the path comes out as poses with clearances.
///
/// A cell is traversable when its clearance (NavigationGrid) is greater
/// than the robot radius: the obstacles grown by the radius, as MRPT grows
/// them before planning, but with the exact Euclidean distance instead of
/// MRPT's repeated 8-neighbour dilation (which grows squares).
///
/// - ValueIteration: the navigation function of MRPT's PlannerSimple2D —
///   cost-to-go to the goal with MRPT's integer metric (2 per side step, 3
///   per diagonal step, 3/2 ≈ √2), propagated from the goal until it
///   reaches the start (the fixed point of value iteration, computed in
///   one pass with a bucket queue: Dial, "Shortest-path forest with
///   topological ordering", CACM 1969), then followed downhill from the
///   start. Among equally good steps, the one nearer to the straight line
///   toward the goal.
/// - AStar: A* search (Hart, Nilsson, Raphael 1968) from start to goal,
///   each step costing its length × (1 + w·c²), c the shortfall of the
///   entered cell's clearance below radius + clearance_distance, relative
///   to clearance_distance; octile-distance heuristic (admissible).
///
/// The cell path then goes through, in order: line-of-sight simplification
/// (optional), smoothing (optional), and thinning to points at least
/// min_step apart (MRPT's minStepInReturnedPath). Every change keeps every
/// segment on traversable cells.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rove/math/se2.h"
#include "rove/nav/navigation_grid.h"

namespace rove {

/// The search of plan_path.
enum class GridPlannerMethod : std::uint8_t {
  ValueIteration,  ///< MRPT's PlannerSimple2D navigation function
  AStar,           ///< A* with a clearance cost
};

/// "value-iteration" or "astar".
std::string_view to_string(GridPlannerMethod method);

/// Options of plan_path (MRPT's PlannerSimple2D names in the comments).
struct GridPlannerOptions {
  /// The search.
  GridPlannerMethod method = GridPlannerMethod::ValueIteration;
  /// Robot radius, meters (`robotRadius`; MRPT's default 0.35). > 0.
  double robot_radius = 0.35;
  /// Thinning: the path keeps a cell when it is more than this from the
  /// last kept point, meters (`minStepInReturnedPath`, 0.4). ≥ 0; 0 keeps
  /// every cell.
  double min_step = 0.4;
  /// Give up (termination TooLong) rather than return a cell path longer
  /// than 1.5 × this, meters (`maxSearchPathLength` with MRPT's factor);
  /// the search stops spreading beyond that cost. ≤ 0: no limit.
  double max_path_length = -1;
  /// A*: weight w of the clearance cost. ≥ 0; 0: shortest path.
  double clearance_weight = 1.0;
  /// A*: clearance beyond the radius below which the cost applies, meters. > 0.
  double clearance_distance = 0.5;
  /// Replace the cell path by the fewest straight segments that stay on
  /// traversable cells (greedy line of sight) before thinning.
  bool simplify = false;
  /// Smoothing passes over the path (each moves every interior point a
  /// quarter of the way toward the midpoint of its neighbours, where that
  /// keeps its segments traversable); 0: none. ≤ 10000.
  int smoothing_iterations = 0;

  /// Throws InvalidArgument naming the first bad field.
  void check() const;
};

/// Why plan_path stopped.
enum class PlanTermination : std::uint8_t {
  Found,            ///< a path was found
  StartOutsideMap,  ///< the start lies outside the grid
  GoalOutsideMap,   ///< the goal lies outside the grid
  StartBlocked,     ///< the start cell is an obstacle or nearer to one than the radius
  GoalBlocked,      ///< the goal cell is an obstacle or nearer to one than the radius
  NoPath,           ///< no traversable path joins them
  TooLong,          ///< the path would exceed max_path_length
};

/// "found", "start-outside-map", ... (stable identifiers for reports).
std::string_view to_string(PlanTermination termination);

/// A planned path: poses from the start to the goal with their clearances.
struct GridPath {
  /// The first is the start pose, the last the goal pose (as given); each
  /// pose in between is at a path point, heading along the segment that
  /// leaves it. Map frame, meters and radians.
  std::vector<SE2d> poses;
  /// Clearance of the cell under each pose, meters (NavigationGrid).
  std::vector<double> clearances;
  /// Sum of the segment lengths, meters.
  double length = 0;
  /// Smallest clearance over every cell the segments pass through, meters.
  double min_clearance = 0;
};

/// Outcome of plan_path.
struct GridPlanResult {
  /// Why the search stopped.
  PlanTermination termination = PlanTermination::NoPath;
  /// One line for a person.
  std::string message;
  /// The path (empty unless Found).
  GridPath path;
  /// Cells of the grid path before simplification and thinning.
  std::size_t path_cells = 0;
  /// Cells the search settled.
  std::size_t expanded_cells = 0;
  /// True only when a path was found.
  bool ok() const noexcept { return termination == PlanTermination::Found; }
};

/// Plans a path for a disc robot from `start` to `goal` (map frame) on
/// `grid`. Start and goal in one cell give the two-pose path. Throws
/// InvalidArgument when the options fail check(); ResourceError when the
/// search's work space (10 bytes per cell) exceeds the memory budget.
/// Thread-safe (no shared state); polls rove::throw_if_interrupted().
GridPlanResult plan_path(const NavigationGrid& grid, const SE2d& start, const SE2d& goal,
                         const GridPlannerOptions& options = {});

}  // namespace rove
