#pragma once
/// \file
/// Branch-and-bound correlative scan matching over multi-resolution max
/// grids (Olson, "Real-time correlative scan matching", ICRA 2009; Hess et
/// al., "Real-Time Loop Closure in 2D LIDAR SLAM", ICRA 2016, Sec. V):
/// the pose in a search window around an initial guess that maximizes the
/// mean occupancy probability of the grid cells under a scan's points,
/// found exactly (on the window's lattice) without scoring every pose.
///
/// The window is a lattice: angles θ₀ + k·δθ for |k| <= ⌈W_θ/δθ⌉ with
/// δθ = arccos(1 − r²/(2·d_max²)) (Hess Eq. 7: the farthest point moves by
/// at most one cell r; d_max may be capped, BranchAndBoundWindow), and
/// translations by whole cells up to ⌈W_x/r⌉ from
/// the initial one. A candidate of height h covers 2^h × 2^h translations;
/// its bound is its score on the precomputed grid of height h, whose cell
/// (x, y) holds the largest probability of the cells [x, x+2^h) × [y, y+2^h)
/// of the original grid (Hess Eq. 14). That bound is admissible: no pose
/// below a candidate scores more than it, so the depth-first search,
/// best-first at each level and pruning at the best score found, returns
/// the best pose of the window (Hess Algorithm 3).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/slam/probability_grid.h"

namespace rove {

/// The precomputed max grids of heights 0..depth of a ProbabilityGrid, with
/// the probabilities quantized to 8 bits over [kMinProbability,
/// kMaxProbability] (unknown as kMinProbability). Thread-safety: immutable
/// after construction.
class PrecomputedGridStack {
 public:
  /// Builds heights 0..depth of `grid`. Preconditions (InvalidArgument):
  /// 0 <= depth <= 16.
  PrecomputedGridStack(const ProbabilityGrid& grid, int depth);

  /// The highest height.
  int depth() const noexcept { return static_cast<int>(levels_.size()) - 1; }
  /// Cell side, meters (the source grid's).
  double resolution() const noexcept { return resolution_; }
  /// The source grid's offset (its cell (0, 0) on the lattice).
  const Eigen::Vector2i& offset() const noexcept { return offset_; }
  /// The 8-bit value of height h at cell (cx, cy) of the source grid's
  /// storage: the largest of the source cells [cx, cx+2^h) × [cy, cy+2^h)
  /// (0 for none). Precondition: 0 <= h <= depth() (unchecked).
  std::uint8_t value(int h, int cx, int cy) const noexcept {
    const Level& l = levels_[static_cast<std::size_t>(h)];
    const unsigned x = static_cast<unsigned>(cx + l.pad), y = static_cast<unsigned>(cy + l.pad);
    if (x >= static_cast<unsigned>(l.width) || y >= static_cast<unsigned>(l.height)) return 0;
    return l.cells[static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * static_cast<std::size_t>(l.width)];
  }
  /// The sum of value(h, c.x() + dx, c.y() + dy) over `cells`, whose
  /// bounding box is [lo, hi] (inclusive, as computed by the caller: the
  /// per-cell range checks are skipped when the shifted box lies inside
  /// height h's array). Precondition: 0 <= h <= depth() (unchecked).
  std::uint32_t sum_values(int h, std::span<const Eigen::Vector2i> cells, const Eigen::Vector2i& lo,
                           const Eigen::Vector2i& hi, int dx, int dy) const noexcept;
  /// The probability an 8-bit value stands for.
  static double to_probability(double value) noexcept {
    return ProbabilityGrid::kMinProbability +
           (ProbabilityGrid::kMaxProbability - ProbabilityGrid::kMinProbability) * value / 255.0;
  }
  /// The 8-bit value of a probability (clamped to the grid's range).
  static std::uint8_t to_value(float probability) noexcept;
  /// Bytes held.
  std::size_t memory_bytes() const noexcept;

 private:
  struct Level {
    int pad = 0, width = 0, height = 0;  // cell (cx, cy) at (cx + pad, cy + pad)
    std::vector<std::uint8_t> cells;
  };
  std::vector<Level> levels_;
  double resolution_;
  Eigen::Vector2i offset_;
};

/// The search window of branch_and_bound_match.
struct BranchAndBoundWindow {
  /// Half-width of the translation window, meters, >= 0.
  double linear = 7.0;
  /// Half-width of the rotation window, radians, in [0, π].
  double angular = 30.0 * 3.14159265358979323846 / 180.0;
  /// The farthest point range used for the angular step (meters, > 0):
  /// d_max is min(farthest point, this). A step computed from a few far
  /// returns multiplies the angles to score; with a cap, points beyond it
  /// may fall a cell or two off the best angle, which the refinement after
  /// the search recovers. Default: no cap.
  double step_range_cap = 1e9;
  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Result of a branch-and-bound search.
struct BranchAndBoundResult {
  /// True when a pose scored above the minimum score.
  bool found = false;
  /// The best pose (the initial guess when not found).
  SE2d T_grid_robot;
  /// Its score: mean probability under the points (0 when not found).
  double score = 0.0;
  /// Candidates scored (all heights), and the lattice's size.
  std::size_t candidates_scored = 0;
  std::size_t angles = 0;
  int linear_cells = 0;
  /// The angular step δθ, radians.
  double angular_step = 0.0;
};

/// The lattice of a search and the scores of its candidates (exposed for
/// tests of the bound). Holds the scan discretized at every angle.
/// Thread-safety: immutable after construction.
class BranchAndBoundSearch {
 public:
  /// Discretizes `points_robot` (robot frame, meters; non-finite skipped)
  /// at every angle of the window around `initial_T_grid_robot`.
  /// Preconditions (InvalidArgument): window.check(); some finite point.
  BranchAndBoundSearch(const PrecomputedGridStack& grids, std::span<const Eigen::Vector2d> points_robot,
                       const SE2d& initial_T_grid_robot, const BranchAndBoundWindow& window);

  /// Angles of the lattice (index 0 is the most negative).
  int num_angles() const noexcept { return static_cast<int>(scans_.size()); }
  /// Translations go from −linear_cells() to +linear_cells() cells.
  int linear_cells() const noexcept { return linear_cells_; }
  /// Angular step, radians.
  double angular_step() const noexcept { return angular_step_; }
  /// Score of the candidate of height h at angle index `a` and cell offset
  /// (dx, dy): the mean of the height-h grid's probabilities under the
  /// points (for h = 0, the pose's score). Preconditions: 0 <= h <= depth,
  /// 0 <= a < num_angles() (unchecked beyond a check of h and a).
  double score(int h, int a, int dx, int dy) const;
  /// The pose of a leaf candidate.
  SE2d pose(int a, int dx, int dy) const;
  /// The best leaf whose score exceeds `min_score` (found = false if none).
  /// With `exclude_radius` > 0, leaves whose translation lies within that
  /// many meters of `exclude_center` (T_grid_robot's translation) are
  /// passed over: the best pose elsewhere in the window, to measure how
  /// distinct a match is (a corridor, a row of identical rooms).
  BranchAndBoundResult search(double min_score, const Eigen::Vector2d& exclude_center = {},
                              double exclude_radius = 0.0) const;

 private:
  struct Candidate {
    int a, dx, dy;
    double score;
  };
  double score_sum(int h, int a, int dx, int dy) const;
  double unchecked_score(int h, int a, int dx, int dy) const;
  struct Exclusion {
    Eigen::Vector2d center_cells = Eigen::Vector2d::Zero();  // from the initial pose
    double radius_cells = 0.0;
    bool contains(int dx, int dy) const {
      return radius_cells > 0.0 && (Eigen::Vector2d(dx, dy) - center_cells).norm() <= radius_cells;
    }
  };
  void descend(std::span<Candidate> candidates, int h, const Exclusion& ex, Candidate& best,
               std::size_t& scored) const;

  const PrecomputedGridStack& grids_;
  std::vector<std::vector<Eigen::Vector2i>> scans_;  // per angle: cells at zero offset
  std::vector<std::pair<Eigen::Vector2i, Eigen::Vector2i>> boxes_;  // per angle: cells' bounding box
  SE2d initial_;
  double angular_step_ = 0.0;
  int linear_cells_ = 0;
  std::size_t points_ = 0;
};

/// Convenience: the best pose in `window` around `initial_T_grid_robot`
/// scoring more than `min_score`.
BranchAndBoundResult branch_and_bound_match(const PrecomputedGridStack& grids,
                                            std::span<const Eigen::Vector2d> points_robot,
                                            const SE2d& initial_T_grid_robot,
                                            const BranchAndBoundWindow& window, double min_score);

}  // namespace rove
