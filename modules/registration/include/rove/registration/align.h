#pragma once
/// \file
/// One call that registers two point clouds the way `rove align` does: the
/// method by name (point-to-point ICP, point-to-plane ICP, GICP or NDT), the
/// voxel sizes chosen from the target's density unless given, the ICP
/// family coarse to fine (icp_3d_multi_resolution), NDT on one voxel grid
/// (ndt_3d). The command line, the Python bindings and batch runs call it,
/// so the three give the same numbers for the same clouds and options.
///
/// Thread-safety: a pure function of its arguments.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se3.h"
#include "rove/registration/termination.h"

namespace rove {

/// The registration method of align_clouds.
enum class AlignMethod {
  PointToPoint,  ///< classic ICP ("icp")
  PointToPlane,  ///< point-to-plane ICP ("point-to-plane")
  Gicp,          ///< generalized ICP ("gicp")
  Ndt,           ///< normal distributions transform ("ndt")
};

/// "icp", "point-to-plane", "gicp", "ndt".
std::string_view to_string(AlignMethod method) noexcept;
/// Inverse of to_string(AlignMethod); throws InvalidArgument naming the
/// accepted names for any other text.
AlignMethod parse_align_method(std::string_view text);

/// Options of align_clouds; the defaults are `rove align`'s.
struct AlignOptions {
  /// Method. Default GICP.
  AlignMethod method = AlignMethod::Gicp;
  /// Voxel-grid leaves for both clouds, m, coarse to fine, each finite and
  /// ≥ 0 (0: the cloud as given). NDT takes exactly one. Unset ("auto"):
  /// the finest round leaf at which the target fills at most kAutoVoxels
  /// voxels (suggest_voxel_size; none for a smaller cloud) and, for the ICP
  /// family, a second level at kFineRatio × it.
  std::optional<std::vector<double>> voxel_sizes;
  /// ICP family with one voxel size: the pairing gate, m, > 0. Default 1.
  double max_distance = 1.0;
  /// ICP family with several voxel sizes: the gate of a level is this
  /// factor × its voxel size, > 0. Default 3.
  double distance_factor = 3.0;
  /// Neighbours (point included) for normals and GICP covariances, 3–1000.
  /// Default 10.
  std::size_t neighbors = 10;
  /// NDT cell side, m, > 0. Default 1.
  double ndt_resolution = 1.0;
  /// Iteration cap (per level for the ICP family); 0: the method's own (64
  /// per level for the ICP family, 35 for NDT). ≥ 0.
  int max_iterations = 0;
  /// Threads, 1–256, 0 for every hardware thread; results do not depend on
  /// it.
  int num_threads = 1;

  /// The auto voxel size keeps at most this many occupied target voxels.
  static constexpr std::size_t kAutoVoxels = 7000;
  /// The auto schedule's fine level, as a fraction of the coarse leaf.
  static constexpr double kFineRatio = 0.4;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// What align_clouds produced.
struct AlignResult {
  /// The estimate: maps source coordinates into the target's frame.
  SE3d T_target_source;
  /// Mean squared distance of the final pairs, m².
  double fitness = 0.0;
  /// Share of the source points paired at the end, in [0, 1] (NDT: its
  /// own goodness score).
  double goodness = 0.0;
  /// Iterations run (summed over the levels of the ICP family).
  int iterations = 0;
  /// The iteration cap in force (per level for the ICP family).
  int iteration_cap = 0;
  /// Finite points of the finest level's source and target.
  std::size_t source_points = 0, target_points = 0;
  /// Why it stopped; only Converged is a trustworthy estimate.
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line: the reason, with its figures.
  std::string message;
  /// The message of every level run, coarse first (ICP family).
  std::vector<std::string> level_messages;
  /// The voxel sizes used, coarse to fine, m.
  std::vector<double> voxel_sizes;
  /// True when the voxel sizes were chosen from the target's density.
  bool voxel_auto = false;
  /// The pairing gate when one ICP-family level ran (max_distance), else 0.
  double max_distance = 0.0;

  /// True only when the registration converged.
  bool ok() const noexcept { return succeeded(termination); }
};

/// Registers `source` onto `target` (points in meters; non-finite points
/// are dropped) from `T_init` (T_target_source). Preconditions
/// (InvalidArgument): options.check(), and one voxel size for NDT. Empty
/// clouds are a result with InvalidInput, not an error.
AlignResult align_clouds(std::span<const Eigen::Vector3f> target,
                         std::span<const Eigen::Vector3f> source, const SE3d& T_init = SE3d(),
                         const AlignOptions& options = {});

}  // namespace rove
