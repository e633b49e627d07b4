#include "rove/slam/probability_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/memory_budget.h"

namespace rove {
namespace {

// Lattice cells beyond which coordinates are refused (well inside int).
constexpr double kMaxLattice = 1 << 30;
constexpr std::uint64_t kMaxCells = std::uint64_t{1} << 28;

double odds(double p) { return p / (1.0 - p); }
double probability_from_odds(double o) { return o / (1.0 + o); }

// The table of an odds update: for every unmarked value, the updated value
// with the update marker set (Hess et al. 2016, Eq. 3).
std::vector<std::uint16_t> update_table(double p) {
  std::vector<std::uint16_t> t(ProbabilityGrid::kUpdateMarker);
  t[ProbabilityGrid::kUnknown] = static_cast<std::uint16_t>(
      ProbabilityGrid::probability_to_value(static_cast<float>(p)) | ProbabilityGrid::kUpdateMarker);
  for (unsigned v = 1; v < ProbabilityGrid::kUpdateMarker; ++v) {
    const double old = ProbabilityGrid::value_to_probability(static_cast<std::uint16_t>(v));
    const double updated = probability_from_odds(odds(old) * odds(p));
    t[v] = static_cast<std::uint16_t>(
        ProbabilityGrid::probability_to_value(static_cast<float>(updated)) |
        ProbabilityGrid::kUpdateMarker);
  }
  return t;
}

// Applies `table` to the cell at `i` unless it was updated during this
// insertion already; remembers it for clearing the markers.
inline void apply(std::uint16_t* cells, std::size_t i, const std::uint16_t* table,
                  std::vector<std::size_t>& touched) {
  std::uint16_t& c = cells[i];
  if (c & ProbabilityGrid::kUpdateMarker) return;
  c = table[c];
  touched.push_back(i);
}

// Calls visit(cx, cy) for the cells the segment from u0 to u1 (continuous
// cell coordinates: cell (i, j) is [i, i+1) × [j, j+1)) crosses, from the
// cell of u0 up to, but excluding, the cell of u1 (Amanatides & Woo, "A fast
// voxel traversal algorithm for ray tracing", Eurographics 1987).
template <typename Visit>
void trace_segment(const Eigen::Vector2d& u0, const Eigen::Vector2d& u1, Visit&& visit) {
  int ix = static_cast<int>(std::floor(u0.x())), iy = static_cast<int>(std::floor(u0.y()));
  const int ex = static_cast<int>(std::floor(u1.x())), ey = static_cast<int>(std::floor(u1.y()));
  const int n = std::abs(ex - ix) + std::abs(ey - iy);
  const Eigen::Vector2d d = u1 - u0;
  const int step_x = d.x() > 0 ? 1 : -1, step_y = d.y() > 0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double delta_x = d.x() != 0 ? std::abs(1.0 / d.x()) : kInf;
  const double delta_y = d.y() != 0 ? std::abs(1.0 / d.y()) : kInf;
  double t_x = d.x() != 0 ? (d.x() > 0 ? ix + 1 - u0.x() : u0.x() - ix) * delta_x : kInf;
  double t_y = d.y() != 0 ? (d.y() > 0 ? iy + 1 - u0.y() : u0.y() - iy) * delta_y : kInf;
  for (int k = 0; k < n; ++k) {
    visit(ix, iy);
    if (t_x < t_y) {
      t_x += delta_x;
      ix += step_x;
    } else {
      t_y += delta_y;
      iy += step_y;
    }
  }
}

}  // namespace

ProbabilityGrid::ProbabilityGrid(double resolution) : resolution_(resolution) {
  ROVE_CHECK_MSG(std::isfinite(resolution) && resolution > 0.0,
                 "grid resolution must be finite and > 0, got {}", resolution);
}

std::uint16_t ProbabilityGrid::probability_to_value(float p) {
  ROVE_CHECK_FINITE(p);
  const float c = std::clamp(p, kMinProbability, kMaxProbability);
  return static_cast<std::uint16_t>(
      1 + std::lround((c - kMinProbability) * ((kMaxValue - 1) / (kMaxProbability - kMinProbability))));
}

Eigen::Vector2i ProbabilityGrid::cell_of(const Eigen::Vector2d& p) const {
  const double ux = std::floor(p.x() / resolution_), uy = std::floor(p.y() / resolution_);
  ROVE_CHECK_MSG(std::abs(ux) < kMaxLattice && std::abs(uy) < kMaxLattice,
                 "point ({}, {}) is too far from the grid's origin", p.x(), p.y());
  return {static_cast<int>(ux) - offset_.x(), static_cast<int>(uy) - offset_.y()};
}

void ProbabilityGrid::set_probability(int cx, int cy, float p) {
  ROVE_CHECK_MSG(contains(cx, cy), "cell ({}, {}) is outside the {} x {} grid", cx, cy, size_x_,
                 size_y_);
  cells_[index(cx, cy)] = probability_to_value(p);
}

std::size_t ProbabilityGrid::known_cells() const noexcept {
  return static_cast<std::size_t>(
      std::count_if(cells_.begin(), cells_.end(), [](std::uint16_t v) { return v != kUnknown; }));
}

void ProbabilityGrid::grow_to_include(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                      double margin) {
  ROVE_CHECK_FINITE(lo);
  ROVE_CHECK_FINITE(hi);
  ROVE_CHECK_MSG(lo.x() <= hi.x() && lo.y() <= hi.y(), "box [{}, {}] x [{}, {}] is empty", lo.x(),
                 hi.x(), lo.y(), hi.y());
  ROVE_CHECK_MSG(std::isfinite(margin) && margin >= 0.0, "margin {} must be >= 0", margin);
  const double m = std::ceil(margin / resolution_);
  const Eigen::Vector2d need_lo = (lo / resolution_).array().floor();
  const Eigen::Vector2d need_hi = (hi / resolution_).array().floor();
  ROVE_CHECK_MSG(need_lo.cwiseAbs().maxCoeff() < kMaxLattice &&
                     need_hi.cwiseAbs().maxCoeff() < kMaxLattice,
                 "box [{}, {}] x [{}, {}] is too far from the grid's origin", lo.x(), hi.x(), lo.y(),
                 hi.y());
  Eigen::Vector2i new_lo = offset_, new_hi = offset_ + Eigen::Vector2i(size_x_, size_y_);
  bool grow = cells_.empty();
  for (int a = 0; a < 2; ++a) {
    const int size = a == 0 ? size_x_ : size_y_;
    // A side that grows gets the margin, and at least a quarter of the
    // current size, so that a moving robot does not copy the grid often.
    const double extra = std::max(m, std::floor(size / 4.0));
    if (cells_.empty()) {
      new_lo[a] = static_cast<int>(need_lo[a] - m);
      new_hi[a] = static_cast<int>(need_hi[a] + m) + 1;
      continue;
    }
    if (need_lo[a] < new_lo[a]) {
      new_lo[a] = static_cast<int>(need_lo[a] - extra);
      grow = true;
    }
    if (need_hi[a] >= new_hi[a]) {
      new_hi[a] = static_cast<int>(need_hi[a] + extra) + 1;
      grow = true;
    }
  }
  if (!grow) return;
  const Eigen::Vector2i size = new_hi - new_lo;
  const std::uint64_t n = static_cast<std::uint64_t>(size.x()) * static_cast<std::uint64_t>(size.y());
  ROVE_CHECK_MSG(n <= kMaxCells, "a {} x {} grid of {} m cells exceeds {} cells", size.x(),
                 size.y(), resolution_, kMaxCells);
  check_memory_budget(checked_bytes(n, sizeof(std::uint16_t)),
                      fmt::format("a {} x {} submap grid of {} m cells", size.x(), size.y(),
                                  resolution_));
  std::vector<std::uint16_t> cells(static_cast<std::size_t>(n), kUnknown);
  const Eigen::Vector2i shift = offset_ - new_lo;
  for (int cy = 0; cy < size_y_; ++cy) {
    std::copy_n(cells_.begin() + static_cast<std::ptrdiff_t>(index(0, cy)), size_x_,
                cells.begin() + static_cast<std::ptrdiff_t>(shift.x()) +
                    static_cast<std::ptrdiff_t>(cy + shift.y()) * size.x());
  }
  cells_ = std::move(cells);
  offset_ = new_lo;
  size_x_ = size.x();
  size_y_ = size.y();
}

void GridInsertionOdds::check() const {
  ROVE_CHECK_MSG(hit_probability > 0.5 && hit_probability < 1.0,
                 "hit_probability {} must lie in (0.5, 1)", hit_probability);
  ROVE_CHECK_MSG(miss_probability > 0.0 && miss_probability < 0.5,
                 "miss_probability {} must lie in (0, 0.5)", miss_probability);
}

GridInsertionOdds GridInsertionOdds::from_config(const ConfigSection& section) {
  GridInsertionOdds o;
  o.hit_probability = section.get_in_range("hit_probability", o.hit_probability, 0.5, 1.0);
  o.miss_probability = section.get_in_range("miss_probability", o.miss_probability, 0.0, 0.5);
  o.insert_free_space = section.get<bool>("insert_free_space", o.insert_free_space);
  if (!(o.hit_probability > 0.5 && o.hit_probability < 1.0)) {
    section.fail("hit_probability", "must lie strictly between 0.5 and 1");
  }
  if (!(o.miss_probability > 0.0 && o.miss_probability < 0.5)) {
    section.fail("miss_probability", "must lie strictly between 0 and 0.5");
  }
  return o;
}

GridScanInserter::GridScanInserter(const GridInsertionOdds& odds) : odds_(odds) {
  odds_.check();
  hit_table_ = update_table(odds_.hit_probability);
  miss_table_ = update_table(odds_.miss_probability);
}

std::size_t GridScanInserter::insert(ProbabilityGrid& grid, const Eigen::Vector2d& origin,
                                     std::span<const Eigen::Vector2d> hits,
                                     std::span<const Eigen::Vector2d> misses) const {
  ROVE_CHECK_FINITE(origin);
  Eigen::Vector2d lo = origin, hi = origin;
  const auto extend = [&](std::span<const Eigen::Vector2d> pts) {
    for (const auto& p : pts) {
      if (!p.allFinite()) continue;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  };
  extend(hits);
  if (odds_.insert_free_space) extend(misses);
  grid.grow_to_include(lo, hi);

  std::uint16_t* cells = grid.mutable_values().data();
  std::vector<std::size_t> touched;
  touched.reserve(hits.size() * 8);
  for (const auto& p : hits) {
    if (!p.allFinite()) continue;
    const Eigen::Vector2i c = grid.cell_of(p);
    apply(cells, grid.index(c.x(), c.y()), hit_table_.data(), touched);
  }
  if (odds_.insert_free_space) {
    const double inv = 1.0 / grid.resolution();
    const Eigen::Vector2d off = grid.offset().cast<double>();
    const Eigen::Vector2d u0 = origin * inv - off;
    const auto ray = [&](const Eigen::Vector2d& p) {
      if (!p.allFinite()) return;
      trace_segment(u0, p * inv - off, [&](int cx, int cy) {
        if (grid.contains(cx, cy)) apply(cells, grid.index(cx, cy), miss_table_.data(), touched);
      });
    };
    for (const auto& p : hits) ray(p);
    for (const auto& p : misses) ray(p);
  }
  for (const std::size_t i : touched) {
    cells[i] = static_cast<std::uint16_t>(cells[i] & ~ProbabilityGrid::kUpdateMarker);
  }
  return touched.size();
}

}  // namespace rove
