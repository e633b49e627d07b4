#pragma once
/// \file
/// A voxel size for registering a cloud when the user gave none: the
/// smallest "round" leaf (1, 2, 2.5 or 5 × a power of ten, 1 cm to 5 m) at
/// which the cloud keeps at most a given number of occupied voxels. With
/// 7,000 (what `rove align` asks), small_gicp's 70,000-point outdoor scan
/// gets 0.25 m, the PCL tutorial's 112,000-point room scan 0.2 m, and a cloud
/// that is already small none at all.
///
/// Why a count and not the extent alone: the cost of a registration grows
/// with the points it pairs, and the sampling bias of a voxel grid with its
/// leaf; a bound on the occupied voxels keeps the first small whatever the
/// scene's size, and picks the finest leaf that does.

#include <cstddef>
#include <span>

#include <Eigen/Core>

namespace rove {

/// Occupied voxels of side `leaf` (m, > 0) among the finite points.
std::size_t count_occupied_voxels(std::span<const Eigen::Vector3f> points, double leaf);

/// The smallest round leaf (m) at which `points` occupy at most
/// `max_voxels` voxels; 0 when the finite points already number at most
/// `max_voxels` (no down-sampling needed); the largest leaf of the ladder
/// (5 m) when none qualifies. Precondition: max_voxels ≥ 1.
double suggest_voxel_size(std::span<const Eigen::Vector3f> points, std::size_t max_voxels);

}  // namespace rove
