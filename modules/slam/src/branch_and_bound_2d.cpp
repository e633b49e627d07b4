#include "rove/slam/branch_and_bound_2d.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "rove/core/check.h"

namespace rove {

std::uint8_t PrecomputedGridStack::to_value(float probability) noexcept {
  const float p = std::clamp(probability, ProbabilityGrid::kMinProbability, ProbabilityGrid::kMaxProbability);
  return static_cast<std::uint8_t>(std::lround(
      255.0f * (p - ProbabilityGrid::kMinProbability) /
      (ProbabilityGrid::kMaxProbability - ProbabilityGrid::kMinProbability)));
}

PrecomputedGridStack::PrecomputedGridStack(const ProbabilityGrid& grid, int depth)
    : resolution_(grid.resolution()), offset_(grid.offset()) {
  ROVE_CHECK_MSG(depth >= 0 && depth <= 16, "branch-and-bound depth {} must lie in [0, 16]", depth);
  levels_.resize(static_cast<std::size_t>(depth) + 1);
  Level& base = levels_[0];
  base.width = grid.size_x();
  base.height = grid.size_y();
  base.cells.resize(grid.values().size());
  std::transform(grid.values().begin(), grid.values().end(), base.cells.begin(),
                 [](std::uint16_t v) { return to_value(ProbabilityGrid::value_to_probability(v)); });
  for (int h = 1; h <= depth; ++h) {
    // In the arrays of height h − 1, the window [x, x + 2^h) of height h's
    // cell x (array coordinates) is the union of the windows at x − s and
    // x (s = 2^(h−1)); out of range counts as 0.
    const int s = 1 << (h - 1);
    const Level& src = levels_[static_cast<std::size_t>(h) - 1];
    Level& l = levels_[static_cast<std::size_t>(h)];
    l.pad = (1 << h) - 1;
    l.width = src.width + s;
    l.height = src.height + s;
    const auto W = static_cast<std::size_t>(l.width);
    // Along x, rows of the source: row[y][x] = max(src(x − s, y), src(x, y)).
    std::vector<std::uint8_t> row(W * static_cast<std::size_t>(src.height), 0);
    for (int y = 0; y < src.height; ++y) {
      const std::uint8_t* in = src.cells.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(src.width);
      std::uint8_t* out = row.data() + static_cast<std::size_t>(y) * W;
      for (int x = 0; x < l.width; ++x) {
        const std::uint8_t a = x - s >= 0 && x - s < src.width ? in[x - s] : 0;
        const std::uint8_t b = x < src.width ? in[x] : 0;
        out[x] = std::max(a, b);
      }
    }
    // Along y: l(x, y) = max(row(x, y − s), row(x, y)).
    l.cells.assign(W * static_cast<std::size_t>(l.height), 0);
    for (int y = 0; y < l.height; ++y) {
      std::uint8_t* out = l.cells.data() + static_cast<std::size_t>(y) * W;
      if (y - s >= 0 && y - s < src.height) {
        const std::uint8_t* a = row.data() + static_cast<std::size_t>(y - s) * W;
        for (std::size_t x = 0; x < W; ++x) out[x] = a[x];
      }
      if (y < src.height) {
        const std::uint8_t* b = row.data() + static_cast<std::size_t>(y) * W;
        for (std::size_t x = 0; x < W; ++x) out[x] = std::max(out[x], b[x]);
      }
    }
  }
}

std::uint32_t PrecomputedGridStack::sum_values(int h, std::span<const Eigen::Vector2i> cells,
                                               const Eigen::Vector2i& lo, const Eigen::Vector2i& hi,
                                               int dx, int dy) const noexcept {
  const Level& l = levels_[static_cast<std::size_t>(h)];
  const int ox = dx + l.pad, oy = dy + l.pad;
  const std::uint8_t* data = l.cells.data();
  const auto W = static_cast<std::size_t>(l.width);
  std::uint32_t sum = 0;
  if (lo.x() + ox >= 0 && lo.y() + oy >= 0 && hi.x() + ox < l.width && hi.y() + oy < l.height) {
    // The whole scan lies inside the array: no check per cell.
    for (const auto& c : cells) {
      sum += data[static_cast<std::size_t>(c.x() + ox) + static_cast<std::size_t>(c.y() + oy) * W];
    }
    return sum;
  }
  for (const auto& c : cells) {
    const auto x = static_cast<unsigned>(c.x() + ox), y = static_cast<unsigned>(c.y() + oy);
    if (x < static_cast<unsigned>(l.width) && y < static_cast<unsigned>(l.height)) {
      sum += data[static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * W];
    }
  }
  return sum;
}

std::size_t PrecomputedGridStack::memory_bytes() const noexcept {
  std::size_t n = 0;
  for (const auto& l : levels_) n += l.cells.capacity();
  return n;
}

void BranchAndBoundWindow::check() const {
  ROVE_CHECK_MSG(std::isfinite(linear) && linear >= 0.0, "linear search window {} must be >= 0",
                 linear);
  ROVE_CHECK_MSG(std::isfinite(angular) && angular >= 0.0 && angular <= std::numbers::pi,
                 "angular search window {} must lie in [0, pi]", angular);
  ROVE_CHECK_MSG(step_range_cap > 0.0, "step_range_cap {} must be > 0", step_range_cap);
}

BranchAndBoundSearch::BranchAndBoundSearch(const PrecomputedGridStack& grids,
                                           std::span<const Eigen::Vector2d> points_robot,
                                           const SE2d& initial_T_grid_robot,
                                           const BranchAndBoundWindow& window)
    : grids_(grids), initial_(initial_T_grid_robot) {
  window.check();
  std::vector<Eigen::Vector2d> pts;
  double d_max = 0.0;
  for (const auto& p : points_robot) {
    if (!p.allFinite()) continue;
    pts.push_back(p);
    d_max = std::max(d_max, p.norm());
  }
  ROVE_CHECK_MSG(!pts.empty(), "branch-and-bound needs at least one finite point");
  points_ = pts.size();
  d_max = std::min(d_max, window.step_range_cap);
  const double r = grids.resolution();
  // Hess Eq. 7: the step that moves the farthest point by about one cell.
  angular_step_ = d_max > r ? std::acos(1.0 - r * r / (2.0 * d_max * d_max)) : std::numbers::pi / 4;
  const int n = window.angular > 0.0 ? static_cast<int>(std::ceil(window.angular / angular_step_)) : 0;
  linear_cells_ = static_cast<int>(std::ceil(window.linear / r));
  const double inv = 1.0 / r;
  scans_.resize(static_cast<std::size_t>(2 * n + 1));
  boxes_.reserve(scans_.size());
  for (int a = 0; a < 2 * n + 1; ++a) {
    const SE2d T(initial_.translation().x(), initial_.translation().y(),
                 initial_.angle() + (a - n) * angular_step_);
    auto& cells = scans_[static_cast<std::size_t>(a)];
    cells.reserve(pts.size());
    for (const auto& p : pts) {
      const Eigen::Vector2d q = T * p;
      cells.emplace_back(static_cast<int>(std::floor(q.x() * inv)) - grids.offset().x(),
                         static_cast<int>(std::floor(q.y() * inv)) - grids.offset().y());
    }
    Eigen::Vector2i lo = cells.front(), hi = cells.front();
    for (const auto& c : cells) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    boxes_.emplace_back(lo, hi);
  }
}

double BranchAndBoundSearch::score_sum(int h, int a, int dx, int dy) const {
  const auto i = static_cast<std::size_t>(a);
  return static_cast<double>(grids_.sum_values(h, scans_[i], boxes_[i].first, boxes_[i].second, dx, dy));
}

double BranchAndBoundSearch::score(int h, int a, int dx, int dy) const {
  ROVE_CHECK_MSG(h >= 0 && h <= grids_.depth(), "height {} outside [0, {}]", h, grids_.depth());
  ROVE_CHECK_MSG(a >= 0 && a < num_angles(), "angle index {} outside [0, {})", a, num_angles());
  return unchecked_score(h, a, dx, dy);
}

double BranchAndBoundSearch::unchecked_score(int h, int a, int dx, int dy) const {
  return PrecomputedGridStack::to_probability(score_sum(h, a, dx, dy) / static_cast<double>(points_));
}

SE2d BranchAndBoundSearch::pose(int a, int dx, int dy) const {
  const int n = (num_angles() - 1) / 2;
  const double r = grids_.resolution();
  return SE2d(initial_.translation().x() + dx * r, initial_.translation().y() + dy * r,
              initial_.angle() + (a - n) * angular_step_);
}

void BranchAndBoundSearch::descend(std::span<Candidate> candidates, int h, const Exclusion& ex,
                                   Candidate& best, std::size_t& scored) const {
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& x, const Candidate& y) { return x.score > y.score; });
  for (const Candidate& c : candidates) {
    if (c.score <= best.score) break;  // sorted: nothing after it can win
    if (h == 0) {
      if (ex.contains(c.dx, c.dy)) continue;
      best = c;
      break;
    }
    const int half = 1 << (h - 1);
    std::array<Candidate, 4> children;
    std::size_t n = 0;
    for (const int ox : {0, half}) {
      for (const int oy : {0, half}) {
        const int dx = c.dx + ox, dy = c.dy + oy;
        if (dx > linear_cells_ || dy > linear_cells_) continue;
        children[n++] = {c.a, dx, dy, unchecked_score(h - 1, c.a, dx, dy)};
        ++scored;
      }
    }
    descend(std::span<Candidate>(children.data(), n), h - 1, ex, best, scored);
  }
}

BranchAndBoundResult BranchAndBoundSearch::search(double min_score, const Eigen::Vector2d& exclude_center,
                                                  double exclude_radius) const {
  ROVE_CHECK_MSG(std::isfinite(exclude_radius) && exclude_radius >= 0.0,
                 "exclude_radius {} must be >= 0", exclude_radius);
  Exclusion ex;
  ex.center_cells = (exclude_center - initial_.translation()) / grids_.resolution();
  ex.radius_cells = exclude_radius / grids_.resolution();
  BranchAndBoundResult res;
  res.T_grid_robot = initial_;
  res.angles = scans_.size();
  res.linear_cells = linear_cells_;
  res.angular_step = angular_step_;
  const int top = grids_.depth();
  const int step = 1 << top;
  std::vector<Candidate> roots;
  for (int a = 0; a < num_angles(); ++a) {
    for (int dx = -linear_cells_; dx <= linear_cells_; dx += step) {
      for (int dy = -linear_cells_; dy <= linear_cells_; dy += step) {
        roots.push_back({a, dx, dy, unchecked_score(top, a, dx, dy)});
      }
    }
  }
  std::size_t scored = roots.size();
  Candidate best{-1, 0, 0, min_score};
  descend(roots, top, ex, best, scored);
  res.candidates_scored = scored;
  if (best.a >= 0) {
    res.found = true;
    res.score = best.score;
    res.T_grid_robot = pose(best.a, best.dx, best.dy);
  }
  return res;
}

BranchAndBoundResult branch_and_bound_match(const PrecomputedGridStack& grids,
                                            std::span<const Eigen::Vector2d> points_robot,
                                            const SE2d& initial_T_grid_robot,
                                            const BranchAndBoundWindow& window, double min_score) {
  return BranchAndBoundSearch(grids, points_robot, initial_T_grid_robot, window).search(min_score);
}

}  // namespace rove
