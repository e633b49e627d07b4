#include "rove/slam/trajectory_eval_run.h"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "rove/core/error.h"

namespace rove {

namespace {

/// Times listed in an issue before "and N more".
constexpr std::size_t kTimesListed = 5;

std::string listed_times(const std::vector<double>& times) {
  std::string s;
  for (std::size_t k = 0; k < std::min(times.size(), kTimesListed); ++k)
    s += fmt::format("{}{:.6f}", k == 0 ? "" : ", ", times[k]);
  if (times.size() > kTimesListed) s += fmt::format(" and {} more", times.size() - kTimesListed);
  return s;
}

std::vector<TrajectoryEvalIssue> association_issues(const TrajectoryAssociation& a,
                                                    std::size_t estimate_size) {
  std::vector<TrajectoryEvalIssue> issues;
  if (!a.unmatched_estimate_times.empty())
    issues.push_back({"unassociated",
                      fmt::format("{} of {} estimate poses have no reference pose within the "
                                  "time tolerance: t = {}",
                                  a.unmatched_estimate_times.size(), estimate_size,
                                  listed_times(a.unmatched_estimate_times))});
  return issues;
}

}  // namespace

AteEvaluation evaluate_ate(const std::vector<StampedPose3>& reference,
                           const std::vector<StampedPose3>& estimate, const AteOptions& options) {
  AteEvaluation e;
  e.result = absolute_trajectory_error(reference, estimate, options);
  const AteResult& r = e.result;
  e.issues = association_issues(r.association, estimate.size());
  if (r.transform.degenerate)
    e.issues.push_back({"degenerate-alignment",
                        "the associated positions lie on a line: the rotation about it is not "
                        "determined by the alignment"});
  if (options.alignment != TrajectoryAlignment::None &&
      r.position_spread < 10.0 * r.translation.rmse) {
    e.issues.push_back(
        {"weak-alignment-rotation",
         fmt::format("the associated positions spread only {:.3g} m (RMS about their centroid), "
                     "under 10 times the position RMSE ({:.3g} m): the alignment's rotation, "
                     "taken from the positions, is weakly determined, and the rotation errors "
                     "mostly show it (rove eval rpe measures rotation without an alignment)",
                     r.position_spread, r.translation.rmse)});
  }
  return e;
}

RpeEvaluation evaluate_rpe(const std::vector<StampedPose3>& reference,
                           const std::vector<StampedPose3>& estimate, const RpeOptions& options,
                           TrajectoryAlignment alignment) {
  if (alignment != TrajectoryAlignment::None && alignment != TrajectoryAlignment::Sim3)
    throw InvalidArgument(fmt::format("RPE alignment '{}': expected none or sim3 (the estimate's "
                                      "scale); the RPE needs no rotation alignment",
                                      to_string(alignment)));
  RpeOptions o = options;
  if (alignment == TrajectoryAlignment::Sim3) {
    AteOptions ate;
    ate.association = o.association;
    ate.alignment = alignment;
    o.scale = absolute_trajectory_error(reference, estimate, ate).transform.scale;
  }
  RpeEvaluation e;
  e.result = relative_pose_error(reference, estimate, o);
  e.scale = o.scale;
  e.issues = association_issues(e.result.association, estimate.size());
  return e;
}

RelationEvaluation evaluate_relations(const std::vector<StampedPose3>& estimate,
                                      std::vector<PoseRelation> relations,
                                      const RelationOptions& options,
                                      const std::optional<std::vector<ClockPair>>& clock) {
  if (clock)
    relations = map_relation_times(std::move(relations), *clock, options.max_time_difference);
  RelationEvaluation e;
  e.result = relation_error(estimate, relations, options);
  const RelationResult& r = e.result;
  if (!r.missing_times.empty())
    e.issues.push_back({"missing-times",
                        fmt::format("{} of {} relations left out: the estimate has no pose "
                                    "within {} s of t = {}",
                                    r.relations - r.used, r.relations, options.max_time_difference,
                                    listed_times(r.missing_times))});
  return e;
}

}  // namespace rove
