#pragma once
/// \file
/// Robust 2D rigid transform from putative pairs that may contain outliers
/// and several consistent subsets (symmetric rooms, repeated structure):
/// RANSAC that keeps every good hypothesis and returns them as a sum of
/// Gaussians (MRPT's tfest::se2_l2_robust semantics, as CICP's doRANSAC and
/// grid-map matching use it; Blanco, González-Jiménez, Fernández-Madrigal,
/// "A robust, multi-hypothesis approach to matching occupancy grid maps",
/// Robotica 31(5), 2013, Sec. 4).
///
/// Each of `n_simulations` trials seeds a hypothesis with two random pairs,
/// then visits the other pairs in random order and adds each one whose
/// residual is within `mahalanobis_threshold` of the prediction (covariance:
/// the hypothesis' own covariance propagated to the point plus 2σ² on each
/// axis, σ = normalization_std), refitting after each addition, until
/// `max_set_size` pairs. Hypotheses with at least `min_set_size` pairs
/// become modes; a hypothesis equal to an existing mode (same pair set when
/// fuse_by_corrs_match, else means within fuse_max_diff_xy / _phi) adds to
/// its weight instead. A mode's weight is the number of trials that found
/// it, so the most supported transform is the most likely mode.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/pdf_sog.h"
#include "rove/registration/termination.h"

namespace rove {

/// Options of ransac_rigid_2d (MRPT's CICP ransac_* keys).
struct RansacRigid2dOptions {
  /// Pairs a hypothesis needs to become a mode, ≥ 2. Default 3.
  unsigned min_set_size = 3;
  /// Pairs at which a hypothesis stops growing, ≥ min_set_size. Default 20.
  unsigned max_set_size = 20;
  /// Trials, ≥ 1. Default 100.
  unsigned n_simulations = 100;
  /// Gate for adding a pair, in standard deviations, > 0. Default 3.
  double mahalanobis_threshold = 3.0;
  /// σ of each point coordinate, meters, > 0. Default 0.02.
  double normalization_std = 0.02;
  /// Fuse hypotheses with the same pair set (true) or with close means
  /// (false). Default true.
  bool fuse_by_corrs_match = true;
  /// Mean distance under which two hypotheses fuse (when not by pairs),
  /// meters and radians, ≥ 0. Defaults 0.01 m and 0.1°.
  double fuse_max_diff_xy = 0.01;
  double fuse_max_diff_phi = 0.1 * 3.14159265358979323846 / 180.0;
  /// Seed of the random generator; equal seeds give equal results.
  std::uint64_t seed = 0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Result of ransac_rigid_2d.
struct RansacRigid2dResult {
  /// The modes: each a Gaussian T_target_source (fit of its pairs, point
  /// variance normalization_std²) with log-weight log(number of trials).
  Pose2SOG sog;
  /// The pair indices of each mode, sorted, in the order of sog.modes().
  std::vector<std::vector<std::uint32_t>> mode_pairs;
  /// Converged (at least one mode), TooFewCorrespondences (fewer pairs than
  /// min_set_size), Degenerate (no trial reached min_set_size consistent
  /// pairs) or InvalidInput (non-finite coordinates).
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  /// One line explaining the termination.
  std::string message;
};

/// Robust T_target_source from putative pairs (targetᵢ ↔ sourceᵢ).
/// Preconditions (InvalidArgument): equal sizes, options.check().
RansacRigid2dResult ransac_rigid_2d(std::span<const Eigen::Vector2d> target,
                                    std::span<const Eigen::Vector2d> source,
                                    const RansacRigid2dOptions& options = {});

}  // namespace rove
