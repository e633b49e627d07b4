#pragma once
/// \file
/// BeaconMap: a map of range-only beacons whose positions are probability
/// densities (MRPT's CBeaconMap / CBeacon), for range-only SLAM and
/// localization with BeaconRanges observations.
///
/// A beacon seen for the first time lies somewhere on a ring (2D) or sphere
/// (3D) around the sensor. It is initialised either as Monte-Carlo samples
/// on that ring or as a sum of Gaussians (SOG) covering it; each later range
/// reweights the samples, or updates each Gaussian with an EKF and reweights
/// it, and once the density is concentrated it collapses into one Gaussian,
/// which further ranges update with an EKF. Reference: J.L. Blanco,
/// J.A. Fernández-Madrigal, J. González, "Efficient Probabilistic Range-Only
/// SLAM", IROS 2008, Sections III–IV (SOG ring, per-mode EKF, weight update
/// with the mode's predicted range likelihood); and "A Pure Probabilistic
/// Approach to Range-Only SLAM", ICRA 2008 (Monte-Carlo ring).
///
/// Frames and units: beacon positions are in the map frame, meters.

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/maps/metric_map.h"
#include "rove/obs/beacon_ranges.h"

namespace rove {

/// A 3D point with a Gaussian density (map frame, meters; covariance m²).
struct PointGaussian3 {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();      ///< meters
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero(); ///< m²
};

/// A weighted sample of a beacon position.
struct BeaconSample {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< meters, map frame
  double log_weight = 0.0;                             ///< natural log, unnormalized
};

/// A weighted Gaussian mode of a beacon position.
struct BeaconMode {
  PointGaussian3 gaussian;  ///< the mode
  double log_weight = 0.0;  ///< natural log, unnormalized
};

/// The form of a beacon's position density.
enum class BeaconPdfKind : std::uint8_t {
  MonteCarlo = 0,      ///< weighted samples (MRPT's pdfMonteCarlo)
  Gaussian = 1,        ///< one Gaussian (pdfGauss)
  SumOfGaussians = 2,  ///< weighted Gaussian modes (pdfSOG)
};

/// "montecarlo", "gaussian" or "sog".
std::string_view to_string(BeaconPdfKind kind) noexcept;

/// One beacon: its identifier and position density. Exactly the member
/// matching `kind` holds the density.
struct Beacon {
  std::int32_t id = 0;                              ///< the beacon's identifier
  BeaconPdfKind kind = BeaconPdfKind::Gaussian;   ///< which member below is used
  std::vector<BeaconSample> samples;                ///< kMonteCarlo
  PointGaussian3 gaussian;                          ///< kGaussian
  std::vector<BeaconMode> modes;                    ///< kSumOfGaussians

  /// The density's mean and covariance (for samples and modes: the
  /// moment-matched Gaussian, weights normalized). Precondition
  /// (InvalidArgument): samples/modes not empty for those kinds.
  PointGaussian3 moments() const;
};

/// How BeaconMap initialises and fuses beacons (MRPT's
/// CBeaconMap::TInsertionOptions; section `<prefix>_insertOpts`). Defaults
/// are MRPT's.
struct BeaconMapInsertOptions {
  /// true: a new beacon becomes Monte-Carlo samples; false: a sum of
  /// Gaussians (`insertAsMonteCarlo`).
  bool insert_as_monte_carlo = true;
  /// Elevation range of the initial ring, degrees (`minElevation_deg`,
  /// `maxElevation_deg`); both 0 (default) keeps beacons in the sensor's
  /// horizontal plane (2D). Must satisfy -90 <= min <= max <= 90.
  double min_elevation_deg = 0.0;
  double max_elevation_deg = 0.0;
  /// Samples per meter of ring radius (`MC_numSamplesPerMeter`).
  unsigned mc_samples_per_meter = 1000;
  /// Largest per-axis std. dev. (m) at which samples collapse into one
  /// Gaussian (`MC_maxStdToGauss`).
  double mc_max_std_to_gauss = 0.4;
  /// Samples whose log-weight is this far below the best are dropped
  /// (`MC_thresholdNegligible`).
  double mc_threshold_negligible = 5.0;
  /// Resample (systematic) when the effective sample size falls below half
  /// instead of dropping samples (`MC_performResampling`).
  bool mc_perform_resampling = false;
  /// Std. dev. (m) of the jitter added to samples after resampling
  /// (`MC_afterResamplingNoise`).
  double mc_after_resampling_noise = 0.01;
  /// Modes whose log-weight is this far below the best are dropped
  /// (`SOG_thresholdNegligible`).
  double sog_threshold_negligible = 20.0;
  /// Largest spacing (m) between neighbouring modes of the initial ring
  /// (`SOG_maxDistBetweenGaussians`).
  double sog_max_dist_between_gaussians = 1.0;
  /// Tangential std. dev. of a mode = mode spacing / this constant
  /// (`SOG_separationConstant`).
  double sog_separation_constant = 3.0;
  /// Seed of the map's random generator (rove only: `random_seed`).
  std::uint64_t random_seed = 0x5eed;

  /// Loads the keys present in `section` over the defaults. Throws
  /// ConfigError (file, section, key) on a malformed or out-of-range value.
  static BeaconMapInsertOptions from_config(const ConfigSection& section);
};

/// How BeaconMap evaluates range likelihoods (MRPT's
/// CBeaconMap::TLikelihoodOptions; section `<prefix>_likelihoodOpts`).
struct BeaconMapLikelihoodOptions {
  /// Std. dev. of a range measurement, meters (`rangeStd`); also the radial
  /// spread of a new beacon's ring. Must be > 0.
  double range_std = 0.08;
  /// Loads the keys present in `section` over the defaults.
  static BeaconMapLikelihoodOptions from_config(const ConfigSection& section);
};

/// A map of beacons. Thread-safety: thread-compatible; insert() draws from
/// the map's own random generator.
class BeaconMap final : public MetricMap {
 public:
  /// An empty map with the given options.
  explicit BeaconMap(BeaconMapInsertOptions insert_options = {},
                     BeaconMapLikelihoodOptions likelihood_options = {});

  /// The options (may be changed between insertions).
  BeaconMapInsertOptions insert_options;
  /// The likelihood options.
  BeaconMapLikelihoodOptions likelihood_options;

  /// The beacons, in order of first sighting.
  const std::vector<Beacon>& beacons() const noexcept { return beacons_; }
  /// The beacon with identifier `id`, or nullptr.
  const Beacon* find(std::int32_t id) const noexcept;
  /// Restarts the map's random generator (the Monte-Carlo rings of new
  /// beacons, the jitter after resampling their samples) from `seed`.
  void reseed(std::uint64_t seed) { rng_.seed(seed); }
  /// Adds a beacon (replacing one with the same id). Precondition
  /// (InvalidArgument): its density is not empty and finite.
  void add(Beacon beacon);

  /// "beaconMap".
  std::string_view kind() const noexcept override { return "beaconMap"; }
  /// Inserts a BeaconRanges observation (other kinds: false). Each reading
  /// with range > 0 creates (ring) or fuses its beacon.
  bool insert(const Observation& observation, const Pose3& T_map_robot) override;
  using MetricMap::insert;
  /// True for BeaconRanges.
  bool can_compute_likelihood(const Observation& observation) const override;
  /// Sum over readings of the log-likelihood of the range: for a known
  /// beacon, the Gaussian log-density (without its constant) of the range
  /// under the beacon's density (samples and modes averaged with their
  /// weights); for an unknown one, the uniform density over the sensor's
  /// [min, max] range. 0 for other observation kinds.
  double log_likelihood(const Observation& observation,
                        const Pose3& T_map_robot) const override;
  /// True when there is no beacon.
  bool empty() const override { return beacons_.empty(); }
  /// Removes every beacon.
  void clear() override { beacons_.clear(); }
  /// Box of the beacons' means.
  MapBounds bounding_box() const override;
  /// Beacon count.
  MapStatistics statistics() const override;

 private:
  void insert_new(std::int32_t id, double range, const Eigen::Vector3d& sensor);
  void fuse(Beacon& beacon, double range, const Eigen::Vector3d& sensor);
  Beacon* find_mutable(std::int32_t id) noexcept;

  std::vector<Beacon> beacons_;
  std::mt19937_64 rng_;
};

/// The sum-of-Gaussians ring of a first range `range_m` from `sensor`
/// (MRPT's CBeacon::generateRingSOG): modes spaced at most
/// sog_max_dist_between_gaussians along the ring (at least 30, an even
/// number), radial variance range_std², tangential variance
/// (spacing / sog_separation_constant)²; in 2D (equal elevation limits) the
/// z rows and columns of each covariance are zero. All weights 0.
/// Preconditions (InvalidArgument): range_m > 0 and finite.
std::vector<BeaconMode> beacon_ring_modes(double range_m, const Eigen::Vector3d& sensor,
                                          const BeaconMapInsertOptions& insert_options,
                                          const BeaconMapLikelihoodOptions& likelihood_options);

}  // namespace rove
