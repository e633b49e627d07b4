#include "rove/maps/occupancy_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/memory_budget.h"

namespace rove {
namespace {

constexpr double kMaxCells = 2147483648.0;  // 2^31

// Refuses a grid of nx × ny cells that rove cannot index (2^31 cells) or
// that exceeds the memory budget, before it is allocated.
template <GridCell Cell>
void check_grid_size(float nx, float ny, float resolution) {
  const std::string what = fmt::format("an occupancy grid of {} \u00d7 {} cells of {} m", nx, ny, resolution);
  if (!(static_cast<double>(nx) * ny <= kMaxCells)) {
    throw ResourceError(fmt::format("{} is above rove's limit of 2^31 cells", what));
  }
  check_memory_budget(
      checked_bytes(static_cast<std::uint64_t>(nx) * static_cast<std::uint64_t>(ny), sizeof(Cell)),
      what);
}

void check_probability(float p) {
  ROVE_CHECK_MSG(p >= 0.0f && p <= 1.0f, "probability {} is outside [0, 1]", p);
}

}  // namespace

template <GridCell Cell>
OccupancyGridT<Cell>::OccupancyGridT() : OccupancyGridT(-20.0f, 20.0f, -20.0f, 20.0f, 0.05f) {}

template <GridCell Cell>
OccupancyGridT<Cell>::OccupancyGridT(float x_min, float x_max, float y_min, float y_max,
                                     float resolution, float p_free) {
  set_size(x_min, x_max, y_min, y_max, resolution, p_free);
}

template <GridCell Cell>
void OccupancyGridT<Cell>::set_size(float x_min, float x_max, float y_min, float y_max,
                                    float resolution, float p_free) {
  ROVE_CHECK_FINITE(x_min);
  ROVE_CHECK_FINITE(x_max);
  ROVE_CHECK_FINITE(y_min);
  ROVE_CHECK_FINITE(y_max);
  ROVE_CHECK_FINITE(resolution);
  ROVE_CHECK_GT(resolution, 0.0f);
  ROVE_CHECK_GT(x_max, x_min);
  ROVE_CHECK_GT(y_max, y_min);
  check_probability(p_free);
  // Snap the limits to whole cells (MRPT: res · round(v / res), float).
  const float xmin = resolution * std::round(x_min / resolution);
  const float ymin = resolution * std::round(y_min / resolution);
  const float xmax = resolution * std::round(x_max / resolution);
  const float ymax = resolution * std::round(y_max / resolution);
  const float nx = std::round((xmax - xmin) / resolution);
  const float ny = std::round((ymax - ymin) / resolution);
  check_grid_size<Cell>(nx, ny, resolution);
  x_min_ = xmin;
  x_max_ = xmax;
  y_min_ = ymin;
  y_max_ = ymax;
  resolution_ = resolution;
  size_x_ = static_cast<std::uint32_t>(nx);
  size_y_ = static_cast<std::uint32_t>(ny);
  cells_.assign(static_cast<std::size_t>(size_x_) * size_y_,
                LogOddsLut<Cell>::instance().p2l(p_free));
  empty_ = true;
  ++revision_;
}

template <GridCell Cell>
void OccupancyGridT<Cell>::resize(float new_x_min, float new_x_max, float new_y_min,
                                  float new_y_max, float p_free, bool additional_margin) {
  ROVE_CHECK_FINITE(new_x_min);
  ROVE_CHECK_FINITE(new_x_max);
  ROVE_CHECK_FINITE(new_y_min);
  ROVE_CHECK_FINITE(new_y_max);
  ROVE_CHECK_LE(new_x_min, new_x_max);
  ROVE_CHECK_LE(new_y_min, new_y_max);
  check_probability(p_free);
  if (new_x_min >= x_min_ && new_y_min >= y_min_ && new_x_max <= x_max_ && new_y_max <= y_max_) {
    return;
  }
  if (additional_margin) {
    if (new_x_min < x_min_) new_x_min = std::floor(new_x_min - 4.0f);
    if (new_x_max > x_max_) new_x_max = std::ceil(new_x_max + 4.0f);
    if (new_y_min < y_min_) new_y_min = std::floor(new_y_min - 4.0f);
    if (new_y_max > y_max_) new_y_max = std::ceil(new_y_max + 4.0f);
  }
  new_x_min = std::min(new_x_min, x_min_);
  new_x_max = std::max(new_x_max, x_max_);
  new_y_min = std::min(new_y_min, y_min_);
  new_y_max = std::max(new_y_max, y_max_);
  const float res = resolution_;
  // Snap a limit to whole cells unless it is already within 5% of a cell
  // boundary (MRPT's rule; keeps the existing limits untouched).
  const auto snap = [res](float v) {
    const float q = v / res;
    return std::fabs(q - std::round(q)) > 0.05f ? res * std::round(q) : v;
  };
  new_x_min = snap(new_x_min);
  new_y_min = snap(new_y_min);
  new_x_max = snap(new_x_max);
  new_y_max = snap(new_y_max);
  const float extra_x = std::round((x_min_ - new_x_min) / res);
  const float extra_y = std::round((y_min_ - new_y_min) / res);
  const float nx = std::round((new_x_max - new_x_min) / res);
  const float ny = std::round((new_y_max - new_y_min) / res);
  check_grid_size<Cell>(nx, ny, res);
  const auto off_x = static_cast<std::uint32_t>(extra_x);
  const auto off_y = static_cast<std::uint32_t>(extra_y);
  const auto new_size_x = static_cast<std::uint32_t>(nx);
  const auto new_size_y = static_cast<std::uint32_t>(ny);
  ROVE_CHECK_GE(new_size_x, size_x_ + off_x);
  ROVE_CHECK_GE(new_size_y, size_y_ + off_y);
  const Cell fill = LogOddsLut<Cell>::instance().p2l(p_free);
  const std::size_t n_new = static_cast<std::size_t>(new_size_x) * new_size_y;
  if (cells_.capacity() < n_new) {
    // A grid that grows once tends to grow again (mapping): half again as
    // much capacity lets the next growths move rows in place, without a new
    // allocation, its page faults, and a fill of the copied cells. Capacity
    // that is never used is never touched, so it costs address space only;
    // where even that is refused, the grid gets exactly its size.
    std::vector<Cell> grown;
    try {
      grown.reserve(n_new + n_new / 2);
    } catch (const std::bad_alloc&) {
      grown.reserve(n_new);
    }
    grown.assign(n_new, fill);
    for (std::uint32_t y = 0; y < size_y_; ++y) {
      std::memcpy(&grown[off_x + static_cast<std::size_t>(y + off_y) * new_size_x],
                  &cells_[static_cast<std::size_t>(y) * size_x_], size_x_ * sizeof(Cell));
    }
    cells_.swap(grown);
  } else {
    // In place: row y moves from y·sx to (y + off_y)·sx' + off_x, never to
    // a lower index (sx' >= sx, offsets >= 0), so moving rows from the last
    // to the first never overwrites a row still to be moved. Then every
    // cell outside the moved rows gets the fill value.
    const std::size_t n_old = cells_.size();
    cells_.resize(n_new, fill);
    Cell* c = cells_.data();
    for (std::uint32_t y = size_y_; y-- > 0;) {
      std::memmove(c + off_x + static_cast<std::size_t>(y + off_y) * new_size_x,
                   c + static_cast<std::size_t>(y) * size_x_, size_x_ * sizeof(Cell));
    }
    const auto fill_range = [&](std::size_t from, std::size_t to) {
      to = std::min(to, n_old);  // the tail is filled already
      if (from < to) std::fill(c + from, c + to, fill);
    };
    fill_range(0, static_cast<std::size_t>(off_y) * new_size_x + off_x);
    for (std::uint32_t y = 0; y < size_y_; ++y) {
      const std::size_t row = static_cast<std::size_t>(y + off_y) * new_size_x;
      const std::size_t next = y + 1 < size_y_ ? row + new_size_x + off_x : n_new;
      fill_range(row + off_x + size_x_, next);
    }
  }
  x_min_ = new_x_min;
  x_max_ = new_x_max;
  y_min_ = new_y_min;
  y_max_ = new_y_max;
  size_x_ = new_size_x;
  size_y_ = new_size_y;
  ++revision_;
}

template <GridCell Cell>
Cell OccupancyGridT<Cell>::cell(int cx, int cy) const {
  ROVE_CHECK_MSG(contains(cx, cy), "cell ({}, {}) is outside the {} x {} grid", cx, cy, size_x_,
                 size_y_);
  return cells_[index(cx, cy)];
}

template <GridCell Cell>
void OccupancyGridT<Cell>::set_cell(int cx, int cy, Cell value) {
  ROVE_CHECK_MSG(contains(cx, cy), "cell ({}, {}) is outside the {} x {} grid", cx, cy, size_x_,
                 size_y_);
  cells_[index(cx, cy)] = value;
  ++revision_;
}

template <GridCell Cell>
void OccupancyGridT<Cell>::set_free_probability(int cx, int cy, float p) {
  check_probability(p);
  if (!contains(cx, cy)) return;
  cells_[index(cx, cy)] = LogOddsLut<Cell>::instance().p2l(p);
  ++revision_;
}

template <GridCell Cell>
void OccupancyGridT<Cell>::fill(float p) {
  check_probability(p);
  std::fill(cells_.begin(), cells_.end(), LogOddsLut<Cell>::instance().p2l(p));
  ++revision_;
}

template <GridCell Cell>
void OccupancyGridT<Cell>::update_cell(int cx, int cy, float p) {
  check_probability(p);
  if (!contains(cx, cy)) return;
  Cell& c = cells_[index(cx, cy)];
  const int obs = LogOddsLut<Cell>::instance().p2l(p);
  const int v = c;
  // Saturating add in the cell's range (MRPT's updateCell).
  if (obs > 0) {
    c = static_cast<Cell>(v > Traits::kMax - obs ? Traits::kMax : v + obs);
  } else {
    c = static_cast<Cell>(v < Traits::kMin - obs ? Traits::kMin : v + obs);
  }
  ++revision_;
}

template <GridCell Cell>
void OccupancyGridT<Cell>::assign(float x_min, float x_max, float y_min, float y_max,
                                  float resolution, std::uint32_t size_x, std::uint32_t size_y,
                                  std::vector<Cell> cells) {
  ROVE_CHECK_FINITE(x_min);
  ROVE_CHECK_FINITE(x_max);
  ROVE_CHECK_FINITE(y_min);
  ROVE_CHECK_FINITE(y_max);
  ROVE_CHECK_FINITE(resolution);
  ROVE_CHECK_GT(resolution, 0.0f);
  ROVE_CHECK_EQ(cells.size(), static_cast<std::size_t>(size_x) * size_y);
  x_min_ = x_min;
  x_max_ = x_max;
  y_min_ = y_min;
  y_max_ = y_max;
  resolution_ = resolution;
  size_x_ = size_x;
  size_y_ = size_y;
  cells_ = std::move(cells);
  ++revision_;
}

template class OccupancyGridT<std::int8_t>;
template class OccupancyGridT<std::int16_t>;

}  // namespace rove
