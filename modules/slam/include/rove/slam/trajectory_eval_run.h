#pragma once
/// \file
/// The evaluations of `rove eval ate|rpe|relations` as library calls (also
/// what rove.eval_* run): trajectory_eval.h's metrics with the checks the
/// command reports as issues (poses or relations left out, an alignment
/// whose rotation is weakly determined).

#include <optional>
#include <string>
#include <vector>

#include "rove/io/trajectory_files.h"
#include "rove/slam/trajectory_eval.h"

namespace rove {

/// Something an evaluation must tell its user: the figures were computed,
/// but on less than the inputs hold, or they mean less than they seem to.
struct TrajectoryEvalIssue {
  /// "unassociated" (estimate poses without a reference pose in time),
  /// "degenerate-alignment" (positions on a line), "weak-alignment-rotation"
  /// (positions spread under 10 times the position RMSE), "missing-times"
  /// (relations without estimate poses at their times).
  std::string code;
  std::string message;  ///< one line for a person, with the counts and times
};

/// An ATE with its issues.
struct AteEvaluation {
  AteResult result;
  std::vector<TrajectoryEvalIssue> issues;
};

/// absolute_trajectory_error and the issues of its result. Throws what it
/// throws (InvalidArgument when nothing associates, for a bad tolerance).
AteEvaluation evaluate_ate(const std::vector<StampedPose3>& reference,
                           const std::vector<StampedPose3>& estimate, const AteOptions& options = {});

/// An RPE with its issues.
struct RpeEvaluation {
  RpeResult result;
  /// The scale applied to the estimate's relative translations (the Sim(3)
  /// ATE alignment's scale with TrajectoryAlignment::Sim3, else 1).
  double scale = 1.0;
  std::vector<TrajectoryEvalIssue> issues;
};

/// relative_pose_error; with `alignment` Sim3 the estimate is first scaled
/// by its Sim(3) alignment onto the reference (monocular estimates; this
/// replaces options.scale). Throws InvalidArgument for an alignment other
/// than None and Sim3, and what relative_pose_error throws.
RpeEvaluation evaluate_rpe(const std::vector<StampedPose3>& reference,
                           const std::vector<StampedPose3>& estimate, const RpeOptions& options = {},
                           TrajectoryAlignment alignment = TrajectoryAlignment::None);

/// A relation error with its issues.
struct RelationEvaluation {
  RelationResult result;
  std::vector<TrajectoryEvalIssue> issues;
};

/// relation_error; with `clock` (a CARMEN log's, carmen_log_clock) the
/// relations' times are first taken to the estimate's clock
/// (map_relation_times, within options.max_time_difference). Throws what
/// relation_error throws.
RelationEvaluation evaluate_relations(const std::vector<StampedPose3>& estimate,
                                      std::vector<PoseRelation> relations,
                                      const RelationOptions& options = {},
                                      const std::optional<std::vector<ClockPair>>& clock = std::nullopt);

}  // namespace rove
