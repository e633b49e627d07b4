#pragma once
/// \file
/// PNG plot of an ATE evaluation (`rove eval ate --plot`): the reference
/// (dark gray) and the aligned estimate (blue) seen from above with the
/// error of each pair (light red) on the left; the position error over time
/// on the right (axes in black, zero at the bottom). A palette PNG.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace rove::cli {

/// Writes `path` atomically. `reference`, `estimate`, `times` and `errors`
/// are per associated pair (same size, at least 1). Throws InvalidArgument
/// for mismatched sizes or panel_px outside [64, 8192], IoError if the file
/// cannot be written.
void write_ate_plot(const std::vector<Eigen::Vector3d>& reference,
                    const std::vector<Eigen::Vector3d>& estimate, const std::vector<double>& times,
                    const std::vector<double>& errors, const std::string& path, int panel_px = 800);

}  // namespace rove::cli
