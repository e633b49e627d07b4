#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "filter_command.h"
#include "kf_slam_picture.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/progress.h"
#include "rove/core/timer.h"
#include "rove/io/tum_trajectory.h"
#include "rove/slam/kf_slam_run.h"

namespace rove::cli {
namespace {

namespace fs = std::filesystem;

struct KfSlamCliOptions {
  std::string config;
  std::string rawlog;
  std::string out_dir = "kf-slam-out";
  bool json = false;
  bool progress = true;
  bool ignore_ids = false;
  double truth_gate = 0.5;
  std::optional<std::uint64_t> max_steps;
};


// One line per step: pose, uncertainty, pairing counts, NIS, timing.
void write_steps(const fs::path& path, const KfSlamResult& res) {
  std::string text =
      "# step time x y z qx qy qz qw position_std readings by_id associated new skipped nis "
      "nis_dof landmarks jcbb_nodes seconds\n"
      "# (m; time in seconds since the Unix epoch, -1 if unknown; position_std: sqrt of the "
      "trace of the robot position covariance)\n";
  for (const auto& s : res.steps) {
    const Eigen::Vector3d& t = s.pose.translation();
    const Eigen::Quaterniond q = s.pose.quaternion();
    fmt::format_to(std::back_inserter(text),
                   "{} {:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f} {:.6f} {} {} {} {} {} "
                   "{:.4f} {} {} {} {:.6f}\n",
                   s.index, s.time.valid() ? s.time.to_seconds() : -1.0, t.x(), t.y(), t.z(), q.x(),
                   q.y(), q.z(), q.w(), s.position_std, s.readings, s.by_id, s.associated,
                   s.created, s.skipped, s.nis, s.nis_dof, s.landmarks, s.jcbb_nodes, s.seconds);
  }
  write_text_file_atomically(path, text);
}

std::string optional_number(const std::optional<double>& v) {
  return v ? fmt::format("{:.6f}", *v) : std::string();
}

// landmarks.csv: mean, covariance (upper triangle), observations, truth.
void write_landmarks(const fs::path& path, const KfSlamResult& res) {
  std::string text =
      "index,id,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,observations,first_step,truth_id,"
      "error\n";
  for (std::size_t i = 0; i < res.landmarks.size(); ++i) {
    const KfSlamLandmark& l = res.landmarks[i];
    const Eigen::Matrix3d& C = l.covariance;
    fmt::format_to(std::back_inserter(text),
                   "{},{},{:.6f},{:.6f},{:.6f},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{},{},{},{}\n",
                   i, l.id, l.mean.x(), l.mean.y(), l.mean.z(), C(0, 0), C(0, 1), C(0, 2), C(1, 1),
                   C(1, 2), C(2, 2), l.observations, l.first_step,
                   l.truth_id ? std::to_string(*l.truth_id) : std::string(),
                   optional_number(l.error));
  }
  write_text_file_atomically(path, text);
}

void json_optional(JsonWriter& j, const char* key, const std::optional<double>& v) {
  j.key(key);
  if (v) j.value(*v); else j.null();
}

void json_landmarks(JsonWriter& j, const KfSlamResult& res) {
  j.key("landmarks").begin_array();
  for (const KfSlamLandmark& l : res.landmarks) {
    j.begin_object();
    j.key("id").value(l.id);
    j.key("mean").begin_array().value(l.mean.x()).value(l.mean.y()).value(l.mean.z()).end_array();
    j.key("covariance").begin_array();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) j.value(l.covariance(r, c));
    }
    j.end_array();
    j.key("observations").value(l.observations);
    j.key("truth_id");
    if (l.truth_id) j.value(*l.truth_id); else j.null();
    json_optional(j, "error", l.error);
    j.end_object();
  }
  j.end_array();
}

void json_association(JsonWriter& j, const KfSlamResult& res) {
  const KfSlamAssociationStats& a = res.association;
  j.key("association").begin_object();
  j.key("method").value(to_string(res.options.data_association.method));
  j.key("metric").value(to_string(res.options.data_association.metric));
  j.key("ic_metric").value(to_string(res.options.data_association.ic_metric));
  j.key("chi2_probability").value(res.options.data_association.chi2_probability);
  j.key("use_landmark_ids").value(res.options.use_landmark_ids);
  j.key("readings").value(a.readings);
  j.key("paired_by_id").value(a.by_id);
  j.key("associated").value(a.associated);
  j.key("new_landmarks").value(a.created);
  j.key("skipped").value(a.skipped);
  j.key("readings_with_truth").value(a.with_truth);
  j.key("correct").value(a.correct);
  j.key("wrong").value(a.wrong);
  j.key("duplicates").value(a.duplicates);
  j.key("node_limit_steps").value(a.node_limit_steps);
  j.end_object();
}

std::string summary_json(const std::string& config, const std::string& rawlog,
                         const KfSlamResult& res, const std::vector<Issue>& issues,
                         const std::vector<std::string>& files, double total) {
  const std::size_t n = res.steps.size();
  double max_step = 0.0;
  for (const auto& s : res.steps) max_step = std::max(max_step, s.seconds);
  JsonWriter j;
  j.begin_object();
  j.key("config").value(config);
  j.key("rawlog").value(rawlog);
  j.key("format").value(to_string(res.format));
  j.key("dimension").value(res.dim);
  j.key("update").value(to_string(res.options.update));
  j.key("steps").value(n);
  j.key("landmark_count").value(res.landmarks.size());
  if (n > 0) {
    const SE3d& p = res.steps.back().pose;
    j.key("final_position").begin_array().value(p.translation().x()).value(p.translation().y())
        .value(p.translation().z()).end_array();
    j.key("final_position_std").value(res.steps.back().position_std);
  }
  json_optional(j, "landmark_rmse", res.landmark_rmse);
  j.key("landmarks_with_truth").value(res.landmarks_with_truth);
  json_optional(j, "path_rmse", res.path_rmse);
  json_optional(j, "heading_rmse_deg",
                res.heading_rmse ? std::optional<double>(*res.heading_rmse * 180.0 / M_PI)
                                 : std::nullopt);
  j.key("nis_sum").value(res.nis_sum);
  j.key("nis_dof").value(res.nis_dof);
  json_association(j, res);
  j.key("filter_seconds").value(res.filter_seconds);
  j.key("seconds_per_step_mean").value(n ? res.filter_seconds / static_cast<double>(n) : 0.0);
  j.key("seconds_per_step_max").value(max_step);
  j.key("read_seconds").value(res.read_seconds);
  j.key("total_seconds").value(total);
  json_landmarks(j, res);
  j.key("files").value(files);
  write_issues(j, issues);
  j.end_object();
  return j.str() + "\n";
}

void print_text(const std::string& config, const std::string& rawlog, const KfSlamResult& res,
                const std::vector<Issue>& issues, const std::vector<std::string>& files,
                const std::string& out_dir, double total) {
  const std::size_t n = res.steps.size();
  const KfSlamAssociationStats& a = res.association;
  fmt::print("kf-slam: {} steps from {} ({}), {}D EKF-SLAM, {} update\n", n, printable(rawlog),
             to_string(res.format), res.dim, to_string(res.options.update));
  fmt::print("  config: {}\n", printable(config));
  fmt::print("  landmarks: {} mapped from {} readings ({} paired by ID, {} associated by {}, {} "
             "new, {} skipped)\n",
             res.landmarks.size(), a.readings, a.by_id, a.associated,
             to_string(res.options.data_association.method), a.created, a.skipped);
  if (a.with_truth > 0) {
    fmt::print("  pairings vs ground truth: {} correct, {} wrong, {} duplicate landmarks\n",
               a.correct, a.wrong, a.duplicates);
  }
  if (res.landmark_rmse) {
    fmt::print("  landmark RMSE: {:.4f} m over {} landmarks\n", *res.landmark_rmse,
               res.landmarks_with_truth);
  }
  if (res.path_rmse) {
    fmt::print("  path RMSE: {:.4f} m, heading {:.3f} deg\n", *res.path_rmse,
               *res.heading_rmse * 180.0 / M_PI);
  }
  fmt::print("  NIS: {:.1f} over {} degrees of freedom\n", res.nis_sum, res.nis_dof);
  fmt::print("  time: filter {:.3f} s ({:.3f} ms/step), reading {:.3f} s, total {:.3f} s\n",
             res.filter_seconds, n ? 1e3 * res.filter_seconds / static_cast<double>(n) : 0.0,
             res.read_seconds, total);
  fmt::print("  wrote {} files to {}/\n", files.size(), printable(out_dir));
  if (issues.empty()) {
    fmt::print("  issues: none\n");
  } else {
    fmt::print("  issues:\n");
    for (const auto& i : issues) fmt::print("    {}: {}\n", i.code, i.message);
  }
}

std::vector<std::string> write_outputs(const fs::path& dir, const KfSlamResult& res) {
  std::vector<TimedPose3> path;
  for (const auto& s : res.steps) path.push_back({s.time, s.pose});
  write_tum_trajectory((dir / "path.tum").string(), path);
  write_steps(dir / "steps.txt", res);
  write_landmarks(dir / "landmarks.csv", res);
  write_kf_slam_picture(res, res.options.quantiles, (dir / "map.png").string());
  return {(dir / "path.tum").string(), (dir / "steps.txt").string(),
          (dir / "landmarks.csv").string(), (dir / "map.png").string()};
}

void run(const KfSlamCliOptions& o) {
  Stopwatch total;
  check_regular_input(o.config, "kf-slam config file");
  const IniFile ini = IniFile::load(o.config);
  const KfSlamConfig cfg = load_kf_slam_config(ini);
  const std::string rawlog = rawlog_to_read(o.rawlog, o.config, cfg, "MappingApplication");
  check_regular_input(rawlog, "rawlog");
  const fs::path dir(o.out_dir);
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw IoError(o.out_dir, "the output folder (-o) exists and is not a folder");
  }
  std::vector<fs::path> inputs{fs::path(o.config), fs::path(rawlog)};
  if (!cfg.ground_truth_file.empty()) {
    inputs.emplace_back(cfg.resolve(cfg.ground_truth_file, "ground_truth_file"));
  }
  if (!cfg.ground_truth_file_robot.empty()) {
    inputs.emplace_back(cfg.resolve(cfg.ground_truth_file_robot, "ground_truth_file_robot"));
  }
  check_outputs_distinct(inputs, {dir / "path.tum", dir / "steps.txt", dir / "landmarks.csv",
                                  dir / "map.png", dir / "summary.json"});
  KfSlamRunOptions ro;
  if (o.ignore_ids) ro.use_landmark_ids = false;
  ro.max_steps = o.max_steps;
  ro.truth_gate = o.truth_gate;
  std::optional<Progress> progress;
  if (o.progress) progress.emplace(std::nullopt, "kf-slam " + printable(rawlog), std::cerr);
  ro.on_step = [&](const KfSlamStep&) {
    throw_if_interrupted();
    if (progress) progress->advance();
  };
  KfSlamResult res;
  try {
    res = run_kf_slam(cfg, rawlog, ro);
  } catch (const Interrupted&) {
    if (progress) progress->finish();
    fmt::print(stderr, "rove: interrupted; nothing written to {}\n", printable(o.out_dir));
    throw;
  }
  if (progress) progress->finish();
  std::vector<Issue> issues;
  for (const auto& i : res.issues) issues.push_back({i.code, i.message});
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(o.out_dir, "cannot create the output folder: " + ec.message());
  std::vector<std::string> files = write_outputs(dir, res);
  const fs::path summary_path = dir / "summary.json";
  files.push_back(summary_path.string());
  const std::string summary = summary_json(o.config, rawlog, res, issues, files, total.elapsed());
  write_text_file_atomically(summary_path, summary);
  if (o.json) {
    fmt::print("{}", summary);
  } else {
    print_text(o.config, rawlog, res, issues, files, o.out_dir, total.elapsed());
  }
  finish(issues);
}

}  // namespace

void add_kf_slam_command(CLI::App& app) {
  auto o = std::make_shared<KfSlamCliOptions>();
  auto* cmd = app.add_subcommand(
      "kf-slam",
      "EKF landmark SLAM with range-bearing readings (MRPT's kf-slam, 2D or 6-DoF) from an MRPT "
      "kf-slam config and a rawlog; errors against the config's ground truth");
  cmd->add_option("config", o->config, "MRPT kf-slam configuration file (.ini), e.g. "
                                       "EKF-SLAM_6D_test_datassoc.ini")
      ->required();
  cmd->add_option("rawlog", o->rawlog, "rawlog (default: the config's rawlog_file)");
  cmd->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  cmd->add_flag("--ignore-ids", o->ignore_ids,
                "pair readings by data association even when they carry landmark IDs (the IDs "
                "then check the pairings)");
  cmd->add_option("--truth-gate", o->truth_gate,
                  "logs without IDs: largest distance (m) between a reading placed from the "
                  "ground-truth pose and the true landmark it is taken for")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--max-steps", o->max_steps, "process at most this many steps (default: all)");
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("!--no-progress", o->progress, "do not report progress on stderr");
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
