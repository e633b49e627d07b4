#pragma once
/// \file
/// Comparing an optimized graph with ground truth.

#include <cstddef>

#include "rove/graph/pose_graph.h"

namespace rove {

/// Position error of an estimate against ground truth after the rigid
/// alignment that minimizes it (Horn/Umeyama without scale: Umeyama,
/// "Least-squares estimation of transformation parameters between two point
/// patterns", PAMI 1991, Eqs. 38–42).
struct AlignedPositionError {
  std::size_t matched = 0;  ///< vertices present in both graphs
  double rmse = 0.0;        ///< root mean square position error (m) after alignment
  double max = 0.0;         ///< largest position error (m) after alignment
};

/// Aligns `estimate` onto `truth` over their common vertex ids and returns
/// the position errors. Throws InvalidArgument if fewer than 3 ids are common.
AlignedPositionError aligned_position_error(const PoseGraph2D& estimate, const PoseGraph2D& truth);
/// 3D overload.
AlignedPositionError aligned_position_error(const PoseGraph3D& estimate, const PoseGraph3D& truth);

}  // namespace rove
