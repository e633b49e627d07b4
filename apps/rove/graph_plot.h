#pragma once
/// \file
/// PNG plot of a 2D pose graph before and after optimization (for
/// `rove graph-slam --plot`): two panels side by side on the same scale,
/// written by the maps module's PNG writer as a palette PNG: odometry edges
/// (consecutive ids) in blue, other edges in light red, vertices in black,
/// anchors as green discs.

#include <string>

#include "rove/graph/pose_graph.h"

namespace rove::cli {

/// Writes `path` atomically (a temporary file renamed when complete) as an
/// 8-bit palette PNG with `panel_px` square panels. Throws IoError if the file
/// cannot be written, InvalidArgument if panel_px is outside [64, 8192].
void write_graph_plot(const PoseGraph2D& before, const PoseGraph2D& after,
                      const std::string& path, int panel_px = 800);

}  // namespace rove::cli
