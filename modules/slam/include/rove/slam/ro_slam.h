#pragma once
/// \file
/// Range-only SLAM with a Rao-Blackwellized particle filter (MRPT's
/// rbpf-slam with a beacon map: RO-SLAM_simulatedData_MC.ini and
/// RO-SLAM_simulatedData_SOG.ini). Each particle is a robot pose
/// T_map_robot, the path that led there, and a map of beacons
/// (rove/maps/beacon_map.h) built along that path: a beacon first seen lies
/// on a ring around the sensor, held as Monte-Carlo samples or a sum of
/// Gaussians; later ranges reweight the samples or update each Gaussian
/// with an EKF, and once the density is concentrated it becomes one
/// Gaussian tracked by an EKF (Blanco, Fernández-Madrigal, González,
/// "Efficient probabilistic range-only SLAM", IROS 2008; "A pure
/// probabilistic approach to range-only SLAM", ICRA 2008).
///
/// One update (the robot moved by `motion` since the last update and took
/// `ranges`), MRPT's pfStandardProposal (PF_algorithm = 0):
///  1. every particle draws its new pose from the odometry's Gaussian and
///     multiplies its weight by the likelihood of the ranges in its map
///     (BeaconMap::log_likelihood), the log-increment scaled by powFactor;
///  2. when ESS/N falls below BETA the particles are resampled
///     (rove/bayes/resampling.h) and the weights equalized;
///  3. when asked, the ranges are inserted into every particle's map at its
///     pose; copies of one particle (made by resampling) insert once and
///     share the resulting map until their next insertion.
///
/// Random numbers: update k (from 1) of a run with seed s draws particle
/// i's pose from Rng::stream(derive_seed(s, k), i) and reseeds the map of
/// the copies of particle i with derive_seed(derive_seed(s, k), i) before
/// inserting, so the result is a function of the seed, not of the threads.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "rove/bayes/resampling.h"
#include "rove/maps/beacon_map.h"
#include "rove/math/se2.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/slam/rbpf_slam.h"

namespace rove {

/// Options of range-only RBPF SLAM (MRPT's names in parentheses, MRPT's
/// defaults).
struct RoSlamOptions {
  /// (sampleSize) particles, ≥ 1. Default 1 as MRPT (configs set it).
  std::uint32_t particles = 1;
  /// (resamplingMethod) Default Multinomial.
  ResamplingMethod resampling = ResamplingMethod::Multinomial;
  /// (BETA) resample when ESS/N falls below it, in [0, 1]. Default 0.5.
  double beta = 0.5;
  /// (powFactor) factor on the log-weight increments, in (0, 1]. Default 1.
  double pow_factor = 1.0;
  /// The beacon map's insertion (its insertOpts: Monte-Carlo or SOG rings,
  /// their collapse into a Gaussian).
  BeaconMapInsertOptions insertion;
  /// The beacon map's likelihood (its likelihoodOpts: rangeStd).
  BeaconMapLikelihoodOptions likelihood;
  /// Threads, 1–256, 0 for all; the result does not depend on it.
  int num_threads = 1;
  /// Seed of every random number: same seed, same result.
  std::uint64_t seed = 0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// One hypothesis: a pose, its path and its beacon map (shared with its
/// copies until one of them inserts).
struct RoSlamParticle {
  /// T_map_robot.
  SE2d pose;
  /// The beacons seen along the path (never null).
  std::shared_ptr<const BeaconMap> map;
  /// The latest node of the path (null before the first insertion).
  std::shared_ptr<const RbpfPathNode> path;
};

/// What one update did.
struct RoSlamUpdateResult {
  /// ESS/N of the weights after the update, before any resampling, (0, 1].
  double ess = 1.0;
  /// True if the particles were resampled.
  bool resampled = false;
  /// Insertions made (one per group of identical particles), 0 if none.
  std::size_t insertions = 0;
  /// Readings with a usable range (finite, > 0) in the observation.
  std::size_t readings = 0;
  /// Beacons of the most likely particle's map after the update.
  std::size_t beacons = 0;
  /// Of those, beacons still held as samples or a sum of Gaussians.
  std::size_t unresolved = 0;
};

/// The filter. Not thread-safe (it runs its own threads).
class RoSlam {
 public:
  /// `options.particles` particles at the origin with empty maps and equal
  /// weights. Throws InvalidArgument if options.check() fails.
  explicit RoSlam(RoSlamOptions options);
  ~RoSlam();
  RoSlam(const RoSlam&) = delete;
  RoSlam& operator=(const RoSlam&) = delete;

  /// Inserts `ranges` into every map at its particle's pose without
  /// filtering (the first observation of a run). Returns the insertions.
  /// Throws InvalidArgument on a malformed observation (see update).
  std::size_t insert(const BeaconRanges& ranges, std::uint64_t step);
  /// One update (see the file comment). `step` labels the path nodes.
  /// Throws InvalidArgument if the motion is malformed (non-finite, a
  /// covariance not symmetric positive semidefinite) or a reading's range
  /// is NaN or its antenna position not finite.
  RoSlamUpdateResult update(const OdometryIncrement& motion, const BeaconRanges& ranges,
                            std::uint64_t step, bool insert_ranges);

  /// The particles.
  const std::vector<RoSlamParticle>& particles() const noexcept { return particles_; }
  /// Their normalized log-weights.
  const std::vector<double>& log_weights() const noexcept { return log_weights_; }
  /// The index of the most likely particle (largest weight, first on ties).
  std::size_t best() const;
  /// Updates run.
  std::uint64_t updates() const noexcept { return updates_; }
  /// The options.
  const RoSlamOptions& options() const noexcept { return options_; }

 private:
  struct Impl;
  std::size_t insert_all(const BeaconRanges& ranges, std::uint64_t seed);
  RoSlamOptions options_;
  std::unique_ptr<Impl> impl_;
  std::vector<RoSlamParticle> particles_;
  std::vector<double> log_weights_;
  std::uint64_t updates_ = 0;
};

}  // namespace rove
