#include "rove/maps/grid_agreement.h"

#include "rove/core/check.h"

namespace rove {

GridAgreement grid_agreement(const OccupancyGrid& grid, const OccupancyGrid& reference,
                             const GridAgreementOptions& options) {
  ROVE_CHECK_MSG(options.known_margin >= 0.0 && options.known_margin < 0.5,
                 "known_margin = {} is outside [0, 0.5)", options.known_margin);
  ROVE_CHECK_MSG(options.wall_tolerance_cells >= 0 && options.wall_tolerance_cells <= 100,
                 "wall_tolerance_cells = {} is outside [0, 100]", options.wall_tolerance_cells);
  const double lo = 0.5 - options.known_margin, hi = 0.5 + options.known_margin;
  const int tol = options.wall_tolerance_cells;
  GridAgreement r;
  for (std::uint32_t y = 0; y < grid.size_y(); ++y) {
    for (std::uint32_t x = 0; x < grid.size_x(); ++x) {
      const double p = grid.free_probability(static_cast<int>(x), static_cast<int>(y));
      if (p > lo && p < hi) continue;
      const double wx = grid.idx_to_x(x), wy = grid.idx_to_y(y);
      const int rx = reference.x_to_idx_clamped(wx), ry = reference.y_to_idx_clamped(wy);
      const double q = reference.free_probability(rx, ry);
      const bool known = q <= lo || q >= hi;
      if (known) {
        ++r.compared;
        r.agreeing += (p < 0.5) == (q < 0.5) ? 1 : 0;
      }
      if (p >= lo) continue;
      ++r.occupied;
      bool matched = false;
      for (int dy = -tol; dy <= tol && !matched; ++dy) {
        for (int dx = -tol; dx <= tol && !matched; ++dx) {
          matched = reference.free_probability(rx + dx, ry + dy) <= lo;
        }
      }
      r.occupied_matched += matched ? 1 : 0;
      r.occupied_known += known ? 1 : 0;
      r.occupied_known_matched += known && matched ? 1 : 0;
    }
  }
  return r;
}

}  // namespace rove
