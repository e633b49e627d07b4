// `rove rbpf-slam` with a beacon map: range-only SLAM (rove/slam/ro_slam_run.h).
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "filter_command.h"
#include "kf_slam_picture.h"
#include "rbpf_slam_cli.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/json.h"
#include "rove/slam/ro_slam_run.h"

namespace rove::cli {
namespace {

namespace fs = std::filesystem;

// Ellipses of the picture at 3 standard deviations (99.7 % per axis).
constexpr double kQuantiles = 3.0;

struct Outcome {
  RoSlamResult res;
  std::optional<BeaconErrors> errors;
  std::vector<std::string> files;
};

// One line per beacon of the most likely map: its density's kind, mean and
// covariance (m, m²), and how many samples or modes hold it.
void write_beacons_csv(const fs::path& path, const BeaconMap& map) {
  std::string text = "id,kind,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,components\n";
  for (const Beacon& b : map.beacons()) {
    const PointGaussian3 g = b.moments();
    const Eigen::Matrix3d& c = g.covariance;
    const std::size_t parts = b.kind == BeaconPdfKind::MonteCarlo       ? b.samples.size()
                              : b.kind == BeaconPdfKind::SumOfGaussians ? b.modes.size()
                                                                         : 1;
    fmt::format_to(std::back_inserter(text), "{},{},{:.6f},{:.6f},{:.6f},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{}\n",
                   b.id, to_string(b.kind), g.mean.x(), g.mean.y(), g.mean.z(), c(0, 0), c(0, 1),
                   c(0, 2), c(1, 1), c(1, 2), c(2, 2), parts);
  }
  write_text_file_atomically(path, text);
}

// One line per filter update.
void write_ess(const fs::path& path, const RoSlamResult& res) {
  std::string text = "step,time,ess,effective_particles,resampled,inserted,readings,beacons,unresolved,seconds\n";
  const double n = static_cast<double>(res.options.particles);
  for (const auto& s : res.steps) {
    if (!s.updated) continue;
    fmt::format_to(std::back_inserter(text), "{},{:.6f},{:.6f},{:.3f},{},{},{},{},{},{:.6f}\n", s.index,
                   s.time.valid() ? s.time.to_seconds() : -1.0, s.update.ess, s.update.ess * n,
                   s.update.resampled ? 1 : 0, s.inserted ? 1 : 0, s.update.readings,
                   s.update.beacons, s.update.unresolved, s.seconds);
  }
  write_text_file_atomically(path, text);
}

void write_picture(const fs::path& path, const Outcome& out,
                   const std::vector<std::pair<std::int32_t, Eigen::Vector3d>>& truth) {
  LandmarkPicture pic;
  for (const Pose2& p : out.res.path) pic.path.emplace_back(p.x(), p.y());
  for (const auto& [id, t] : truth) pic.true_landmarks.push_back(t.head<2>());
  for (const Beacon& b : out.res.map.beacons()) {
    const PointGaussian3 g = b.moments();
    if (b.kind == BeaconPdfKind::Gaussian) {
      pic.landmarks.push_back({g.mean.head<2>(), g.covariance.topLeftCorner<2, 2>()});
    }
    for (const auto& s : b.samples) pic.samples.push_back(s.position.head<2>());
    for (const auto& m : b.modes) pic.samples.push_back(m.gaussian.mean.head<2>());
  }
  for (const SE2d& p : out.res.particles) pic.samples.push_back(p.translation());
  write_landmark_picture(pic, kQuantiles, path.string());
}

void write_beacons_json(JsonWriter& j, const Outcome& out) {
  j.key("beacons").begin_array();
  for (const Beacon& b : out.res.map.beacons()) {
    const PointGaussian3 g = b.moments();
    j.begin_object().key("id").value(b.id).key("kind").value(std::string(to_string(b.kind)));
    j.key("mean").begin_array();
    for (int i = 0; i < 3; ++i) j.value(g.mean[i]);
    j.end_array().key("covariance").begin_array();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) j.value(g.covariance(r, c));
    }
    j.end_array().end_object();
  }
  j.end_array();
  j.key("ground_truth");
  if (!out.errors) {
    j.null();
    return;
  }
  j.begin_object().key("beacon_rmse").value(out.errors->rmse);
  j.key("matched").value(out.errors->matched.size());
  for (const auto& [key, ids] : {std::pair{"missing", &out.errors->missing}, std::pair{"unknown", &out.errors->unknown}}) {
    j.key(key).begin_array();
    for (const std::int32_t id : *ids) j.value(id);
    j.end_array();
  }
  j.key("errors").begin_array();
  for (const auto& e : out.errors->matched) {
    j.begin_object().key("id").value(e.id).key("error").value(e.error).end_object();
  }
  j.end_array().end_object();
}

std::string summary_json(const RbpfSlamCliOptions& o, const std::string& rawlog,
                         const RbpfSlamConfig& cfg, const Outcome& out,
                         const std::vector<Issue>& issues, double total) {
  const RoSlamResult& res = out.res;
  const Pose2& last = res.path.back();
  JsonWriter j;
  j.begin_object();
  j.key("config").value(o.config);
  j.key("rawlog").value(rawlog);
  j.key("format").value(to_string(res.format));
  j.key("map").value("beacons");
  j.key("seed").value(o.seed);
  j.key("threads").value(res.options.num_threads);
  j.key("proposal").value("pfStandardProposal");
  j.key("particles").value(res.options.particles);
  j.key("beacon_init").value(res.options.insertion.insert_as_monte_carlo ? "montecarlo" : "sog");
  j.key("observations").value(res.observations);
  write_rbpf_counts(j, res);
  j.key("final_pose").begin_object();
  j.key("x").value(last.x()).key("y").value(last.y()).key("phi").value(last.phi()).end_object();
  write_beacons_json(j, out);
  j.key("mapping_seconds").value(res.mapping_seconds);
  j.key("read_seconds").value(res.read_seconds);
  j.key("total_seconds").value(total);
  write_ignored_keys(j, cfg);
  j.key("files").value(out.files);
  write_issues(j, issues);
  j.end_object();
  return j.str() + "\n";
}

void print_text(const RbpfSlamCliOptions& o, const std::string& rawlog, const RbpfSlamConfig& cfg,
                const Outcome& out, const std::vector<Issue>& issues, double total) {
  const RoSlamResult& res = out.res;
  fmt::print("rbpf-slam: {} steps ({} with beacon ranges) from {} ({})\n", res.steps.size(),
             res.observations, printable(rawlog), to_string(res.format));
  fmt::print("  config: {}\n", printable(o.config));
  fmt::print("  filter: {} particles, pfStandardProposal, beacons as {}, {} updates, {} insertions\n",
             res.options.particles, res.options.insertion.insert_as_monte_carlo ? "Monte-Carlo samples" : "sums of Gaussians",
             res.updates, res.insertions);
  fmt::print("  result: {}\n", res.message);
  fmt::print("  final pose: {}\n", res.path.back().as_string());
  if (out.errors) {
    fmt::print("  ground truth {}: beacon RMSE {:.4f} m over {} beacons ({} missing, {} unknown)\n",
               printable(o.truth), out.errors->rmse, out.errors->matched.size(),
               out.errors->missing.size(), out.errors->unknown.size());
  }
  fmt::print("  time: mapping {:.3f} s, reading {:.3f} s, total {:.3f} s\n", res.mapping_seconds,
             res.read_seconds, total);
  if (!cfg.ignored_keys.empty()) fmt::print("  config keys without effect: {}\n", cfg.ignored_keys.size());
  fmt::print("  wrote {} files to {}/\n", out.files.size(), printable(o.out_dir));
  if (issues.empty()) {
    fmt::print("  issues: none\n");
  } else {
    fmt::print("  issues:\n");
    for (const auto& i : issues) fmt::print("    {}: {}\n", i.code, i.message);
  }
}

}  // namespace

void run_ro_slam_command(const RbpfSlamCliOptions& o, const RbpfSlamConfig& cfg,
                         const std::string& rawlog, RbpfSlamRunOptions ro, const Stopwatch& total) {
  const fs::path dir = output_folder(o.out_dir);
  std::vector<fs::path> inputs{fs::path(o.config), fs::path(rawlog)};
  std::vector<std::pair<std::int32_t, Eigen::Vector3d>> truth;
  if (!o.truth.empty()) {
    check_regular_input(o.truth, "beacon ground truth");
    inputs.emplace_back(o.truth);
    truth = load_beacon_truth(o.truth);
  }
  const std::vector<fs::path> outputs{dir / "path.tum", dir / "odometry.tum", dir / "ess.csv",
                                      dir / "beacons.csv", dir / "picture.png", dir / "summary.json"};
  check_outputs_distinct(inputs, outputs);
  Outcome out;
  out.res = run_with_progress(o.progress, "rbpf-slam " + printable(rawlog), o.out_dir,
                              [&](const std::function<void()>& step) {
                                ro.on_step = [&](std::uint64_t) { step(); };
                                return run_ro_slam(cfg, rawlog, ro);
                              });
  if (!o.truth.empty()) out.errors = beacon_errors(out.res.map, truth);
  const std::vector<Issue> issues = to_issues(out.res.issues);
  create_output_folder(dir);
  write_rbpf_paths(dir, out.res.steps, out.res.path, out.files);
  write_ess(dir / "ess.csv", out.res);
  write_beacons_csv(dir / "beacons.csv", out.res.map);
  write_picture(dir / "picture.png", out, truth);
  for (const char* f : {"ess.csv", "beacons.csv", "picture.png"}) out.files.push_back((dir / f).string());
  publish_summary(
      dir, out.files, o.json, [&] { return summary_json(o, rawlog, cfg, out, issues, total.elapsed()); },
      [&] { print_text(o, rawlog, cfg, out, issues, total.elapsed()); }, issues);
}

}  // namespace rove::cli
