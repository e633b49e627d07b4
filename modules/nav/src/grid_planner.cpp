#include "rove/nav/grid_planner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/memory_budget.h"
#include "rove/nav/path_processing.h"
#include "grid_search.h"

namespace rove {

std::string_view to_string(GridPlannerMethod method) {
  return method == GridPlannerMethod::AStar ? "astar" : "value-iteration";
}

std::string_view to_string(PlanTermination t) {
  switch (t) {
    case PlanTermination::Found: return "found";
    case PlanTermination::StartOutsideMap: return "start-outside-map";
    case PlanTermination::GoalOutsideMap: return "goal-outside-map";
    case PlanTermination::StartBlocked: return "start-blocked";
    case PlanTermination::GoalBlocked: return "goal-blocked";
    case PlanTermination::NoPath: return "no-path";
    case PlanTermination::TooLong: return "too-long";
  }
  return "unknown";
}

void GridPlannerOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(robot_radius) && robot_radius > 0, "robot_radius must be > 0, got {}",
                 robot_radius);
  ROVE_CHECK_MSG(std::isfinite(min_step) && min_step >= 0, "min_step must be >= 0, got {}", min_step);
  ROVE_CHECK_MSG(!std::isnan(max_path_length), "max_path_length is NaN");
  ROVE_CHECK_MSG(std::isfinite(clearance_weight) && clearance_weight >= 0,
                 "clearance_weight must be >= 0, got {}", clearance_weight);
  ROVE_CHECK_MSG(std::isfinite(clearance_distance) && clearance_distance > 0,
                 "clearance_distance must be > 0, got {}", clearance_distance);
  ROVE_CHECK_MSG(smoothing_iterations >= 0 && smoothing_iterations <= 10000,
                 "smoothing_iterations must be in [0, 10000], got {}", smoothing_iterations);
}

namespace detail {

// A* from start to goal with the clearance cost of grid_planner.h.

std::vector<GridCellIndex> astar_search(const GridSearchSpace& s, GridCellIndex start,
                                        GridCellIndex goal, const GridPlannerOptions& o,
                                        GridPlanResult& r) {
  const NavigationGrid& g = s.grid();
  const std::size_t n = static_cast<std::size_t>(g.size_x()) * g.size_y();
  std::vector<float> cost(n, std::numeric_limits<float>::infinity());
  // The move that reached each cell (bits 0-6; 0x7f: none) and whether it
  // is closed (bit 7).
  std::vector<std::uint8_t> came_by(n, 0x7f);
  const double res = g.resolution();
  const auto heuristic = [&](int x, int y) {
    const double dx = std::abs(x - goal.x), dy = std::abs(y - goal.y);
    return res * (std::max(dx, dy) + (std::numbers::sqrt2 - 1.0) * std::min(dx, dy));
  };
  const double reach = o.robot_radius + o.clearance_distance;
  const auto factor = [&](int x, int y) {
    const double shortfall = std::clamp((reach - g.clearance(x, y)) / o.clearance_distance, 0.0, 1.0);
    return 1.0 + o.clearance_weight * shortfall * shortfall;
  };
  const double limit = o.max_path_length > 0 ? 1.5 * o.max_path_length * (1.0 + o.clearance_weight)
                                             : std::numeric_limits<double>::infinity();
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const std::size_t si = g.index(start.x, start.y), gi = g.index(goal.x, goal.y);
  cost[si] = 0;
  open.emplace(heuristic(start.x, start.y), static_cast<std::uint32_t>(si));
  std::size_t counter = 0;
  bool reached = false;
  while (!open.empty()) {
    const auto [f, i] = open.top();
    open.pop();
    if (came_by[i] & 0x80) continue;
    if (f > limit) {
      r.termination = PlanTermination::TooLong;
      return {};
    }
    came_by[i] |= 0x80;
    poll_interrupt(counter);
    ++r.expanded_cells;
    if (i == gi) {
      reached = true;
      break;
    }
    const int x = static_cast<int>(i % g.size_x()), y = static_cast<int>(i / g.size_x());
    for (int k = 0; k < 8; ++k) {
      if (!s.can_move(x, y, k)) continue;
      const int nx = x + kMoveDx[k], ny = y + kMoveDy[k];
      const std::size_t j = g.index(nx, ny);
      if (came_by[j] & 0x80) continue;
      const double step = res * (k < 4 ? 1.0 : std::numbers::sqrt2) * factor(nx, ny);
      const auto c = static_cast<float>(cost[i] + step);
      if (c < cost[j]) {
        cost[j] = c;
        came_by[j] = static_cast<std::uint8_t>(k);
        open.emplace(c + heuristic(nx, ny), static_cast<std::uint32_t>(j));
      }
    }
  }
  if (!reached) return {};
  std::vector<GridCellIndex> cells{goal};
  GridCellIndex c = goal;
  while (!(c == start)) {
    const int k = came_by[g.index(c.x, c.y)] & 0x7f;
    c = {c.x - kMoveDx[k], c.y - kMoveDy[k]};
    cells.push_back(c);
  }
  std::reverse(cells.begin(), cells.end());
  return cells;
}

}  // namespace detail

namespace {

std::string describe(const SE2d& p) {
  return fmt::format("({:.3f}, {:.3f})", p.translation().x(), p.translation().y());
}

// Outside the grid, or not traversable: the termination and its message.
bool refuse_endpoint(const detail::GridSearchSpace& s, double radius, const SE2d& p, bool is_start,
                     GridPlanResult& r) {
  const NavigationGrid& g = s.grid();
  const char* what = is_start ? "start" : "goal";
  const int x = g.cell_x(p.translation().x()), y = g.cell_y(p.translation().y());
  if (!g.contains(x, y)) {
    r.termination = is_start ? PlanTermination::StartOutsideMap : PlanTermination::GoalOutsideMap;
    r.message = fmt::format("the {} {} is outside the map [{:.3f}, {:.3f}] x [{:.3f}, {:.3f}] m", what,
                            describe(p), g.x_min(), g.x_max(), g.y_min(), g.y_max());
    return true;
  }
  if (s.free(x, y)) return false;
  r.termination = is_start ? PlanTermination::StartBlocked : PlanTermination::GoalBlocked;
  r.message = g.occupied(x, y)
                  ? fmt::format("the {} {} is in an obstacle", what, describe(p))
                  : fmt::format("the {} {} is {:.3f} m from an obstacle, within the robot radius {} m",
                                what, describe(p), g.clearance(x, y), radius);
  return true;
}

}  // namespace

GridPlanResult plan_path(const NavigationGrid& grid, const SE2d& start, const SE2d& goal,
                         const GridPlannerOptions& o) {
  o.check();
  GridPlanResult r;
  // The free flags (1 byte per cell) and the search's own (A* 5; value
  // iteration 4, and 5 more for its connectivity check).
  check_memory_budget(checked_bytes(static_cast<std::uint64_t>(grid.size_x()) * grid.size_y(), 10),
                      fmt::format("path planning on a {} \u00d7 {} grid", grid.size_x(), grid.size_y()));
  const detail::GridSearchSpace s(grid, o.robot_radius);
  if (refuse_endpoint(s, o.robot_radius, start, true, r) ||
      refuse_endpoint(s, o.robot_radius, goal, false, r)) {
    return r;
  }
  const detail::GridCellIndex sc{grid.cell_x(start.translation().x()), grid.cell_y(start.translation().y())};
  const detail::GridCellIndex gc{grid.cell_x(goal.translation().x()), grid.cell_y(goal.translation().y())};
  std::vector<detail::GridCellIndex> cells;
  if (sc == gc) {
    cells = {sc};
  } else if (o.method == GridPlannerMethod::ValueIteration) {
    cells = detail::value_iteration_search(s, sc, gc, o.max_path_length, r);
  } else {
    cells = detail::astar_search(s, sc, gc, o, r);
  }
  if (cells.empty()) {
    if (r.termination == PlanTermination::TooLong) {
      r.message = fmt::format("no path from {} to {} shorter than 1.5 x {} m (max_path_length)",
                              describe(start), describe(goal), o.max_path_length);
    } else {
      r.termination = PlanTermination::NoPath;
      r.message = fmt::format("no path from {} to {} for a robot of radius {} m ({} cells searched)",
                              describe(start), describe(goal), o.robot_radius, r.expanded_cells);
    }
    return r;
  }
  r.path_cells = cells.size();
  if (o.max_path_length > 0) {
    double cell_path = 0;
    for (std::size_t i = 1; i < cells.size(); ++i) {
      cell_path += std::hypot(cells[i].x - cells[i - 1].x, cells[i].y - cells[i - 1].y) * grid.resolution();
    }
    if (cell_path > 1.5 * o.max_path_length) {
      r.termination = PlanTermination::TooLong;
      r.message = fmt::format("the path from {} to {} is {:.3f} m, longer than 1.5 x {} m (max_path_length)",
                              describe(start), describe(goal), cell_path, o.max_path_length);
      return r;
    }
  }
  // The cell centers between the start and goal positions themselves.
  PathPoints points{start.translation()};
  for (std::size_t i = 1; i + 1 < cells.size(); ++i) points.push_back(grid.cell_center(cells[i].x, cells[i].y));
  points.push_back(goal.translation());
  if (o.simplify) points = simplify_path(grid, points, o.robot_radius);
  if (o.smoothing_iterations > 0) {
    const double spacing = std::max(o.min_step, 2.0 * grid.resolution());
    points = smooth_path(grid, points, o.robot_radius, o.smoothing_iterations, spacing);
  }
  points = thin_path(grid, points, o.robot_radius, o.min_step);
  r.path = make_grid_path(grid, points, start, goal);
  r.termination = PlanTermination::Found;
  r.message = fmt::format("{}: {:.3f} m through {} points, minimum clearance {:.3f} m", to_string(o.method),
                          r.path.length, r.path.poses.size(), r.path.min_clearance);
  return r;
}

}  // namespace rove
