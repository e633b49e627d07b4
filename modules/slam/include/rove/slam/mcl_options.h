#pragma once
/// \file
/// Options of Monte-Carlo localization (rove/slam/mcl.h): how the particles
/// start, augmented MCL's recovery from a kidnapping, and when a run counts
/// as converged. The particle filter's own options are rove::bayes's
/// (ParticleFilterOptions, KldOptions), with MRPT's names.

#include <cstdint>
#include <numbers>
#include <optional>

#include "rove/bayes/kld_sampling.h"
#include "rove/bayes/particle_filter_options.h"
#include "rove/math/se2.h"
#include "rove/obs/motion_model_options.h"

namespace rove {

/// Where the particles are drawn at the start (MRPT's `init_PDF_mode`, with
/// two rove additions).
enum class ParticleInitMode : std::uint8_t {
  /// MRPT's init_PDF_mode = 0: uniform over the free cells of the
  /// occupancy grid (p(free) ≥ ParticleInit::free_threshold) inside the box,
  /// heading uniform in [min_yaw, max_yaw).
  FreeSpaceInBox = 0,
  /// MRPT's init_PDF_mode = 1: uniform over the box, map or not.
  UniformInBox = 1,
  /// rove (init_PDF_mode = 2): uniform over every free cell of the grid,
  /// any heading (global localization); the box is not used.
  FreeSpace = 2,
  /// rove (init_PDF_mode = 3): Gaussian around `pose` with standard
  /// deviations std_xy (each axis) and std_yaw.
  AroundPose = 3,
};

/// The initial particle set.
struct ParticleInit {
  /// How the particles are drawn.
  ParticleInitMode mode = ParticleInitMode::FreeSpaceInBox;
  /// Initial particle count (MRPT `particles_count`), ≥ 1.
  std::uint32_t count = 1000;
  /// The box of FreeSpaceInBox and UniformInBox, meters (MRPT
  /// `init_PDF_min_x`, ... ; min ≤ max).
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
  /// Heading range of the box modes, radians (MRPT `init_PDF_min_yaw_deg`,
  /// `init_PDF_max_yaw_deg`, in degrees there; default the full circle).
  double min_yaw = -std::numbers::pi, max_yaw = std::numbers::pi;
  /// Mean pose of AroundPose, T_map_robot (rove keys `init_PDF_mean_x`,
  /// `init_PDF_mean_y`, `init_PDF_mean_yaw_deg`).
  SE2d pose;
  /// Standard deviations of AroundPose: meters per axis (`init_PDF_std_xy`)
  /// and radians (`init_PDF_std_yaw_deg`, degrees there); ≥ 0.
  double std_xy = 0.5, std_yaw = 0.2;
  /// A cell is free when p(free) ≥ this (MRPT's pf-localization uses 0.7).
  double free_threshold = 0.7;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Augmented MCL (Thrun, Burgard, Fox, "Probabilistic Robotics", 2005,
/// §8.3.5, Table 8.3): short- and long-term averages of the observation
/// likelihood, w_fast and w_slow; after each update a fraction
/// max(0, 1 − w_fast / w_slow) of the particles is replaced by poses drawn
/// uniformly over the map's free space. The names are those of ROS AMCL
/// (`recovery_alpha_slow`, `recovery_alpha_fast`); both 0 (the default, as
/// in AMCL and MRPT) disables recovery.
struct RecoveryOptions {
  /// α_slow ∈ [0, 1): smoothing of the long-term average (AMCL suggests 0.001).
  double alpha_slow = 0.0;
  /// α_fast ∈ [0, 1): smoothing of the short-term average, > α_slow when
  /// enabled (AMCL suggests 0.1).
  double alpha_fast = 0.0;
  /// True when recovery is on (both averages positive).
  bool enabled() const noexcept { return alpha_slow > 0.0 && alpha_fast > 0.0; }
  /// Throws InvalidArgument unless both are in [0, 1), and either both are 0
  /// or 0 < alpha_slow < alpha_fast.
  void check() const;
};

/// When a run counts as converged: the belief is concentrated (at least
/// `min_mass` of the particles' weight within `radius` and `heading_radius`
/// of the estimate), and, where the map allows a check, the observations
/// agree with the map at the estimate, for `min_steps` consecutive steps.
/// A probability mass rather than a standard deviation: a few random
/// particles far away (recovery's) carry little weight but a large variance,
/// and a second mode with a tenth of the weight must count against it.
struct ConvergenceOptions {
  /// Distance from the estimate, meters (> 0). Default 0.5.
  double radius = 0.5;
  /// Heading difference from the estimate, radians (> 0). Default 10°.
  double heading_radius = 10.0 * std::numbers::pi / 180.0;
  /// Share of the weight that must lie that close, in (0, 1]. Default 0.95.
  double min_mass = 0.95;
  /// Consecutive steps that must meet both bounds (and the map check).
  /// Default 3, ≥ 1.
  std::uint32_t min_steps = 3;
  /// Scans against an occupancy grid: at least this fraction of the scan's
  /// points must lie within `fit_distance` of an occupied cell when the
  /// robot is at the estimate (a scan that fits no wall is not localized,
  /// however concentrated the particles are). In [0, 1]; 0 disables the
  /// check. Default 0.5.
  double min_scan_fit = 0.5;
  /// Distance for min_scan_fit, meters (> 0). Default 0.3.
  double fit_distance = 0.3;
  /// Beacon ranges against beacons/landmarks: the root-mean-square range
  /// residual at the estimate, in standard deviations of a range, must stay
  /// below this (> 0). Default 3.
  double max_range_residual = 3.0;
  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Everything MonteCarloLocalization needs besides the map.
struct MclOptions {
  /// The particle filter ([PF_options]).
  ParticleFilterOptions pf;
  /// KLD-sampling ([KLD_options]), used when pf.adaptive_sample_size.
  KldOptions kld;
  /// The initial particles.
  ParticleInit init;
  /// Recovery from kidnapping.
  RecoveryOptions recovery;
  /// When the run counts as converged.
  ConvergenceOptions convergence;
  /// Replaces the motion model each odometry action of the log carries
  /// (rove's [MotionModel] section); unset: the log's own model.
  std::optional<MotionModelOptions> motion_model;
  /// Gaussian model of the odometry increments of a log without actions
  /// (observation-only layout): MRPT's [DummyOdometryParams] minStdXY
  /// (default 0.04 m) and minStdPHI (default 2°), α1..α4 at MRPT's
  /// defaults (as its application leaves them).
  GaussianMotionOptions dummy_odometry = default_dummy_odometry();
  /// Powers the likelihood weighting; 1–256 threads, 0 for every hardware
  /// thread. The result does not depend on it.
  int num_threads = 1;
  /// Seed of every random number of a run: same seed, same result.
  std::uint64_t seed = 0;

  /// MRPT's pf-localization defaults for [DummyOdometryParams].
  static GaussianMotionOptions default_dummy_odometry();
  /// Throws InvalidArgument naming the first field out of range (all
  /// members' checks; pf's sample_size is replaced by init.count).
  void check() const;
};

}  // namespace rove
