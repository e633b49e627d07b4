#pragma once
/// \file
/// Running Monte-Carlo localization over a whole log, as MRPT's
/// pf-localization application does, from one configuration
/// (rove/slam/pf_localization_config.h): the map is built from the
/// config's map_file, the particles start as the config says, and each
/// step of the log moves and weighs them (rove/slam/mcl.h).
///
/// Steps: in a log of actions and sensory frames (layout #1) one step is an
/// action collection with the sensory frame after it; frames met before the
/// first action are passed over (as MRPT's getActionObservationPairOrObservation).
/// In an observation-only log (layout #2) odometry readings are accumulated
/// and every other observation is a step whose motion is the odometry
/// increment since the previous step, with the Gaussian model of
/// [DummyOdometryParams] (as MRPT). Unlike MRPT, which shows the initial
/// particles at step 0 without filtering its data, rove filters every
/// step, the first one included; the initial particles are a snapshot of
/// their own.
///
/// Convergence (ConvergenceOptions): a step is converged when the particles
/// are concentrated and the observations agree with the map at the
/// estimate; the run has converged at the first step of a run of at least
/// min_steps converged steps, and its result is Converged only if it is
/// still converged at its last step.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rove/bayes/particle_filter.h"
#include "rove/io/any_rawlog.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"
#include "rove/slam/mcl.h"
#include "rove/slam/pf_localization_config.h"

namespace rove {

/// What a map file was and what it gave.
struct LocalizationMapInfo {
  /// "simplemap", "gridmap", "ros-map-yaml", or "config" (no map_file).
  std::string kind = "config";
  /// The file read (resolved), empty for "config".
  std::string file;
  /// Keyframes of a simplemap inserted into the maps.
  std::size_t keyframes = 0;
  /// Observations inserted (simplemap).
  std::size_t observations_used = 0;
  /// The first occupancy grid's size (0 if none): cells along x and y and
  /// the cell side (m).
  std::uint32_t grid_size_x = 0, grid_size_y = 0;
  double grid_resolution = 0.0;
};

/// Builds the maps of `config.map` from `config.map_file` (resolved with
/// config.resolve): a simplemap's keyframes are inserted into every map (as
/// MRPT's loadFromProbabilisticPosesAndObservations); a .gridmap (MRPT) or
/// a ROS map.yaml replaces the cells of the first occupancy grid (a
/// .gridmap also its insertion and likelihood options, which MRPT stores
/// in the file and its pf-localization takes from there). Throws
/// ConfigError naming map_file when the file does not exist, its kind is
/// unknown, or a grid file meets a configuration without occupancy grid;
/// IoError / ParseError on unreadable files; ConfigError if every map
/// stays empty although a simplemap was given.
LocalizationMapInfo load_localization_map(const PfLocalizationConfig& config, MultiMetricMap& map);

/// One step of a run: the state after processing it.
struct PfLocalizationStep {
  /// 0-based step index in the log (counting steps skipped by rawlog_offset).
  std::uint64_t index = 0;
  /// Time of the step's first observation (invalid if none has one).
  Timestamp time;
  /// The estimate after the update.
  MclEstimate estimate;
  /// Particles after the step.
  std::size_t particles = 0;
  /// ESS/N after the update, before any resampling.
  double ess = 1.0;
  /// True if the map could evaluate the step's observations.
  bool informative = false;
  /// True if every particle had zero likelihood and the observation was
  /// ignored (the filter's Degenerate termination).
  bool degenerate = false;
  /// Scan agreement with the map at the estimate (see MclStepResult).
  std::optional<double> scan_fit;
  /// Range residual at the estimate, in standard deviations.
  std::optional<double> range_residual;
  /// Share of the weight within ConvergenceOptions::radius and
  /// heading_radius of the estimate.
  double mass_near = 0.0;
  /// Concentrated and agreeing with the map.
  bool converged = false;
  /// Particles replaced by random ones (recovery).
  std::size_t injected = 0;
  /// The accumulated odometry after the step (from initial_odo_*).
  Pose2 odometry;
  /// The ground-truth pose of the step, when ground_truth_path_file has it.
  std::optional<Pose2> ground_truth;
  /// Wall time of the filter step, seconds (reading excluded).
  double seconds = 0.0;
};

/// The particles at one moment of a run.
struct PfLocalizationSnapshot {
  /// The step after which they were taken; unset: the initial particles.
  std::optional<std::uint64_t> step;
  /// Why: "initial", "converged", "final" or "periodic".
  std::string reason;
  /// The particles.
  ParticleSet<SE2d> particles;
};

/// How a run ended.
enum class PfLocalizationTermination : std::uint8_t {
  /// Converged, and still converged at the last step.
  Converged,
  /// Never converged (ConvergenceOptions were never met long enough).
  NotConverged,
  /// Converged at some point, but not at the last step.
  Lost,
};

/// "converged", "not-converged" or "lost".
std::string_view to_string(PfLocalizationTermination termination) noexcept;

/// Something the user must know about a finished run.
struct PfLocalizationIssue {
  /// "not-converged", "lost", "degenerate-steps", "no-observations".
  std::string code;
  /// One line for a person.
  std::string message;
};

/// Options of run_pf_localization (what the command line sets).
struct PfLocalizationRunOptions {
  /// Seed of the run's random numbers.
  std::uint64_t seed = 0;
  /// Threads (1–256, 0 all); the result does not depend on it.
  int num_threads = 1;
  /// Replace the configuration's initial particles.
  std::optional<ParticleInit> init;
  /// Replace the configuration's recovery options.
  std::optional<RecoveryOptions> recovery;
  /// Stop after this many processed steps (all if unset).
  std::optional<std::uint64_t> max_steps;
  /// Also keep the particles every this many steps (0: only the initial,
  /// first converged and final sets).
  std::uint64_t snapshot_every = 0;
  /// Options of the log reader.
  AnyRawlogOptions reader;
  /// Called after every processed step, if set.
  std::function<void(const PfLocalizationStep&)> on_step;
};

/// The result of run_pf_localization.
struct PfLocalizationResult {
  /// How the run ended.
  PfLocalizationTermination termination = PfLocalizationTermination::NotConverged;
  /// One line: the termination with its steps.
  std::string message;
  /// Every processed step, in order.
  std::vector<PfLocalizationStep> steps;
  /// Particle snapshots, in order.
  std::vector<PfLocalizationSnapshot> snapshots;
  /// Index of the step at which the run converged (first step of its last
  /// converged streak), if it ended converged.
  std::optional<std::uint64_t> converged_step;
  /// Index of the step at which it first converged, if ever.
  std::optional<std::uint64_t> first_converged_step;
  /// Most particles held after any step (or initially).
  std::size_t peak_particles = 0;
  /// Sum of the steps' filter times, seconds.
  double filter_seconds = 0.0;
  /// Time to load and build the map, seconds.
  double map_seconds = 0.0;
  /// Time spent reading the log, seconds.
  double read_seconds = 0.0;
  /// The log's format and entries read.
  RawlogFormat format = RawlogFormat::Mrpt;
  std::uint64_t entries = 0;
  /// The map used (shared: the picture of the outputs draws it).
  std::shared_ptr<const MultiMetricMap> map;
  /// What the map file gave.
  LocalizationMapInfo map_info;
  /// The options the filter ran with (seed, threads, overrides applied).
  MclOptions options;
  /// Position RMSE against the ground truth over the steps that have one,
  /// meters, if any.
  std::optional<double> ground_truth_rmse;
  /// What the user must know (empty when fine).
  std::vector<PfLocalizationIssue> issues;
  /// True only when the run ended converged.
  bool ok() const noexcept { return termination == PfLocalizationTermination::Converged; }
};

/// Localizes the robot of the log at `rawlog_path` in the configuration's
/// map (the configuration is taken over: its map declaration is filled and
/// kept in the result): loads the map (load_localization_map) and the ground truth, draws
/// the initial particles and runs a MonteCarloLocalization step per log
/// step, polling rove::throw_if_interrupted() once per entry. Throws
/// ConfigError / IoError / ParseError on unusable configuration, map or log
/// (ParseError names the step's offset when the filter rejects an
/// observation); SelectionError when rawlog_offset skips every step or the
/// log holds no step. A run that never converges, or loses its convergence,
/// is a result with that termination and an issue, not an error.
PfLocalizationResult run_pf_localization(PfLocalizationConfig config,
                                         const std::string& rawlog_path,
                                         const PfLocalizationRunOptions& options = {});

}  // namespace rove
