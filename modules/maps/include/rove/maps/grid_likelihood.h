#pragma once
/// \file
/// Observation likelihood of a 2D range scan in an occupancy grid: MRPT's
/// seven methods (COccupancyGridMap2D::TLikelihoodOptions), with MRPT's
/// options, defaults and numbers.
///
/// Two levels: GridLikelihoodModel holds the per-grid setup (the likelihood
/// field, built once with an exact distance transform instead of MRPT's
/// lazily filled per-cell cache — same values); prepare() does the per-scan
/// setup (the scan's points, as MRPT's auxiliary points map); then
/// log_likelihood() evaluates one pose or a batch of poses (a particle
/// filter's particles) without repeating either setup.
///
/// Values are natural-log likelihoods as MRPT returns them:
/// - kLikelihoodFieldThrun: Σ ln(zRandom/maxRange + zHit·exp(−d²/(2σ²)))
///   over the scan's points (one in LF_decimation; all if fewer than 10),
///   d = distance to the nearest occupied cell (p(free) < 0.5) capped at
///   LF_maxCorrsDistance; points in the grid's last row/column or outside
///   get the capped value. LF_alternateAverageMethod: ln(mean) instead.
///   Thrun, Burgard, Fox, "Probabilistic Robotics" (2005), §6.4, Table 6.3.
/// - kLikelihoodFieldII: per point, the mean over a (2K+1)² window of
///   p_free/maxRange + (1 − p_free)·exp(−d²/(2σ²)); mean of their logs.
/// - kRayTracing: 1 + Σ ln(0.1/maxRange + 0.9·exp(−(min(|r_sim − r|, 2)/(√2·σ))²))
///   over one ray in rayTracing_decimation, r_sim simulated in the grid.
/// - kConsensus: consensus_pow · ln(mean occupancy of the points' cells)
///   (Blanco et al., ICRA 2007).
/// - kConsensusOWA: ln Σ_k w_k·o_(k), o_(k) the k-th largest 3×3-window
///   occupancy of the points.
/// - kCellsDifference: ln(1 − fraction of disagreeing cells) between the grid
///   and a 20 m × 20 m grid built from the scan alone.
/// - kMeanInformation: MI_exponent · ln(mean information of the cells the
///   scan would update, over MI_ratio_max_distance × maxDistanceInsertion).
///
/// Differences from MRPT 2.5.8 by default (GridLikelihoodOptions::arithmetic
/// Mrpt removes the first): the comparison grid of kCellsDifference and the
/// cells of kMeanInformation come from rove's double-precision insertion
/// (grid_insertion.h). Where MRPT's result is not usable: MRPT's
/// consensus-OWA returns 1e−3 for every 2D scan and its mean-information
/// method returns −inf (and inserts the scan into the grid); rove computes
/// what both methods describe (above). Points far outside the grid, which
/// make MRPT read outside its arrays, read as unknown cells (p = 0.5).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/math/se2.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"

namespace rove {

/// MRPT's TLikelihoodMethod, same numbering.
enum class GridLikelihoodMethod : std::uint8_t {
  MeanInformation = 0,       ///< `lmMeanInformation`
  RayTracing = 1,            ///< `lmRayTracing`
  Consensus = 2,             ///< `lmConsensus`
  CellsDifference = 3,       ///< `lmCellsDifference`
  LikelihoodFieldThrun = 4,  ///< `lmLikelihoodField_Thrun`
  LikelihoodFieldII = 5,     ///< `lmLikelihoodField_II`
  ConsensusOWA = 6,          ///< `lmConsensusOWA`
};

/// Options of the likelihood methods: MRPT's TLikelihoodOptions and
/// defaults; the INI key of each field is the MRPT name in its comment.
struct GridLikelihoodOptions {
  /// `likelihoodMethod` (names as MRPT's enum or its number).
  GridLikelihoodMethod method = GridLikelihoodMethod::LikelihoodFieldThrun;
  /// `LF_stdHit`: σ of the hit model, meters.
  float lf_std_hit = 0.35f;
  /// `LF_zHit`: weight of the hit model.
  float lf_z_hit = 0.95f;
  /// `LF_zRandom`: weight of the random-measurement model.
  float lf_z_random = 0.05f;
  /// `LF_maxRange`: range of the random model, meters.
  float lf_max_range = 81.0f;
  /// `LF_decimation`: use one point out of this many (>= 1).
  std::uint32_t lf_decimation = 5;
  /// `LF_maxCorrsDistance`: distance cap (search radius), meters.
  float lf_max_corrs_distance = 0.3f;
  /// `LF_useSquareDist`: use d⁴ instead of d² in the exponent (MRPT's flag).
  bool lf_use_square_dist = false;
  /// `LF_alternateAverageMethod`: average the likelihoods instead of
  /// multiplying them.
  bool lf_alternate_average_method = false;
  /// `MI_exponent`.
  float mi_exponent = 2.5f;
  /// `MI_skip_rays`: use one ray out of this many (>= 1).
  std::uint32_t mi_skip_rays = 10;
  /// `MI_ratio_max_distance`: factor on maxDistanceInsertion.
  float mi_ratio_max_distance = 1.5f;
  /// `rayTracing_useDistanceFilter`: read for compatibility; MRPT 2.5.8's
  /// ray-tracing method ignores it, and so does rove.
  bool ray_tracing_use_distance_filter = true;
  /// `rayTracing_decimation`: simulate one ray out of this many (>= 1).
  std::int32_t ray_tracing_decimation = 10;
  /// `rayTracing_stdHit`: range σ, meters.
  float ray_tracing_std_hit = 1.0f;
  /// `consensus_takeEachRange`: use one point out of this many (>= 1).
  std::int32_t consensus_take_each_range = 1;
  /// `consensus_pow`.
  float consensus_pow = 5.0f;
  /// `OWA_weights`: weights of the ordered occupancies, largest first.
  std::vector<float> owa_weights = std::vector<float>(100, 1.0f / 100.0f);
  /// `enableLikelihoodCache`: accepted for compatibility; rove always
  /// precomputes the likelihood field (same values).
  bool enable_likelihood_cache = true;
  /// `arithmetic` (rove's key: double | mrpt): the scan insertion behind
  /// kCellsDifference (its comparison grid) and kMeanInformation (the cells
  /// a scan would update) runs in this arithmetic (GridInsertionOptions::
  /// arithmetic). Mrpt reproduces MRPT's numbers, including the int8
  /// overflow of the comparison grid's p = 0.95 occupied update; Double
  /// saturates it and casts the rays at the scan's own angles. Default
  /// Double.
  Arithmetic arithmetic = Arithmetic::Double;

  /// Reads the keys present in `section`. Throws ConfigError (file,
  /// section, key) on malformed values or values check() rejects.
  static GridLikelihoodOptions from_config(const ConfigSection& config);
  /// Throws InvalidArgument unless values are finite, σ's and ranges > 0,
  /// decimations >= 1.
  void check() const;
  /// Exact equality.
  friend bool operator==(const GridLikelihoodOptions&, const GridLikelihoodOptions&) = default;
};

/// A scan made ready for repeated evaluation at many poses (see
/// GridLikelihoodModel::prepare). Immutable; cheap to share.
struct PreparedGridScan {
  /// Copy of the scan's geometry and ranges.
  std::shared_ptr<const RangeScan2D> scan;
  /// The scan's points in the robot frame (x, y), MRPT's auxiliary points
  /// map for this method (float, as MRPT).
  std::vector<float> xs, ys;
  /// False when the scan is not horizontal or not at the map altitude:
  /// every pose then gets `fixed_value` (MRPT's −10 / 0.5 conventions).
  bool usable = true;
  /// The value returned for every pose when !usable.
  double fixed_value = 0.0;
};

/// The per-grid part of the likelihood computation. Keeps a reference to
/// the grid: the grid must outlive the model, and after the grid changes
/// (revision()) refresh() must be called before evaluating again.
/// Thread-safety: const member functions may run concurrently.
template <GridCell Cell>
class GridLikelihoodModel {
 public:
  /// Builds the setup of `options.method` for `grid` (for the likelihood
  /// field: one distance transform, O(cells)). `insertion` supplies
  /// horizontalTolerance, useMapAltitude/mapAltitude and
  /// maxDistanceInsertion as MRPT reads them from the grid's insertion
  /// options. Throws InvalidArgument if the options fail check().
  GridLikelihoodModel(const OccupancyGridT<Cell>& grid, GridLikelihoodOptions options = {},
                      GridInsertionOptions insertion = {});

  /// Rebuilds the per-grid setup after the grid changed.
  void refresh();

  /// The per-scan setup. Throws InvalidArgument if scan.check() fails.
  PreparedGridScan prepare(const RangeScan2D& scan) const;

  /// Natural-log likelihood of the prepared scan with the robot at
  /// T_map_robot. Throws InvalidArgument if the grid changed since the
  /// model was built or refreshed.
  double log_likelihood(const PreparedGridScan& scan, const Pose2& T_map_robot) const;
  /// The same for many poses: out[i] = log_likelihood(scan, poses[i]).
  /// Precondition (InvalidArgument): out.size() == poses.size().
  void log_likelihood(const PreparedGridScan& scan, std::span<const Pose2> poses,
                      std::span<double> out) const;
  /// The same with the pose as an SE2d. For the likelihood field its
  /// rotation's cosine and sine are used directly (the particle filter's
  /// path); the other methods go through Pose2.
  double log_likelihood(const PreparedGridScan& scan, const SE2d& T_map_robot) const;
  /// prepare() and log_likelihood() in one call; a 3D pose is reduced to
  /// (x, y, yaw) as MRPT does.
  double log_likelihood(const RangeScan2D& scan, const Pose3& T_map_robot) const;

  /// The options in use.
  const GridLikelihoodOptions& options() const noexcept { return options_; }
  /// The grid.
  const OccupancyGridT<Cell>& grid() const noexcept { return *grid_; }

 private:
  void check_fresh() const;
  double eval_one(const PreparedGridScan& s, const Pose2& pose) const;

  const OccupancyGridT<Cell>* grid_;
  GridLikelihoodOptions options_;
  GridInsertionOptions insertion_;
  std::uint64_t revision_ = 0;
  // Likelihood field: per cell ln(lik) (product) or lik (average).
  std::vector<double> field_;
  double field_outside_ = 0.0;
};

/// One-call form: builds a model and evaluates one scan at one pose.
template <GridCell Cell>
double scan_log_likelihood(const OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                           const Pose3& T_map_robot, const GridLikelihoodOptions& options = {},
                           const GridInsertionOptions& insertion = {});

/// The points of a 2D scan in the robot frame exactly as MRPT's
/// CSimplePointsMap loads them (float arithmetic, rays at MRPT's angles):
/// rays without a valid range are skipped; with min_dist > 0 a point closer
/// than min_dist (3D) to the last kept point, or right after an invalid
/// ray, is dropped, and the last valid point is always kept. z is dropped.
void mrpt_scan_points(const RangeScan2D& scan, float min_dist, std::vector<float>& xs,
                      std::vector<float>& ys);

extern template class GridLikelihoodModel<std::int8_t>;
extern template class GridLikelihoodModel<std::int16_t>;

}  // namespace rove
