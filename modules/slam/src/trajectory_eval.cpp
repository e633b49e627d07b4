// Trajectory association, alignment, ATE, RPE and the relation metric.
#include "rove/slam/trajectory_eval.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/math/point_set_alignment.h"

namespace rove {

namespace {

/// The rotation angle of a unit quaternion, in [0, π].
double rotation_angle(const SE3d& T) {
  const Eigen::Quaterniond& q = T.quaternion();
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

/// Indices of `poses` sorted by time (stable: equal times keep file order).
std::vector<std::size_t> time_order(const std::vector<StampedPose3>& poses) {
  std::vector<std::size_t> order(poses.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return poses[a].time < poses[b].time; });
  return order;
}

std::string time_range(const std::vector<StampedPose3>& poses) {
  if (poses.empty()) return "no pose";
  const auto [lo, hi] = std::minmax_element(
      poses.begin(), poses.end(),
      [](const StampedPose3& a, const StampedPose3& b) { return a.time < b.time; });
  return fmt::format("{} poses, t {:.6f} .. {:.6f} s", poses.size(), lo->time, hi->time);
}

void check_association_options(const AssociationOptions& o) {
  ROVE_CHECK_MSG(std::isfinite(o.max_time_difference) && o.max_time_difference >= 0.0,
                 "max_time_difference {} is not a finite value >= 0", o.max_time_difference);
  ROVE_CHECK_MSG(std::isfinite(o.time_offset), "time_offset {} is not finite", o.time_offset);
}

TrajectoryAssociation associate_or_throw(const std::vector<StampedPose3>& reference,
                                         const std::vector<StampedPose3>& estimate,
                                         const AssociationOptions& options) {
  TrajectoryAssociation a = associate_by_time(reference, estimate, options);
  if (a.pairs.empty())
    throw InvalidArgument(fmt::format(
        "no estimate pose is within {} s of a reference pose (reference: {}; estimate: {})",
        options.max_time_difference, time_range(reference), time_range(estimate)));
  return a;
}

}  // namespace

ErrorStatistics error_statistics(const std::vector<double>& errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  for (const double e : errors) ROVE_CHECK_MSG(std::isfinite(e), "error {} is not finite", e);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const double n = static_cast<double>(errors.size());
  double sum = 0.0;
  for (const double e : errors) sum += e, s.sse += e * e;
  s.mean = sum / n;
  s.rmse = std::sqrt(s.sse / n);
  double var = 0.0;
  for (const double e : errors) var += (e - s.mean) * (e - s.mean);
  s.stddev = std::sqrt(var / n);
  const std::size_t m = sorted.size() / 2;
  s.median = sorted.size() % 2 == 1 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  s.min = sorted.front();
  s.max = sorted.back();
  return s;
}

TrajectoryAssociation associate_by_time(const std::vector<StampedPose3>& reference,
                                        const std::vector<StampedPose3>& estimate,
                                        const AssociationOptions& options) {
  check_association_options(options);
  const std::vector<std::size_t> ref_order = time_order(reference);
  // Candidates: for each estimate pose, the reference poses within the
  // tolerance (found by binary search on the sorted reference times).
  struct Candidate {
    double diff;
    std::size_t ref, est;
  };
  std::vector<Candidate> candidates;
  std::vector<double> ref_times(ref_order.size());
  for (std::size_t k = 0; k < ref_order.size(); ++k) ref_times[k] = reference[ref_order[k]].time;
  for (std::size_t e = 0; e < estimate.size(); ++e) {
    const double t = estimate[e].time + options.time_offset;
    auto it = std::lower_bound(ref_times.begin(), ref_times.end(),
                               t - options.max_time_difference);
    for (; it != ref_times.end() && *it <= t + options.max_time_difference; ++it) {
      const auto k = static_cast<std::size_t>(it - ref_times.begin());
      candidates.push_back({std::abs(*it - t), ref_order[k], e});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.diff < b.diff; });
  std::vector<bool> ref_used(reference.size(), false), est_used(estimate.size(), false);
  TrajectoryAssociation out;
  for (const Candidate& c : candidates) {
    if (ref_used[c.ref] || est_used[c.est]) continue;
    ref_used[c.ref] = est_used[c.est] = true;
    out.pairs.emplace_back(c.ref, c.est);
  }
  std::sort(out.pairs.begin(), out.pairs.end(), [&](const auto& a, const auto& b) {
    return estimate[a.second].time < estimate[b.second].time ||
           (estimate[a.second].time == estimate[b.second].time && a.second < b.second);
  });
  for (const std::size_t e : time_order(estimate))
    if (!est_used[e]) out.unmatched_estimate_times.push_back(estimate[e].time);
  return out;
}

TrajectoryAlignment parse_trajectory_alignment(std::string_view text) {
  if (text == "none") return TrajectoryAlignment::None;
  if (text == "se3") return TrajectoryAlignment::SE3;
  if (text == "se2") return TrajectoryAlignment::SE2;
  if (text == "sim3") return TrajectoryAlignment::Sim3;
  throw InvalidArgument(fmt::format("alignment '{}' is not none, se3, se2 or sim3", text));
}

std::string_view to_string(TrajectoryAlignment alignment) {
  switch (alignment) {
    case TrajectoryAlignment::None: return "none";
    case TrajectoryAlignment::SE3: return "se3";
    case TrajectoryAlignment::SE2: return "se2";
    case TrajectoryAlignment::Sim3: return "sim3";
  }
  return "?";
}

SE3d apply(const TrajectoryTransform& transform, const SE3d& pose) {
  const SE3d& T = transform.T_reference_estimate;
  return SE3d(T.rotation() * pose.rotation(),
              transform.scale * (T.rotation_matrix() * pose.translation()) + T.translation());
}

TrajectoryTransform align_trajectory(const std::vector<Eigen::Vector3d>& reference,
                                     const std::vector<Eigen::Vector3d>& estimate,
                                     TrajectoryAlignment alignment) {
  ROVE_CHECK_MSG(reference.size() == estimate.size() && !estimate.empty(),
                 "{} reference and {} estimate positions to align", reference.size(),
                 estimate.size());
  TrajectoryTransform out;
  switch (alignment) {
    case TrajectoryAlignment::None: return out;
    case TrajectoryAlignment::SE3:
    case TrajectoryAlignment::Sim3: {
      const PointSetAlignment<3> fit = align_point_sets<3>(
          estimate, reference, alignment == TrajectoryAlignment::Sim3);
      out.T_reference_estimate = SE3d(fit.R, fit.t);
      out.scale = fit.scale;
      out.degenerate = fit.degenerate;
      return out;
    }
    case TrajectoryAlignment::SE2: {
      std::vector<Eigen::Vector2d> ref_xy(reference.size()), est_xy(estimate.size());
      for (std::size_t k = 0; k < reference.size(); ++k) {
        ref_xy[k] = reference[k].head<2>();
        est_xy[k] = estimate[k].head<2>();
      }
      const PointSetAlignment<2> fit = align_point_sets<2>(est_xy, ref_xy);
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      R.topLeftCorner<2, 2>() = fit.R;
      out.T_reference_estimate = SE3d(R, Eigen::Vector3d(fit.t.x(), fit.t.y(), 0.0));
      out.degenerate = fit.degenerate;
      return out;
    }
  }
  return out;
}

AteResult absolute_trajectory_error(const std::vector<StampedPose3>& reference,
                                    const std::vector<StampedPose3>& estimate,
                                    const AteOptions& options) {
  AteResult out;
  out.association = associate_or_throw(reference, estimate, options.association);
  const auto& pairs = out.association.pairs;
  std::vector<Eigen::Vector3d> ref_p, est_p;
  for (const auto& [r, e] : pairs) {
    ref_p.push_back(reference[r].pose.translation());
    est_p.push_back(estimate[e].pose.translation());
  }
  out.transform = align_trajectory(ref_p, est_p, options.alignment);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : ref_p) centroid += p;
  centroid /= static_cast<double>(ref_p.size());
  double spread2 = 0.0;
  for (const auto& p : ref_p) spread2 += (p - centroid).squaredNorm();
  out.position_spread = std::sqrt(spread2 / static_cast<double>(ref_p.size()));
  for (const auto& [r, e] : pairs) {
    const SE3d aligned = apply(out.transform, estimate[e].pose);
    const SE3d& truth = reference[r].pose;
    out.times.push_back(reference[r].time);
    out.translation_errors.push_back((aligned.translation() - truth.translation()).norm());
    out.rotation_errors.push_back(rotation_angle(truth.inverse() * aligned));
    out.aligned_estimate.push_back(aligned);
  }
  out.translation = error_statistics(out.translation_errors);
  out.rotation = error_statistics(out.rotation_errors);
  return out;
}

RpeUnit parse_rpe_unit(std::string_view text) {
  if (text == "frames" || text == "f") return RpeUnit::Frames;
  if (text == "m") return RpeUnit::Meters;
  if (text == "s") return RpeUnit::Seconds;
  throw InvalidArgument(fmt::format("unit '{}' is not frames, m or s", text));
}

std::string_view to_string(RpeUnit unit) {
  switch (unit) {
    case RpeUnit::Frames: return "frames";
    case RpeUnit::Meters: return "m";
    case RpeUnit::Seconds: return "s";
  }
  return "?";
}

RpeResult relative_pose_error(const std::vector<StampedPose3>& reference,
                              const std::vector<StampedPose3>& estimate,
                              const RpeOptions& options) {
  ROVE_CHECK_MSG(std::isfinite(options.delta) && options.delta > 0.0,
                 "delta {} is not a finite value > 0", options.delta);
  ROVE_CHECK_MSG(options.unit != RpeUnit::Frames || options.delta == std::floor(options.delta),
                 "delta {} is not a whole number of frames", options.delta);
  ROVE_CHECK_MSG(std::isfinite(options.scale) && options.scale > 0.0,
                 "scale {} is not a finite value > 0", options.scale);
  RpeResult out;
  out.association = associate_or_throw(reference, estimate, options.association);
  const auto& pairs = out.association.pairs;
  const std::size_t n = pairs.size();
  // Distance of each associated pose from the first, in the unit.
  std::vector<double> at(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const StampedPose3& q = reference[pairs[k].first];
    switch (options.unit) {
      case RpeUnit::Frames: at[k] = static_cast<double>(k); break;
      case RpeUnit::Seconds: at[k] = q.time; break;
      case RpeUnit::Meters:
        at[k] = k == 0 ? 0.0
                       : at[k - 1] + (q.pose.translation() -
                                      reference[pairs[k - 1].first].pose.translation())
                                         .norm();
        break;
    }
  }
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    j = std::max(j, i + 1);
    while (j < n && at[j] - at[i] < options.delta) ++j;
    if (j >= n) break;
    out.intervals.emplace_back(i, j);
    const SE3d& Qi = reference[pairs[i].first].pose;
    const SE3d& Qj = reference[pairs[j].first].pose;
    const SE3d& Pi = estimate[pairs[i].second].pose;
    const SE3d& Pj = estimate[pairs[j].second].pose;
    SE3d dp = Pi.inverse() * Pj;
    dp = SE3d(dp.rotation(), options.scale * dp.translation());
    const SE3d E = (Qi.inverse() * Qj).inverse() * dp;
    out.times.push_back(reference[pairs[i].first].time);
    out.translation_errors.push_back(E.translation().norm());
    out.rotation_errors.push_back(rotation_angle(E));
  }
  if (out.intervals.empty())
    throw InvalidArgument(fmt::format("no two of the {} associated poses are {} {} apart", n,
                                      options.delta, to_string(options.unit)));
  out.translation = error_statistics(out.translation_errors);
  out.rotation = error_statistics(out.rotation_errors);
  return out;
}

std::vector<PoseRelation> map_relation_times(std::vector<PoseRelation> relations,
                                             std::vector<ClockPair> clock, double tolerance) {
  ROVE_CHECK_MSG(std::isfinite(tolerance) && tolerance >= 0.0,
                 "tolerance {} is not a finite value >= 0", tolerance);
  std::sort(clock.begin(), clock.end(),
            [](const ClockPair& a, const ClockPair& b) { return a.from < b.from; });
  auto mapped = [&](double t) {
    const auto it = std::lower_bound(clock.begin(), clock.end(), t,
                                     [](const ClockPair& c, double v) { return c.from < v; });
    const ClockPair* best = nullptr;
    double best_diff = tolerance;
    for (auto c : {it, it == clock.begin() ? it : it - 1}) {
      if (c == clock.end()) continue;
      if (const double d = std::abs(c->from - t); d <= best_diff) best_diff = d, best = &*c;
    }
    return best == nullptr ? t : best->to;
  };
  for (PoseRelation& r : relations) {
    r.t1 = mapped(r.t1);
    r.t2 = mapped(r.t2);
  }
  return relations;
}

RelationResult relation_error(const std::vector<StampedPose3>& estimate,
                              const std::vector<PoseRelation>& relations,
                              const RelationOptions& options) {
  ROVE_CHECK_MSG(std::isfinite(options.max_time_difference) && options.max_time_difference >= 0.0,
                 "max_time_difference {} is not a finite value >= 0",
                 options.max_time_difference);
  const std::vector<std::size_t> order = time_order(estimate);
  std::vector<double> times(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) times[k] = estimate[order[k]].time;
  // The estimate pose nearest to t within the tolerance, or nullptr.
  auto pose_at = [&](double t) -> const SE3d* {
    const auto it = std::lower_bound(times.begin(), times.end(), t);
    std::size_t best = times.size();
    double best_diff = options.max_time_difference;
    for (auto c : {it, it == times.begin() ? it : it - 1}) {
      if (c == times.end()) continue;
      const double d = std::abs(*c - t);
      if (d <= best_diff) best_diff = d, best = static_cast<std::size_t>(c - times.begin());
    }
    return best == times.size() ? nullptr : &estimate[order[best]].pose;
  };
  RelationResult out;
  out.relations = relations.size();
  for (const PoseRelation& rel : relations) {
    const SE3d* a = pose_at(rel.t1);
    const SE3d* b = pose_at(rel.t2);
    if (a == nullptr) out.missing_times.push_back(rel.t1);
    if (b == nullptr) out.missing_times.push_back(rel.t2);
    if (a == nullptr || b == nullptr) continue;
    const SE3d E = rel.T_1_2.inverse() * (a->inverse() * *b);
    out.translation_errors.push_back(E.translation().norm());
    out.rotation_errors.push_back(rotation_angle(E));
  }
  std::sort(out.missing_times.begin(), out.missing_times.end());
  out.missing_times.erase(std::unique(out.missing_times.begin(), out.missing_times.end()),
                          out.missing_times.end());
  out.used = out.translation_errors.size();
  if (out.used == 0) {
    std::string first;
    for (std::size_t k = 0; k < std::min<std::size_t>(3, out.missing_times.size()); ++k)
      first += fmt::format("{}{:.6f}", k == 0 ? "" : ", ", out.missing_times[k]);
    throw InvalidArgument(fmt::format(
        "none of the {} relations has both of its times in the estimate within {} s (first "
        "missing: {}; estimate: {})",
        relations.size(), options.max_time_difference, first.empty() ? "none" : first,
        time_range(estimate)));
  }
  auto squares = [](std::vector<double> v) {
    for (double& x : v) x *= x;
    return v;
  };
  out.translation = error_statistics(out.translation_errors);
  out.translation_squared = error_statistics(squares(out.translation_errors));
  out.rotation = error_statistics(out.rotation_errors);
  out.rotation_squared = error_statistics(squares(out.rotation_errors));
  return out;
}

}  // namespace rove
