// `rove eval ate|rpe|relations`: trajectory evaluation. A thin layer over
// rove/slam/trajectory_eval.h; the plot is drawn by eval_plot.cpp.

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "eval_plot.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/json.h"
#include "rove/graph/graph_io.h"
#include "rove/io/carmen_log.h"
#include "rove/io/trajectory_files.h"
#include "rove/io/tum_trajectory.h"
#include "rove/slam/trajectory_eval.h"

namespace rove::cli {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;
/// Times listed in an issue before "and N more".
constexpr std::size_t kTimesListed = 5;

struct EvalArgs {
  std::string first, second;  // GT EST (ate, rpe) or EST RELATIONS
  std::string format = "auto", align = "se3", unit = "frames", plot, log;
  double max_dt = 0.01, offset = 0.0, delta = 1.0;
  bool json = false;
};

struct Trajectory {
  std::vector<StampedPose3> poses;
  std::string format;  // "tum", "kitti", "g2o/toro (2D)", ...
};

std::string extension(const std::string& path) {
  const std::string e = std::filesystem::path(path).extension().string();
  std::string lower;
  for (const char c : e) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

template <class Graph>
std::vector<StampedPose3> graph_vertices(const Graph& g) {
  std::vector<StampedPose3> out;
  for (const auto& [id, v] : g.vertices()) {
    if constexpr (std::is_same_v<typename Graph::Pose, SE2d>) {
      const Eigen::Matrix3d R(Eigen::AngleAxisd(v.pose.rotation().angle(), Eigen::Vector3d::UnitZ()));
      out.push_back({static_cast<double>(id),
                     SE3d(R, Eigen::Vector3d(v.pose.translation().x(), v.pose.translation().y(), 0))});
    } else {
      out.push_back({static_cast<double>(id), v.pose});
    }
  }
  return out;
}

/// Reads a trajectory: TUM (8 fields a row), KITTI (12), or the vertices of
/// a g2o/TORO graph (.g2o, .graph; the vertex id as time).
Trajectory load_trajectory(const std::string& path, const std::string& format) {
  check_regular_input(path, "trajectory");
  std::string f = format;
  const std::string ext = extension(path);
  if (f == "auto") {
    const std::vector<std::string> first =
        ext == ".gz" ? std::vector<std::string>{}
                     : first_row_fields(read_input_file(path, 1ull << 32, "trajectory"));
    const std::size_t n = first.size();
    if (ext == ".g2o" || ext == ".graph" || ext == ".gz" ||
        (n > 0 && std::isalpha(static_cast<unsigned char>(first[0][0])))) {
      f = "graph";
    } else {
      if (n == 8) f = "tum";
      else if (n == 12) f = "kitti";
      else
        throw ParseError({printable(path), std::nullopt, std::nullopt, "format"},
                         fmt::format("the first row has {} fields: not a TUM trajectory (8: t x y z "
                                     "qx qy qz qw) nor KITTI poses (12); use --format",
                                     n));
    }
  }
  if (f == "tum") return {read_tum_trajectory(path), "tum"};
  if (f == "kitti") return {read_kitti_trajectory(path), "kitti"};
  if (detect_graph_dimension(path) == GraphDimension::ThreeD)
    return {graph_vertices(read_graph_3d(path)), "graph (3D vertices, id as time)"};
  return {graph_vertices(read_graph_2d(path)), "graph (2D vertices, id as time)"};
}

std::string listed_times(const std::vector<double>& times) {
  std::string s;
  for (std::size_t k = 0; k < std::min(times.size(), kTimesListed); ++k)
    s += fmt::format("{}{:.6f}", k == 0 ? "" : ", ", times[k]);
  if (times.size() > kTimesListed) s += fmt::format(" and {} more", times.size() - kTimesListed);
  return s;
}

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

std::vector<Issue> association_issues(const TrajectoryAssociation& a, std::size_t estimate_size) {
  std::vector<Issue> issues;
  if (!a.unmatched_estimate_times.empty())
    issues.push_back({"unassociated",
                      fmt::format("{} of {} estimate poses have no reference pose within the "
                                  "time tolerance: t = {}",
                                  a.unmatched_estimate_times.size(), estimate_size,
                                  listed_times(a.unmatched_estimate_times))});
  return issues;
}

void begin_report(JsonWriter& j, std::string_view metric, const EvalArgs& a, const Trajectory& ref,
                  const Trajectory& est) {
  j.begin_object();
  j.key("metric").value(metric);
  j.key("reference").begin_object().key("file").value(a.first).key("format").value(ref.format);
  j.key("poses").value(static_cast<std::uint64_t>(ref.poses.size())).end_object();
  j.key("estimate").begin_object().key("file").value(a.second).key("format").value(est.format);
  j.key("poses").value(static_cast<std::uint64_t>(est.poses.size())).end_object();
}

void run_ate(const EvalArgs& a) {
  if (!a.plot.empty()) check_outputs_distinct({a.first, a.second}, {a.plot});
  const Trajectory ref = load_trajectory(a.first, a.format);
  const Trajectory est = load_trajectory(a.second, a.format);
  AteOptions o;
  o.association = {a.max_dt, a.offset};
  o.alignment = parse_trajectory_alignment(a.align);
  const AteResult r = absolute_trajectory_error(ref.poses, est.poses, o);
  std::vector<Issue> issues = association_issues(r.association, est.poses.size());
  if (r.transform.degenerate)
    issues.push_back({"degenerate-alignment",
                      "the associated positions lie on a line: the rotation about it is not "
                      "determined by the alignment"});
  if (o.alignment != TrajectoryAlignment::None && r.position_spread < 10.0 * r.translation.rmse) {
    issues.push_back({"weak-alignment-rotation",
                      fmt::format("the associated positions spread only {:.3g} m (RMS about their "
                                  "centroid), under 10 times the position RMSE ({:.3g} m): the "
                                  "alignment's rotation, taken from the positions, is weakly "
                                  "determined, and the rotation errors mostly show it (rove eval "
                                  "rpe measures rotation without an alignment)",
                                  r.position_spread, r.translation.rmse)});
  }
  if (!a.plot.empty()) {
    std::vector<Eigen::Vector3d> ref_xy, est_xy;
    for (const auto& [i, e] : r.association.pairs) ref_xy.push_back(ref.poses[i].pose.translation());
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
  const Trajectory ref = load_trajectory(a.first, a.format);
  const Trajectory est = load_trajectory(a.second, a.format);
  RpeOptions o;
  o.association = {a.max_dt, a.offset};
  o.delta = a.delta;
  o.unit = parse_rpe_unit(a.unit);
  const TrajectoryAlignment alignment = parse_trajectory_alignment(a.align);
  if (alignment == TrajectoryAlignment::Sim3) {
    AteOptions ate;
    ate.association = o.association;
    ate.alignment = alignment;
    o.scale = absolute_trajectory_error(ref.poses, est.poses, ate).transform.scale;
  }
  const RpeResult r = relative_pose_error(ref.poses, est.poses, o);
  const std::vector<Issue> issues = association_issues(r.association, est.poses.size());
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

/// The ipc and logger timestamps of a CARMEN log's front-laser lines.
std::vector<ClockPair> carmen_clock(const std::string& path) {
  check_regular_input(path, "CARMEN log");
  CarmenLogReader reader = CarmenLogReader::open(path);
  std::vector<ClockPair> clock;
  CarmenRecord record;
  while (reader.next(record))
    if (record.type == CarmenMessage::Flaser || record.type == CarmenMessage::RobotLaser1)
      clock.push_back({record.ipc_timestamp, record.logger_timestamp});
  if (clock.empty())
    throw ParseError({printable(path), std::nullopt, std::nullopt, "FLASER"},
                     "the log has no front-laser line (FLASER or ROBOTLASER1) to take times from");
  return clock;
}

void run_relations(const EvalArgs& a) {
  const Trajectory est = load_trajectory(a.first, a.format);
  RelationOptions o;
  o.max_time_difference = a.max_dt;
  std::vector<PoseRelation> relations = read_relations(a.second);
  if (!a.log.empty()) relations = map_relation_times(std::move(relations), carmen_clock(a.log), a.max_dt);
  const RelationResult r = relation_error(est.poses, relations, o);
  std::vector<Issue> issues;
  if (!r.missing_times.empty())
    issues.push_back({"missing-times",
                      fmt::format("{} of {} relations left out: the estimate has no pose within "
                                  "{} s of t = {}",
                                  r.relations - r.used, r.relations, a.max_dt,
                                  listed_times(r.missing_times))});
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
