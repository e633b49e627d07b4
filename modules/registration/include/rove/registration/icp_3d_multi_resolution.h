#pragma once
/// \file
/// Coarse-to-fine 3D ICP / GICP: the two clouds are down-sampled on a voxel
/// grid at each level of a list (coarse first), prepared (KD-tree, normals or
/// covariances from `neighbors` points) and registered with icp_3d, each level
/// starting from the previous level's estimate, with a pairing gate of
/// `distance_factor` × the level's voxel size.
///
/// Why: at one coarse voxel size the cost's minimum is biased by the sampling
/// (on the small_gicp outdoor pair, 0.25 m alone leaves 0.2–0.7° of rotation
/// error); the coarse level gives a wide basin, the fine level an unbiased
/// minimum with a gate small enough to reject wrong pairs. This is the
/// multi-scale scheme of Segal et al. (GICP, RSS 2009, Sec. IV) and of
/// KISS-ICP's adaptive threshold reduced to a fixed schedule.
///
/// Thread-safety: a pure function of its arguments.

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/registration/icp_3d.h"

namespace rove {

/// Options of icp_3d_multi_resolution.
struct Icp3dMultiResolutionOptions {
  /// Voxel sizes, m, coarse to fine; 0 means the cloud as given (no
  /// down-sampling). Non-empty, each finite and ≥ 0. Default {0.25, 0.1}.
  std::vector<double> voxel_sizes = {0.25, 0.1};
  /// Pairing gate of a level = distance_factor × its voxel size (a level
  /// with voxel 0 uses `full_resolution_distance`). > 0. Default 3.
  double distance_factor = 3.0;
  /// Pairing gate of a level with voxel size 0, m, > 0. Default 0.15.
  double full_resolution_distance = 0.15;
  /// Neighbours (point included) for the normals / GICP covariances, ≥ 3.
  /// Default 10: on LiDAR scans a smaller neighbourhood keeps the local
  /// plane local (k = 20 spans several surfaces at 0.25 m).
  std::size_t neighbors = 10;
  /// ε of the GICP plane regularization (eigenvalues (ε, 1, 1)), in (0, 1].
  /// Default 1e-3.
  double gicp_epsilon = 1e-3;
  /// Everything else of each level's icp_3d (method, tolerances, kernel,
  /// threads, ...). Its max_correspondence_distance is replaced per level.
  /// Defaults as Icp3dOptions but tighter step tolerances: 0.01°, 1e-4 m.
  Icp3dOptions icp = [] {
    Icp3dOptions o;
    o.rotation_epsilon = 0.01 * 3.14159265358979323846 / 180.0;
    o.translation_epsilon = 1e-4;
    return o;
  }();

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Result of icp_3d_multi_resolution.
struct Icp3dMultiResolutionResult {
  /// The last level run: its estimate, covariance, termination and message
  /// are the answer. A level that ends other than Converged, MaxIterations
  /// or Stalled stops the schedule and is reported here.
  Icp3dResult result;
  /// Every level run, coarse first (result == levels.back()).
  std::vector<Icp3dResult> levels;
  /// Iterations summed over the levels.
  int total_iterations = 0;
  /// Finite points of each level after down-sampling, coarse first.
  std::vector<std::size_t> target_points, source_points;
};

/// Registers `source` onto `target` (points in meters; non-finite points are
/// dropped) coarse to fine from `initial_T_target_source`. Preconditions
/// (InvalidArgument): options.check(). Empty clouds give InvalidInput.
Icp3dMultiResolutionResult icp_3d_multi_resolution(
    std::span<const Eigen::Vector3f> target, std::span<const Eigen::Vector3f> source,
    const SE3d& initial_T_target_source,
    const Icp3dMultiResolutionOptions& options = {});

}  // namespace rove
