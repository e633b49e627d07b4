#pragma once
/// \file
/// Voxel-grid down-sampling: one point per occupied voxel, at the centroid of
/// the points inside it (PCL's VoxelGrid).
///
/// Voxel assignment follows PCL exactly, so both libraries put every point
/// in the same voxel: with inv = 1.0f / leaf (float), a point's voxel index
/// on an axis is floor(x * inv) evaluated in float. Output order is PCL's:
/// voxels sorted by the linear index (x fastest, then y, then z) relative
/// to the smallest occupied voxel.
///
/// Unlike PCL, whose 32-bit linear index forces it to give up (returning the
/// input unchanged) when the grid has more than 2^31 cells, the index here
/// is 64-bit and a grid larger than 2^64 cells is still handled, by sorting
/// index triples: no leaf size is "too small" short of the per-axis index
/// leaving the int64 range, which is rejected with InvalidArgument.
///
/// Points with a non-finite coordinate are skipped. Centroids are summed in
/// double (PCL sums in float). With `average_channels`, colors, intensities
/// and normals are averaged as well (colors rounded to the nearest integer;
/// normals averaged then re-normalized, kept as (0,0,0) if they cancel).

#include <cstddef>

#include <Eigen/Core>

#include "rove/maps/point_cloud.h"

namespace rove {

/// Options of voxel_grid_filter.
struct VoxelGridOptions {
  /// Voxel edge lengths along x, y, z, meters; each finite and > 0.
  Eigen::Vector3f leaf_size{0.1f, 0.1f, 0.1f};
  /// Voxels holding fewer points than this are dropped (PCL's
  /// setMinimumPointsNumberPerVoxel; 0 and 1 keep every voxel).
  std::size_t min_points_per_voxel = 0;
  /// Average the color/intensity/normal channels too (PCL's
  /// setDownsampleAllData, default true). Otherwise the output has no channels.
  bool average_channels = true;
};

/// Result of voxel_grid_filter.
struct VoxelGridResult {
  PointCloud cloud;                 ///< one point per kept voxel
  std::size_t finite_input = 0;     ///< input points with finite coordinates
  std::size_t occupied_voxels = 0;  ///< voxels with at least one point
  std::size_t dropped_voxels = 0;   ///< voxels under min_points_per_voxel
};

/// Down-samples `cloud` (see the file comment). Preconditions
/// (InvalidArgument): leaf sizes finite and > 0, and every finite
/// coordinate divided by its leaf size within ±2^62.
VoxelGridResult voxel_grid_filter(const PointCloud& cloud, const VoxelGridOptions& options = {});

/// Shortcut: the down-sampled cloud with a cubic leaf of `leaf_size` meters.
PointCloud voxel_downsample(const PointCloud& cloud, float leaf_size);

}  // namespace rove
