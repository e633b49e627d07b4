#pragma once
/// \file
/// A picture of a localization: the occupancy grid with the particles, the
/// estimated path and (if known) the ground truth, as an 8-bit palette PNG
/// written with the grid image code of rove::maps.

#include <string>
#include <vector>

#include "rove/maps/occupancy_grid.h"
#include "rove/math/se2.h"
#include "rove/poses/pose2.h"

namespace rove {

/// Options of render_localization_png.
struct LocalizationImageOptions {
  /// Largest image side, pixels (≥ 16): a larger grid is drawn with one
  /// pixel for every k × k cells.
  int max_side = 4096;
  /// Side of the start and end markers, pixels (odd, ≥ 1).
  int marker = 7;
};

/// Draws the grid (gray: white free, black occupied, mid-gray unknown; 128
/// levels), the particles (orange pixels), the ground truth (magenta
/// line), the path of the estimates (red line; its start a green square,
/// its end a blue one), +x right, +y up. Poses outside the grid are
/// clipped. Throws IoError if the file cannot be written and
/// InvalidArgument on bad options or an empty grid.
void render_localization_png(const std::string& path, const OccupancyGrid& grid,
                             const std::vector<SE2d>& particles,
                             const std::vector<Pose2>& estimated_path,
                             const std::vector<Pose2>& ground_truth = {},
                             const LocalizationImageOptions& options = {});

}  // namespace rove
