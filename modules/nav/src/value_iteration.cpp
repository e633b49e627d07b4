// MRPT's PlannerSimple2D search, as its documentation and behaviour
// describe it: two waves of values, one spreading from the start and one
// from the goal, over the cells of a window around both that grows by one
// cell on every side before each sweep; a sweep visits the window row by
// row and gives every free cell not yet reached the best value its reached
// neighbours offer (2 per side step, 3 per diagonal step), in place, so a
// value set early in a sweep spreads further in the same sweep (value
// iteration in Gauss–Seidel order, a cell keeping the first value it
// gets). The search stops at the first cell that both waves reach; the
// path follows each wave's values down to its source.
#include <algorithm>
#include <cstdint>
#include <limits>

#include "grid_search.h"
#include "rove/core/check.h"

namespace rove::detail {

namespace {

// wave > 0: reached from the start with cost wave − 1; wave < 0: reached
// from the goal with cost −wave − 1; 0: not reached.
using Wave = std::int32_t;

// Follows one wave (sign +1: the start's, −1: the goal's) from `from` down
// to its source, appending the cells after `from`.
void descend(const GridSearchSpace& s, const std::vector<Wave>& wave, GridCellIndex from, int sign,
             std::vector<GridCellIndex>& out) {
  const NavigationGrid& g = s.grid();
  GridCellIndex c = from;
  while (sign * wave[g.index(c.x, c.y)] != 1) {
    const Wave here = sign * wave[g.index(c.x, c.y)];
    int best = -1;
    Wave best_value = here;
    for (int k = 0; k < 8; ++k) {
      if (!s.can_move(c.x, c.y, k)) continue;
      const Wave v = sign * wave[g.index(c.x + kMoveDx[k], c.y + kMoveDy[k])];
      if (v > 0 && v < best_value) {
        best_value = v;
        best = k;
      }
    }
    ROVE_CHECK_MSG(best >= 0, "value iteration: no way down from cell ({}, {})", c.x, c.y);
    c = {c.x + kMoveDx[best], c.y + kMoveDy[best]};
    out.push_back(c);
  }
}

// True when a chain of moves joins a and b (a flood fill from a). The
// sweeps below would find the same in time proportional to the map's size
// times its width; this takes one pass over the cells a reaches.
bool connected(const GridSearchSpace& s, GridCellIndex a, GridCellIndex b) {
  const NavigationGrid& g = s.grid();
  std::vector<std::uint8_t> mark(static_cast<std::size_t>(g.size_x()) * g.size_y(), 0);
  std::vector<std::uint32_t> queue{static_cast<std::uint32_t>(g.index(a.x, a.y))};
  mark[queue.front()] = 1;
  const std::size_t target = g.index(b.x, b.y);
  bool found = false;
  std::size_t counter = 0;
  for (std::size_t head = 0; head < queue.size() && !found; ++head) {
    poll_interrupt(counter);
    const std::uint32_t i = queue[head];
    const int x = static_cast<int>(i % g.size_x()), y = static_cast<int>(i / g.size_x());
    for (int k = 0; k < 8; ++k) {
      if (!s.can_move(x, y, k)) continue;
      const std::size_t j = g.index(x + kMoveDx[k], y + kMoveDy[k]);
      if (mark[j] != 0) continue;
      mark[j] = 1;
      queue.push_back(static_cast<std::uint32_t>(j));
      found = found || j == target;
    }
  }
  return found;
}

}  // namespace

std::vector<GridCellIndex> value_iteration_search(const GridSearchSpace& s, GridCellIndex start,
                                                  GridCellIndex goal, double max_path_length,
                                                  GridPlanResult& r) {
  const NavigationGrid& g = s.grid();
  const int nx = static_cast<int>(g.size_x()), ny = static_cast<int>(g.size_y());
  // Costs stay below 3 per cell of the grid.
  ROVE_CHECK_LT(static_cast<double>(nx) * ny, std::numeric_limits<Wave>::max() / 4.0);
  std::vector<Wave> wave(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);
  wave[g.index(start.x, start.y)] = 1;
  wave[g.index(goal.x, goal.y)] = -1;
  int x0 = std::min(start.x, goal.x) - 1, x1 = std::max(start.x, goal.x) + 1;
  int y0 = std::min(start.y, goal.y) - 1, y1 = std::max(start.y, goal.y) + 1;
  // Costs count 2 per cell side: a cost c is c / 2 · res meters.
  // Each wave stops where its cost passes 1.5 × max_path_length (MRPT's
  // factor); plan_path refuses a longer path found within it.
  const double cost_limit = max_path_length > 0 ? 1.5 * max_path_length * 2.0 / g.resolution()
                                                : std::numeric_limits<double>::infinity();
  bool limited = false;
  constexpr Wave kNone = std::numeric_limits<Wave>::max();
  std::size_t counter = 0;
  // Most queries meet within a few dozen sweeps; a query still open then
  // checks once that start and goal are connected at all.
  constexpr int kSweepsBeforeConnectivity = 64;
  for (int sweep = 1;; ++sweep) {
    if (sweep == kSweepsBeforeConnectivity && !connected(s, start, goal)) return {};
    x0 = std::max(0, x0 - 1);
    y0 = std::max(0, y0 - 1);
    x1 = std::min(nx - 1, x1 + 1);
    y1 = std::min(ny - 1, y1 + 1);
    bool grew = false;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        Wave& w = wave[g.index(x, y)];
        if (w != 0 || !s.free(x, y)) continue;
        poll_interrupt(counter);
        Wave from_start = kNone, from_goal = kNone;
        for (int k = 0; k < 8; ++k) {
          if (!s.can_move(x, y, k)) continue;
          const Wave v = wave[g.index(x + kMoveDx[k], y + kMoveDy[k])];
          const Wave step = k < 4 ? 2 : 3;
          if (v > 0) from_start = std::min(from_start, v + step);
          if (v < 0) from_goal = std::min(from_goal, -v + step);
        }
        if (from_start == kNone && from_goal == kNone) continue;
        if (static_cast<double>(std::min(from_start, from_goal)) > cost_limit) {
          limited = true;
          continue;
        }
        ++r.expanded_cells;
        grew = true;
        if (from_start != kNone && from_goal != kNone) {
          // The waves meet here: down the start's wave, then the goal's.
          w = from_start;
          std::vector<GridCellIndex> cells{{x, y}};
          descend(s, wave, {x, y}, 1, cells);
          std::reverse(cells.begin(), cells.end());
          w = -from_goal;
          descend(s, wave, {x, y}, -1, cells);
          return cells;
        }
        w = from_start != kNone ? from_start : -from_goal;
      }
    }
    if (!grew) {
      if (limited) r.termination = PlanTermination::TooLong;
      return {};
    }
  }
}

}  // namespace rove::detail
