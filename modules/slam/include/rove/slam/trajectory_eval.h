#pragma once
/// \file
/// Trajectory evaluation, in the spirit of evo and of the TUM RGB-D and
/// Freiburg benchmark tools (docs/eval.md):
///  - association of an estimate with a reference by timestamp;
///  - alignment of the estimate onto the reference (SE(3), SE(2), Sim(3) or
///    none; Umeyama 1991 on the associated positions);
///  - the absolute trajectory error (ATE; Sturm et al., IROS 2012);
///  - the relative pose error over a distance in frames, meters or seconds
///    (RPE; same paper);
///  - the relation metric of Kümmerle et al., "On measuring the accuracy of
///    SLAM algorithms", Auton. Robots 27(4), 2009.
/// Errors: translation in meters, rotation as the angle of the error
/// rotation in radians.

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rove/io/trajectory_files.h"
#include "rove/math/se3.h"

namespace rove {

/// Summary of a list of errors (population standard deviation, as evo).
struct ErrorStatistics {
  std::size_t count = 0;  ///< number of errors
  double rmse = 0.0;      ///< sqrt(mean of squares)
  double mean = 0.0;
  double median = 0.0;    ///< mean of the two middle values for an even count
  double stddev = 0.0;    ///< population standard deviation
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;  ///< sum of squares
};

/// The statistics of `errors` (all zero for an empty list). Throws
/// InvalidArgument for a value that is not finite.
ErrorStatistics error_statistics(const std::vector<double>& errors);

/// How estimate and reference poses are paired.
struct AssociationOptions {
  /// Largest |t_reference − (t_estimate + time_offset)| of a pair, seconds.
  /// Default 0.01 (TUM's associate.py and evo use 0.02 and 0.01).
  double max_time_difference = 0.01;
  /// Added to every estimate time before pairing, seconds. Default 0.
  double time_offset = 0.0;
};

/// Pairs of reference and estimate poses.
struct TrajectoryAssociation {
  /// (reference index, estimate index), in the order of the estimate's
  /// times; each index at most once.
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  /// Times of the estimate's poses left without a reference pose.
  std::vector<double> unmatched_estimate_times;
};

/// Pairs each estimate pose with the reference pose nearest in time within
/// the tolerance, one-to-one, closest differences first (TUM's
/// associate.py). The inputs need not be sorted. Throws InvalidArgument
/// for a negative or non-finite tolerance or offset.
TrajectoryAssociation associate_by_time(const std::vector<StampedPose3>& reference,
                                        const std::vector<StampedPose3>& estimate,
                                        const AssociationOptions& options = {});

/// The transformation that brings the estimate onto the reference.
enum class TrajectoryAlignment {
  None,  ///< compare as they are
  SE3,   ///< rotation and translation in 3D
  SE2,   ///< rotation about z and translation in x and y (planar robots)
  Sim3,  ///< SE3 and a scale (monocular estimates)
};

/// Parses "none", "se3", "se2" or "sim3"; throws InvalidArgument otherwise.
TrajectoryAlignment parse_trajectory_alignment(std::string_view text);
/// The lowercase name (parse_trajectory_alignment's input).
std::string_view to_string(TrajectoryAlignment alignment);

/// reference ≈ scale·R·estimate + t applied to the estimate's poses: each
/// pose becomes (R·R_k, scale·R·t_k + t).
struct TrajectoryTransform {
  SE3d T_reference_estimate;  ///< R and t
  double scale = 1.0;         ///< 1 unless Sim3
  /// The estimate's positions lie on a line: a rotation about it is not
  /// determined by the positions (the aligned errors are still minimal).
  bool degenerate = false;
};

/// Applies `transform` to a pose of the estimate.
SE3d apply(const TrajectoryTransform& transform, const SE3d& pose);

/// The least-squares alignment of `estimate` onto `reference` (paired by
/// index). Throws InvalidArgument if the sizes differ or are 0, or for Sim3
/// when the estimate's positions all coincide.
TrajectoryTransform align_trajectory(const std::vector<Eigen::Vector3d>& reference,
                                     const std::vector<Eigen::Vector3d>& estimate,
                                     TrajectoryAlignment alignment);

/// Options of absolute_trajectory_error.
struct AteOptions {
  AssociationOptions association;  ///< pairing by time
  TrajectoryAlignment alignment = TrajectoryAlignment::SE3;  ///< default SE3
};

/// The absolute trajectory error: after alignment, the position error and
/// the rotation error of every associated pose.
struct AteResult {
  TrajectoryAssociation association;  ///< the pairs used
  TrajectoryTransform transform;      ///< the alignment applied to the estimate
  ErrorStatistics translation;        ///< meters
  ErrorStatistics rotation;           ///< radians
  std::vector<double> times;               ///< reference time of each pair
  std::vector<double> translation_errors;  ///< per pair, meters
  std::vector<double> rotation_errors;     ///< per pair, radians
  std::vector<SE3d> aligned_estimate;      ///< the estimate's paired poses after alignment
  /// RMS distance of the paired reference positions from their centroid,
  /// meters. The alignment takes its rotation from the positions alone (as
  /// evo does): when they spread little more than the position errors (a
  /// camera turning in place), that rotation is weakly determined and the
  /// rotation errors mostly show it.
  double position_spread = 0.0;
};

/// ATE of `estimate` against `reference`. Throws InvalidArgument if no pose
/// associates (the message gives both time ranges).
AteResult absolute_trajectory_error(const std::vector<StampedPose3>& reference,
                                    const std::vector<StampedPose3>& estimate,
                                    const AteOptions& options = {});

/// What the RPE's distance counts.
enum class RpeUnit {
  Frames,   ///< associated poses
  Meters,   ///< path length of the reference
  Seconds,  ///< reference time
};

/// Parses "frames", "m" or "s"; throws InvalidArgument otherwise.
RpeUnit parse_rpe_unit(std::string_view text);
/// "frames", "m" or "s".
std::string_view to_string(RpeUnit unit);

/// Options of relative_pose_error.
struct RpeOptions {
  AssociationOptions association;  ///< pairing by time
  double delta = 1.0;              ///< > 0; a whole number for Frames. Default 1
  RpeUnit unit = RpeUnit::Frames;  ///< default Frames
  /// Scale applied to the estimate's relative translations (1: none). A
  /// Sim3 ATE alignment's scale makes monocular RPE meaningful.
  double scale = 1.0;
};

/// The relative pose error over pose pairs (i, j) of the associated poses,
/// j the first pose at least `delta` after i: E = (Q_i⁻¹Q_j)⁻¹(P_i⁻¹P_j),
/// Q the reference, P the estimate.
struct RpeResult {
  TrajectoryAssociation association;  ///< the pairs of poses associated by time
  /// (i, j) as indices into association.pairs, one per relative pose.
  std::vector<std::pair<std::size_t, std::size_t>> intervals;
  ErrorStatistics translation;             ///< meters
  ErrorStatistics rotation;                ///< radians
  std::vector<double> times;               ///< reference time at i
  std::vector<double> translation_errors;  ///< per interval
  std::vector<double> rotation_errors;     ///< per interval
};

/// RPE of `estimate` against `reference`. Throws InvalidArgument for a delta
/// that is not > 0 (or not whole in Frames), if no pose associates, or if no
/// interval of that length fits in the associated poses.
RpeResult relative_pose_error(const std::vector<StampedPose3>& reference,
                              const std::vector<StampedPose3>& estimate,
                              const RpeOptions& options = {});

/// Options of relation_error.
struct RelationOptions {
  /// Largest difference between a relation's time and the estimate pose
  /// taken for it, seconds. Default 1e-3 (the relations name the log's
  /// own timestamps).
  double max_time_difference = 1e-3;
};

/// The relation metric: for each relation whose two times the estimate has
/// a pose at, the error of the estimate's relative pose against it.
struct RelationResult {
  std::size_t relations = 0;  ///< in the file
  std::size_t used = 0;       ///< with both times found in the estimate
  /// Relation times with no estimate pose within the tolerance (each once,
  /// sorted).
  std::vector<double> missing_times;
  ErrorStatistics translation;          ///< |t(δ*⁻¹·δ)|, meters
  ErrorStatistics translation_squared;  ///< its square, m²
  ErrorStatistics rotation;             ///< angle of δ*⁻¹·δ, radians
  ErrorStatistics rotation_squared;     ///< its square, rad²
  std::vector<double> translation_errors;  ///< per used relation
  std::vector<double> rotation_errors;     ///< per used relation
};

/// One instant read on two clocks (e.g. a CARMEN line's ipc and logger
/// timestamps).
struct ClockPair {
  double from = 0.0;  ///< seconds on the relations' clock
  double to = 0.0;    ///< seconds on the estimate's clock
};

/// The relations with each time moved to the estimate's clock: a time within
/// `tolerance` of a pair's `from` becomes that pair's `to` (the nearest);
/// other times are kept (and then reported missing by relation_error).
/// Freiburg's relations name the FLASER lines' ipc timestamps, while rove's
/// trajectories of CARMEN logs carry the logger timestamps. Throws
/// InvalidArgument for a negative or non-finite tolerance.
std::vector<PoseRelation> map_relation_times(std::vector<PoseRelation> relations,
                                             std::vector<ClockPair> clock, double tolerance);

/// The relation error of `estimate`. Throws InvalidArgument if the tolerance
/// is negative or not finite, or if no relation can be used (the message
/// names the first missing times and the estimate's time range).
RelationResult relation_error(const std::vector<StampedPose3>& estimate,
                              const std::vector<PoseRelation>& relations,
                              const RelationOptions& options = {});

}  // namespace rove
