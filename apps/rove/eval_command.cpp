// `rove eval ate|rpe|relations`: trajectory evaluation. A thin layer over
// rove/slam/trajectory_eval_run.h (the metrics and their issues) and
// trajectory_input.h (the files); the plot is drawn by eval_plot.cpp.

#include <fmt/format.h>

#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "eval_plot.h"
#include "report.h"
#include "rove/core/files.h"
#include "rove/core/json.h"
#include "rove/io/trajectory_files.h"
#include "rove/slam/trajectory_eval.h"
#include "rove/slam/trajectory_eval_run.h"
#include "rove/slam/trajectory_input.h"

namespace rove::cli {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

struct EvalArgs {
  std::string first, second;  // GT EST (ate, rpe) or EST RELATIONS
  std::string format = "auto", align = "se3", unit = "frames", plot, log;
  double max_dt = 0.01, offset = 0.0, delta = 1.0;
  bool json = false;
};

void write_stats(JsonWriter& j, std::string_view name, const ErrorStatistics& s) {
  j.key(name).begin_object();
  j.key("count").value(static_cast<std::uint64_t>(s.count));
  j.key("rmse").value(s.rmse).key("mean").value(s.mean).key("median").value(s.median);
  j.key("std").value(s.stddev).key("min").value(s.min).key("max").value(s.max);
  j.key("sse").value(s.sse);
  j.end_object();
}

void print_stats(std::string_view name, const ErrorStatistics& s, double factor,
                 std::string_view unit) {
  fmt::print("{:<14} rmse {:.6g}  mean {:.6g}  median {:.6g}  std {:.6g}  min {:.6g}  max {:.6g} {}\n",
             name, s.rmse * factor, s.mean * factor, s.median * factor, s.stddev * factor,
             s.min * factor, s.max * factor, unit);
}

std::vector<Issue> issues_of(const std::vector<TrajectoryEvalIssue>& found) {
  std::vector<Issue> issues;
  for (const auto& i : found) issues.push_back({i.code, i.message});
  return issues;
}

void begin_report(JsonWriter& j, std::string_view metric, const EvalArgs& a, const LoadedTrajectory& ref,
                  const LoadedTrajectory& est) {
  j.begin_object();
  j.key("metric").value(metric);
  j.key("reference").begin_object().key("file").value(a.first).key("format").value(ref.format);
  j.key("poses").value(static_cast<std::uint64_t>(ref.poses.size())).end_object();
  j.key("estimate").begin_object().key("file").value(a.second).key("format").value(est.format);
  j.key("poses").value(static_cast<std::uint64_t>(est.poses.size())).end_object();
}

void run_ate(const EvalArgs& a) {
  if (!a.plot.empty()) check_outputs_distinct({a.first, a.second}, {a.plot});
  const LoadedTrajectory ref = load_trajectory(a.first, a.format);
  const LoadedTrajectory est = load_trajectory(a.second, a.format);
  AteOptions o;
  o.association = {a.max_dt, a.offset};
  o.alignment = parse_trajectory_alignment(a.align);
  const AteEvaluation e = evaluate_ate(ref.poses, est.poses, o);
  const AteResult& r = e.result;
  const std::vector<Issue> issues = issues_of(e.issues);
  if (!a.plot.empty()) {
    std::vector<Eigen::Vector3d> ref_xy, est_xy;
    for (const auto& [i, est_index] : r.association.pairs) ref_xy.push_back(ref.poses[i].pose.translation());
    for (const SE3d& p : r.aligned_estimate) est_xy.push_back(p.translation());
    write_ate_plot(ref_xy, est_xy, r.times, r.translation_errors, a.plot);
  }
  const Eigen::Vector3d t = r.transform.T_reference_estimate.translation();
  if (a.json) {
    JsonWriter j;
    begin_report(j, "ate", a, ref, est);
    j.key("pairs").value(static_cast<std::uint64_t>(r.association.pairs.size()));
    j.key("alignment").begin_object().key("method").value(to_string(o.alignment));
    j.key("scale").value(r.transform.scale);
    j.key("translation").begin_array().value(t.x()).value(t.y()).value(t.z()).end_array();
    const Eigen::Quaterniond& q = r.transform.T_reference_estimate.quaternion();
    j.key("quaternion_xyzw").begin_array().value(q.x()).value(q.y()).value(q.z()).value(q.w()).end_array();
    j.key("position_spread_m").value(r.position_spread);
    j.end_object();
    write_stats(j, "translation_m", r.translation);
    write_stats(j, "rotation_rad", r.rotation);
    j.key("plot");
    if (a.plot.empty()) j.null(); else j.value(a.plot);
    write_issues(j, issues);
    j.end_object();
    fmt::print("{}\n", j.str());
  } else {
    fmt::print("ATE of {} ({}, {} poses) against {} ({}, {} poses)\n", printable(a.second),
               est.format, est.poses.size(), printable(a.first), ref.format, ref.poses.size());
    fmt::print("pairs          {} (time tolerance {} s, offset {} s)\n",
               r.association.pairs.size(), a.max_dt, a.offset);
    fmt::print("alignment      {}: t = ({:.6g}, {:.6g}, {:.6g}) m, scale {:.6g}; positions spread "
               "{:.4g} m\n",
               to_string(o.alignment), t.x(), t.y(), t.z(), r.transform.scale, r.position_spread);
    print_stats("translation", r.translation, 1.0, "m");
    print_stats("rotation", r.rotation, kDeg, "deg");
    if (!a.plot.empty()) fmt::print("plot           {}\n", printable(a.plot));
  }
  finish(issues);
}

void run_rpe(const EvalArgs& a) {
  const LoadedTrajectory ref = load_trajectory(a.first, a.format);
  const LoadedTrajectory est = load_trajectory(a.second, a.format);
  RpeOptions o;
  o.association = {a.max_dt, a.offset};
  o.delta = a.delta;
  o.unit = parse_rpe_unit(a.unit);
  const RpeEvaluation e = evaluate_rpe(ref.poses, est.poses, o, parse_trajectory_alignment(a.align));
  const RpeResult& r = e.result;
  o.scale = e.scale;
  const std::vector<Issue> issues = issues_of(e.issues);
  if (a.json) {
    JsonWriter j;
    begin_report(j, "rpe", a, ref, est);
    j.key("pairs").value(static_cast<std::uint64_t>(r.association.pairs.size()));
    j.key("delta").value(o.delta).key("unit").value(to_string(o.unit));
    j.key("scale").value(o.scale);
    j.key("intervals").value(static_cast<std::uint64_t>(r.intervals.size()));
    write_stats(j, "translation_m", r.translation);
    write_stats(j, "rotation_rad", r.rotation);
    write_issues(j, issues);
    j.end_object();
    fmt::print("{}\n", j.str());
  } else {
    fmt::print("RPE of {} ({}, {} poses) against {} ({}, {} poses)\n", printable(a.second),
               est.format, est.poses.size(), printable(a.first), ref.format, ref.poses.size());
    fmt::print("pairs          {}; {} intervals of {} {}{}\n", r.association.pairs.size(),
               r.intervals.size(), o.delta, to_string(o.unit),
               o.scale != 1.0 ? fmt::format(", estimate scaled by {:.6g} (sim3)", o.scale) : "");
    print_stats("translation", r.translation, 1.0, "m");
    print_stats("rotation", r.rotation, kDeg, "deg");
  }
  finish(issues);
}

void run_relations(const EvalArgs& a) {
  const LoadedTrajectory est = load_trajectory(a.first, a.format);
  RelationOptions o;
  o.max_time_difference = a.max_dt;
  std::optional<std::vector<ClockPair>> clock;
  if (!a.log.empty()) clock = carmen_log_clock(a.log);
  const RelationEvaluation e = evaluate_relations(est.poses, read_relations(a.second), o, clock);
  const RelationResult& r = e.result;
  const std::vector<Issue> issues = issues_of(e.issues);
  if (a.json) {
    JsonWriter j;
    j.begin_object();
    j.key("metric").value("relations");
    j.key("estimate").begin_object().key("file").value(a.first).key("format").value(est.format);
    j.key("poses").value(static_cast<std::uint64_t>(est.poses.size())).end_object();
    j.key("relations_file").value(a.second);
    j.key("relations").value(static_cast<std::uint64_t>(r.relations));
    j.key("used").value(static_cast<std::uint64_t>(r.used));
    write_stats(j, "translation_m", r.translation);
    write_stats(j, "translation_squared_m2", r.translation_squared);
    write_stats(j, "rotation_rad", r.rotation);
    write_stats(j, "rotation_squared_rad2", r.rotation_squared);
    write_issues(j, issues);
    j.end_object();
    fmt::print("{}\n", j.str());
  } else {
    fmt::print("relation error of {} ({}, {} poses) on {}\n", printable(a.first), est.format,
               est.poses.size(), printable(a.second));
    fmt::print("relations      {} used of {}\n", r.used, r.relations);
    fmt::print("translation    {:.4f} ± {:.4f} m (abs, mean ± std), squared {:.4f} ± {:.4f} m², max {:.4f} m\n",
               r.translation.mean, r.translation.stddev, r.translation_squared.mean,
               r.translation_squared.stddev, r.translation.max);
    fmt::print("rotation       {:.4f} ± {:.4f} deg (abs, mean ± std), squared {:.4f} ± {:.4f} deg², max {:.4f} deg\n",
               r.rotation.mean * kDeg, r.rotation.stddev * kDeg, r.rotation_squared.mean * kDeg * kDeg,
               r.rotation_squared.stddev * kDeg * kDeg, r.rotation.max * kDeg);
  }
  finish(issues);
}

void add_common(CLI::App* cmd, EvalArgs& a, double default_max_dt) {
  a.max_dt = default_max_dt;
  cmd->add_option("--format", a.format,
                  "Trajectory format: auto (TUM if 8 fields a row, KITTI if 12, graph vertices "
                  "for .g2o/.graph) | tum | kitti | graph")
      ->check(CLI::IsMember({"auto", "tum", "kitti", "graph"}))
      ->capture_default_str();
  cmd->add_option("--max-dt", a.max_dt, "Largest time difference of an associated pair, seconds")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("--json", a.json, "Print the result as one JSON object");
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto* eval = app.add_subcommand(
      "eval", "Evaluate a trajectory against ground truth (ATE, RPE) or relations (Kümmerle et "
              "al. 2009). Exit status: 0 ok, 1 error, 3 evaluated with issues (poses or "
              "relations that could not be associated)");
  eval->require_subcommand(1);

  auto ate = std::make_shared<EvalArgs>();
  auto* c = eval->add_subcommand("ate", "Absolute trajectory error after alignment");
  c->add_option("GT", ate->first, "Reference trajectory (TUM, KITTI or g2o/TORO)")->required();
  c->add_option("EST", ate->second, "Estimated trajectory")->required();
  add_common(c, *ate, 0.01);
  c->add_option("--align", ate->align, "Alignment of the estimate: se3 | se2 | sim3 | none")
      ->check(CLI::IsMember({"se3", "se2", "sim3", "none"}))
      ->capture_default_str();
  c->add_option("--offset", ate->offset, "Seconds added to the estimate's times")->capture_default_str();
  c->add_option("--plot", ate->plot,
                "PNG: both trajectories seen from above (left), the position error over time "
                "(right); never over an input");
  c->callback([ate] { run_ate(*ate); });

  auto rpe = std::make_shared<EvalArgs>();
  auto* r = eval->add_subcommand("rpe", "Relative pose error over a distance");
  r->add_option("GT", rpe->first, "Reference trajectory (TUM, KITTI or g2o/TORO)")->required();
  r->add_option("EST", rpe->second, "Estimated trajectory")->required();
  add_common(r, *rpe, 0.01);
  r->add_option("--delta", rpe->delta, "Distance between the two poses of a relative pose")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  r->add_option("--unit", rpe->unit, "Unit of --delta: frames | m | s")
      ->check(CLI::IsMember({"frames", "m", "s"}))
      ->capture_default_str();
  rpe->align = "none";
  r->add_option("--align", rpe->align,
                "sim3: scale the estimate by its Sim(3) alignment's scale (monocular); none")
      ->check(CLI::IsMember({"none", "sim3"}))
      ->capture_default_str();
  r->add_option("--offset", rpe->offset, "Seconds added to the estimate's times")->capture_default_str();
  r->callback([rpe] { run_rpe(*rpe); });

  auto rel = std::make_shared<EvalArgs>();
  auto* l = eval->add_subcommand(
      "relations", "Relation error (Kümmerle et al. 2009) on a Freiburg relations file");
  l->add_option("EST", rel->first, "Estimated trajectory (TUM, KITTI or g2o/TORO)")->required();
  l->add_option("RELATIONS", rel->second, "Relations file: t1 t2 x y z roll pitch yaw")->required();
  add_common(l, *rel, 1e-3);
  l->add_option("--log", rel->log,
                "CARMEN log the estimate was computed from: the relations' times (its FLASER "
                "lines' ipc timestamps) are taken to those lines' logger timestamps, the times "
                "rove's trajectories of CARMEN logs carry");
  l->callback([rel] { run_relations(*rel); });
}

}  // namespace rove::cli
