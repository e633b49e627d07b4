#pragma once
/// \file
/// PNG picture of an EKF-SLAM run (`rove kf-slam`), seen from above: the
/// ground-truth path (gray) and landmarks (green crosses) when known, the
/// estimated path (blue), and every mapped landmark (red dot) inside its
/// position-uncertainty ellipse (the x-y marginal at `quantiles` standard
/// deviations, orange). A palette PNG.

#include <string>

#include "rove/slam/kf_slam_run.h"

namespace rove::cli {

/// Writes `path` atomically as a square picture of `size_px` pixels.
/// Throws InvalidArgument if size_px is outside [64, 8192], IoError if the
/// file cannot be written.
void write_kf_slam_picture(const KfSlamResult& result, double quantiles, const std::string& path,
                           int size_px = 900);

}  // namespace rove::cli
