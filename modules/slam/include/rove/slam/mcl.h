#pragma once
/// \file
/// Monte-Carlo localization of a planar robot in a known map (Dellaert, Fox,
/// Burgard, Thrun, "Monte Carlo localization for mobile robots", ICRA
/// 1999; MRPT's CMonteCarloLocalization2D): particles are SE2d poses
/// T_map_robot, moved by samples of the odometry motion model and weighted
/// by the likelihood of the observations in the map, with the particle
/// filter of rove::bayes (MRPT's four algorithms, KLD-sampling, its
/// resamplers). Added to MRPT's filter: recovery from a kidnapping by
/// augmented MCL (rove/slam/mcl_options.h, RecoveryOptions), and an honest
/// convergence test (ConvergenceOptions).
///
/// The map is a MultiMetricMap (as MRPT's pf-localization builds it from
/// the config's [MetricMap]); its maps with likelihood enabled weigh the
/// observations they can evaluate (sum of log-likelihoods, MRPT's fuse-all
/// or its likelihoodMapSelection). Occupancy grids are evaluated with their
/// own likelihood options through GridLikelihoodModel, built once.
///
/// Random numbers: step k of a run with seed s uses the streams of
/// derive_seed(s, k + 1) (the filter's, per particle) and the
/// initialization those of derive_seed(s, 0); so the result is a function
/// of the seed, not of the thread count.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "rove/bayes/particle_filter.h"
#include "rove/core/parallel.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/math/se2.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/slam/mcl_options.h"

namespace rove {

/// The Gaussian summary of a particle set.
struct MclEstimate {
  /// Weighted mean: x, y averaged, the heading as the angle of the weighted
  /// mean of (cos, sin) (MRPT's CPosePDFParticles::getMean).
  SE2d mean;
  /// Covariance in the right tangent at the mean, (ρx, ρy, θ): position
  /// along the mean robot's axes (m², m·rad, rad²). It is the weighted
  /// covariance C of (x, y, heading) around the mean (heading differences
  /// wrapped to (−π, π], MRPT's getCovarianceAndMean) rotated into the
  /// robot's frame, J·C·Jᵀ with J = diag(Rᵀ, 1): the first-order tangent
  /// covariance. world_covariance() gives C back.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  /// √ of the larger eigenvalue of the xy block, meters.
  double position_std = 0.0;
  /// √ of the heading variance, radians.
  double heading_std = 0.0;
  /// The covariance of (x, y, heading) in the map frame (MRPT's
  /// CPosePDFGaussian order and frame).
  Eigen::Matrix3d world_covariance() const;
};

/// The estimate of a weighted set of poses. Precondition (InvalidArgument):
/// non-empty, as many log-weights as states, not all −inf.
MclEstimate estimate_of(const ParticleSet<SE2d>& particles);

/// The share of the weight of `particles` within `radius` (m) of `center`'s
/// position and `heading_radius` (rad) of its heading. Preconditions
/// (InvalidArgument): as estimate_of.
double mass_near(const ParticleSet<SE2d>& particles, const SE2d& center, double radius,
                 double heading_radius);

/// What one MCL step did.
struct MclStepResult {
  /// The particle filter's report (algorithm, counts, ESS, resampling,
  /// log-evidence).
  ParticleFilterStepResult filter;
  /// The estimate after the update, before any recovery injection.
  MclEstimate estimate;
  /// Particles after the step (after recovery).
  std::size_t particles = 0;
  /// True if some map could evaluate some observation of the frame.
  bool informative = false;
  /// Fraction of the scan's points within ConvergenceOptions::fit_distance
  /// of an occupied cell with the robot at the estimate (grid maps and 2D
  /// scans only).
  std::optional<double> scan_fit;
  /// Root-mean-square range residual at the estimate, in standard
  /// deviations of a range (beacon/landmark maps and beacon ranges only).
  std::optional<double> range_residual;
  /// Share of the weight within ConvergenceOptions::radius and
  /// heading_radius of the estimate (after the update, before recovery).
  double mass_near = 0.0;
  /// mass_near ≥ ConvergenceOptions::min_mass.
  bool concentrated = false;
  /// The observations agree with the map at the estimate (true when no
  /// check applies).
  bool fits = true;
  /// Probability max(0, 1 − w_fast / w_slow) of replacing a particle by a
  /// random one (recovery; 0 when disabled).
  double injection_probability = 0.0;
  /// Particles replaced by random poses.
  std::size_t injected = 0;
};

/// Monte-Carlo localization over one map. Not thread-safe (the steps use
/// the options' threads internally).
class MonteCarloLocalization {
 public:
  /// Prepares the filter for `map`, which must outlive it and not change.
  /// Throws InvalidArgument if options.check() fails, if a free-space
  /// initialization or recovery needs an occupancy grid the map lacks, or
  /// if the map holds no free cell where the particles must start.
  MonteCarloLocalization(const MultiMetricMap& map, MclOptions options);
  ~MonteCarloLocalization();
  MonteCarloLocalization(const MonteCarloLocalization&) = delete;
  MonteCarloLocalization& operator=(const MonteCarloLocalization&) = delete;

  /// Draws the initial particles (options.init) with equal weights and
  /// restarts the step count and the recovery averages.
  void initialize();
  /// Replaces the particles (e.g. to test a kidnapping); restarts as
  /// initialize(). Precondition (InvalidArgument): non-empty, sizes agree.
  void set_particles(ParticleSet<SE2d> particles);

  /// One step: moves the particles by `motion` (none: they stay) and
  /// weighs them with the observations of `frame`. A frame the map cannot
  /// evaluate only moves the particles. Throws InvalidArgument if an
  /// observation or the motion is malformed (non-finite values).
  MclStepResult step(const RobotMovement2D* motion, const SensoryFrame& frame);

  /// The current particles (log-weights normalized after a step).
  const ParticleSet<SE2d>& particles() const noexcept { return particles_; }
  /// The estimate of the current particles.
  MclEstimate estimate() const { return estimate_of(particles_); }
  /// Steps run since initialize().
  std::uint64_t steps() const noexcept { return steps_; }
  /// The options in use.
  const MclOptions& options() const noexcept { return options_; }

 private:
  std::size_t inject(std::uint64_t step_seed, double p);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  MclOptions options_;
  ParticleSet<SE2d> particles_;
  std::uint64_t steps_ = 0;
};

}  // namespace rove
