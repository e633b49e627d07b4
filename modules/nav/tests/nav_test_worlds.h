#pragma once
// Small worlds for the navigation tests, built from obstacle masks.

#include <cstdint>
#include <random>
#include <vector>

#include "rove/nav/navigation_grid.h"

namespace rove::nav_test {

/// An empty room of w × h cells of `res` meters with its lower-left
/// corner at the origin (the outside of the grid is the wall).
inline NavigationGrid empty_room(std::uint32_t w, std::uint32_t h, double res) {
  return NavigationGrid::from_mask(w, h, 0.0, 0.0, res, std::vector<std::uint8_t>(std::size_t{w} * h, 0));
}

/// A room with random obstacle cells (each with probability p).
inline NavigationGrid random_world(std::uint32_t w, std::uint32_t h, double res, double p,
                                   std::uint64_t seed, double x_min = -1.0, double y_min = 2.0) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution occupied(p);
  std::vector<std::uint8_t> mask(std::size_t{w} * h);
  for (auto& m : mask) m = occupied(rng) ? 1 : 0;
  return NavigationGrid::from_mask(w, h, x_min, y_min, res, std::move(mask));
}

/// A room of w × h cells split by a wall at column `wall_x` with a gap of
/// `gap` cells starting at row `gap_y`.
inline NavigationGrid wall_with_gap(std::uint32_t w, std::uint32_t h, double res, std::uint32_t wall_x,
                                    std::uint32_t gap_y, std::uint32_t gap) {
  std::vector<std::uint8_t> mask(std::size_t{w} * h, 0);
  for (std::uint32_t y = 0; y < h; ++y) {
    if (y >= gap_y && y < gap_y + gap) continue;
    mask[wall_x + std::size_t{y} * w] = 1;
  }
  return NavigationGrid::from_mask(w, h, 0.0, 0.0, res, std::move(mask));
}

}  // namespace rove::nav_test
