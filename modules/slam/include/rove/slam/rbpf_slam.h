#pragma once
/// \file
/// Rao-Blackwellized particle-filter grid mapping (Murphy 1999; Doucet et
/// al. 2000; Grisetti, Stachniss, Burgard, "Improved techniques for grid
/// mapping with Rao-Blackwellized particle filters", IEEE T-RO 23(1),
/// 2007), MRPT's rbpf-slam with its options: each particle is a robot pose
/// T_map_robot, the path that led there, and an occupancy grid built along
/// that path. The grids are TiledGrids (rove/maps/tiled_grid.h) whose
/// tiles are shared copy-on-write, so resampled copies cost no map memory
/// and the memory grows with what the particles change.
///
/// One update (the robot moved by `motion` since the last update and took
/// `scan`):
///  1. every particle draws its new pose from the proposal
///     (RbpfProposal) and multiplies its weight by the proposal's weight;
///     MRPT's powFactor scales the log-weight increments (likelihood
///     tempering, as GMapping's gain), never the proposal itself;
///  2. when the effective sample size ESS/N falls below BETA the particles
///     are resampled (rove/bayes/resampling.h, MRPT's four schemes) and the
///     weights equalized (Grisetti 2007, §IV adaptive resampling);
///  3. when asked, the scan is inserted into every particle's grid at its
///     pose with MRPT's insertion; copies of one particle insert once and
///     share the result.
///
/// Random numbers: update k (from 1) of a run with seed s draws particle
/// i's numbers from Rng::stream(derive_seed(s, k), i) and the resampling's
/// from another stream of the same seed, so the result is a function of the
/// seed and not of the thread count.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/bayes/resampling.h"
#include "rove/core/parallel.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/tiled_grid.h"
#include "rove/math/se2.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/registration/icp_2d.h"

namespace rove {

/// How a particle draws its new pose (MRPT's PF_algorithm, for grids).
enum class RbpfProposal : std::uint8_t {
  /// PF_algorithm = 0 (pfStandardProposal): a sample of the odometry
  /// motion model, weighted by the scan's likelihood in the particle's map.
  Standard,
  /// PF_algorithm = 3 (pfAuxiliaryPFOptimal, MRPT's "optimal sampling";
  /// gridmapping_optimal_sampling.ini, gridmapping_intel.ini): the optimal
  /// proposal p(x | x_{t−1}, u, z, m) ∝ p(z | x, m)·p(x | x_{t−1}, u)
  /// approximated as Grisetti et al. 2007 (§IV, eq. 18–20): the scan is
  /// matched against the particle's map from the odometry prediction (hill
  /// climbing on the likelihood field plus the motion prior, with the
  /// LF_decimation points, then refined with every point of the scan) to
  /// find the mode x*, K = pfAuxFilterOptimal_MaximumSearchSamples poses
  /// are drawn around it, the covariance Σ of them weighted by
  /// p(z | x, m)·p(x | x_{t−1}, u) is found, the new pose is drawn from
  /// N(x*, Σ), and the weight is multiplied by
  /// η = ∫ p(z | x, m)·p(x | x_{t−1}, u) dx. Where
  /// Grisetti samples a fixed interval around x*, rove draws the K poses
  /// by defensive importance sampling (Hesterberg, Technometrics 37(2),
  /// 1995): half from a Gaussian of one cell around x*, half from the
  /// motion prior, each weighted by target/mixture density, so η and
  /// (μ, Σ) stay right whether the likelihood is sharp (a wall in view) or
  /// flat (nothing seen): the estimate of η is unbiased for any K.
  /// MRPT draws the same distribution by rejection sampling of motion
  /// samples; the result differs from MRPT's by its sampling, not its target.
  Optimal,
  /// PF_algorithm = 2 (pfOptimalProposal) with pfOptimalProposal_mapSelection
  /// = 0 (gridmapping_RBPF_grid_ICPbased_malaga.ini): the scan is aligned
  /// with ICP ([MappingApplication]'s ICP keys) against the occupied cells
  /// of the particle's grid around the prediction; an alignment with
  /// goodness at least ICPGlobalAlign_MinQuality gives the new pose, drawn
  /// from the ICP's Gaussian, else the odometry motion model is sampled.
  /// The weight is multiplied by the scan's likelihood at the new pose
  /// (MRPT's rule).
  Icp,
};

/// MRPT's name of the proposal ("pfOptimalProposal", ...).
std::string_view mrpt_name(RbpfProposal proposal);

/// Options of RBPF grid mapping (MRPT's CMetricMapBuilderRBPF and
/// CMultiMetricMapPDF options, names in parentheses, MRPT's defaults).
struct RbpfSlamOptions {
  /// (PF_algorithm) the proposal. Default Optimal.
  RbpfProposal proposal = RbpfProposal::Optimal;
  /// (sampleSize) particles, ≥ 1. Default 1 as MRPT (configs set it).
  std::uint32_t particles = 1;
  /// (resamplingMethod) Default Multinomial.
  ResamplingMethod resampling = ResamplingMethod::Multinomial;
  /// (BETA) resample when ESS/N falls below it, in [0, 1]. Default 0.5.
  double beta = 0.5;
  /// (powFactor) factor on the log-weight increments, in (0, 1]. Default 1.
  double pow_factor = 1.0;
  /// (pfAuxFilterOptimal_MaximumSearchSamples) poses drawn around each
  /// particle's scan-matched mode by the optimal proposal, ≥ 4. Default 100.
  std::uint32_t search_samples = 100;
  /// Grid cell side, meters (the occupancy grid's creationOpts resolution).
  float resolution = 0.05f;
  /// Scan insertion (the grid's insertOpts).
  GridInsertionOptions insertion;
  /// The scan likelihood (the grid's likelihoodOpts; likelihoodMethod must
  /// be 4, lmLikelihoodField_Thrun).
  GridLikelihoodOptions likelihood;
  /// ICP of the Icp proposal (the ICP keys of [MappingApplication]).
  Icp2dOptions icp;
  /// (ICPGlobalAlign_MinQuality) least ICP goodness to use its result,
  /// in [0, 1]. Default 0.8.
  double icp_min_quality = 0.8;
  /// Threads, 1–256, 0 for all; the result does not depend on it.
  int num_threads = 1;
  /// Seed of every random number: same seed, same result.
  std::uint64_t seed = 0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// The odometry between two updates: the mean increment (in the robot
/// frame at the start) and the covariance of (Δx, Δy, Δφ), m and rad.
struct OdometryIncrement {
  /// The mean increment T_start_end.
  SE2d mean;
  /// Covariance of (Δx, Δy, Δφ) (MRPT's order), positive semidefinite.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/// One pose of a particle's path (a persistent list: copies share it).
struct RbpfPathNode {
  /// A node after `previous`.
  RbpfPathNode(const SE2d& pose_, std::uint64_t step_, std::shared_ptr<const RbpfPathNode> previous_)
      : pose(pose_), step(step_), previous(std::move(previous_)) {}
  RbpfPathNode(const RbpfPathNode&) = default;
  RbpfPathNode(RbpfPathNode&&) = default;
  RbpfPathNode& operator=(const RbpfPathNode&) = default;
  RbpfPathNode& operator=(RbpfPathNode&&) = default;
  /// Frees the nodes only this one holds iteratively (a path of 10⁵ nodes
  /// would otherwise be freed by as deep a recursion).
  ~RbpfPathNode();
  /// T_map_robot after the update.
  SE2d pose;
  /// The caller's index of the update's step.
  std::uint64_t step = 0;
  /// The pose before (null at the start).
  std::shared_ptr<const RbpfPathNode> previous;
};

/// One hypothesis: a pose, its path and its map.
struct RbpfParticle {
  /// T_map_robot.
  SE2d pose;
  /// The map built along the path.
  TiledGrid map;
  /// The latest node of the path (null before the first update).
  std::shared_ptr<const RbpfPathNode> path;
};

/// What one update did.
struct RbpfUpdateResult {
  /// ESS/N of the weights after the update, before any resampling, (0, 1].
  double ess = 1.0;
  /// True if the particles were resampled.
  bool resampled = false;
  /// Particles whose proposal had to fall back to the motion model (the
  /// Icp proposal's rejected alignments; the optimal proposal never does).
  std::size_t fallbacks = 0;
  /// Scans inserted (one per group of identical particles), 0 if none.
  std::size_t insertions = 0;
  /// Distinct tiles held by all particles' maps after the update.
  std::size_t distinct_tiles = 0;
  /// Fraction of the scan's points within LF_maxCorrsDistance of an
  /// occupied cell of the most likely particle's map at its new pose
  /// (before insertion; 1 when the map was empty).
  double fit = 1.0;
  /// Fraction of the scan's returns whose ray passes through an occupied
  /// cell of the same map more than kThroughWallsMargin (or 4 cells, if
  /// more) before the return, at the same pose (rays_through_occupied,
  /// tiled_grid.h; scan_consistency.h; 0 when the map was empty): free
  /// space the scan saw where the map holds a wall.
  double through_walls = 0.0;
};

/// The filter. Not thread-safe (it runs its own threads).
class RbpfSlam {
 public:
  /// `options.particles` particles at the origin with empty maps and equal
  /// weights. Throws InvalidArgument if options.check() fails or the
  /// likelihood options are not usable on tiled grids.
  explicit RbpfSlam(RbpfSlamOptions options);
  ~RbpfSlam();
  RbpfSlam(const RbpfSlam&) = delete;
  RbpfSlam& operator=(const RbpfSlam&) = delete;

  /// Inserts `scan` into every map at its particle's pose without filtering
  /// (the first scan of a run: nothing to match against yet). Returns the
  /// insertions made.
  std::size_t insert(const RangeScan2D& scan, std::uint64_t step);
  /// One update (see the file comment): moves the particles by `motion`
  /// through the proposal with `scan`, reweighs, resamples on low ESS and,
  /// if `insert_scan`, inserts the scan. `step` labels the path nodes.
  /// Throws InvalidArgument if the scan or the motion is malformed
  /// (non-finite values, a covariance that is not symmetric positive
  /// semidefinite).
  RbpfUpdateResult update(const OdometryIncrement& motion, const RangeScan2D& scan,
                          std::uint64_t step, bool insert_scan);

  /// The particles.
  const std::vector<RbpfParticle>& particles() const noexcept { return particles_; }
  /// Their normalized log-weights.
  const std::vector<double>& log_weights() const noexcept { return log_weights_; }
  /// The index of the most likely particle (largest weight, first on ties).
  std::size_t best() const;
  /// Distinct tiles of all maps (shared tiles once).
  std::size_t distinct_tiles() const;
  /// Updates run.
  std::uint64_t updates() const noexcept { return updates_; }
  /// The options.
  const RbpfSlamOptions& options() const noexcept { return options_; }

 private:
  struct Impl;
  std::size_t insert_all(const RangeScan2D& scan);
  RbpfSlamOptions options_;
  std::unique_ptr<Impl> impl_;
  std::vector<RbpfParticle> particles_;
  std::vector<double> log_weights_;
  std::uint64_t updates_ = 0;
};

/// The path of a particle, oldest first.
std::vector<RbpfPathNode> path_of(const RbpfParticle& particle);
/// The path ending at `last`, oldest first (empty for null).
std::vector<RbpfPathNode> path_of(const std::shared_ptr<const RbpfPathNode>& last);

}  // namespace rove
