// `rove align SOURCE TARGET`: register two point clouds (PCD or PLY) and
// print T_target_source.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cli_values.h"
#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/json.h"
#include "rove/core/parallel.h"
#include "rove/core/timer.h"
#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/poses/lie_conversion.h"
#include "rove/registration/align.h"

namespace rove::cli {

namespace {

struct AlignCliOptions {
  std::string source, target, method = "gicp", init, init_file, output;
  std::string voxel = "auto";
  double max_distance = 1.0;
  double distance_factor = 3.0;
  std::size_t neighbors = 10;
  double resolution = 1.0;
  int max_iterations = 0;
  int threads = 1;
  bool json = false;
};

std::string extension(const std::string& path) {
  const auto dot = path.rfind('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

PointCloud read_cloud(const std::string& path, const char* what) {
  check_regular_input(path, what);
  const std::string e = extension(path);
  if (e == "pcd") return read_pcd(path);
  if (e == "ply") return read_ply(path);
  throw IoError(path, fmt::format("{}: unknown point cloud format (expected .pcd or .ply)", what));
}

/// "auto", or "0.25,0.1" (meters, coarse to fine) as voxel sizes, each finite
/// and ≥ 0. Auto: nullopt.
std::optional<std::vector<double>> parse_voxels(const std::string& text) {
  if (text == "auto") return std::nullopt;
  std::vector<double> v = parse_number_list(text, "--voxel");
  for (const double x : v)
    if (x < 0)
      throw ParseError({"--voxel", std::nullopt, std::nullopt, "voxel"},
                       fmt::format("{} is not 'auto' or a size >= 0", x));
  return v;
}

/// --init as a transform (the command line's pose convention, cli_values.h).
SE3d parse_init(const std::string& text) { return to_se3(parse_cli_pose3(text, "--init")); }

/// A 4×4 matrix of 16 numbers (rows), e.g. small_gicp's T_target_source.txt.
SE3d read_init_file(const std::string& path) {
  std::istringstream in(read_input_file(path, 1 << 20, "--init-file"));
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) {
    if (!(in >> M(i / 4, i % 4)) || !std::isfinite(M(i / 4, i % 4)))
      throw ParseError({path, std::nullopt, std::nullopt, "T"},
                       fmt::format("expected 16 finite numbers, read {}", i));
  }
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
      R.determinant() < 0 || M.row(3).cwiseAbs().sum() != 1.0 || M(3, 3) != 1.0)
    throw ParseError({path, std::nullopt, std::nullopt, "T"}, "not a rigid 4x4 transform");
  return SE3d(Eigen::Quaterniond(R).normalized(), Eigen::Vector3d(M.topRightCorner<3, 1>()));
}

/// The issue code of a termination that is not Converged.
std::string issue_code(RegistrationTermination t) {
  switch (t) {
    case RegistrationTermination::Converged: return "converged";
    case RegistrationTermination::MaxIterations: return "max-iterations";
    case RegistrationTermination::Degenerate: return "degenerate";
    case RegistrationTermination::TooFewCorrespondences: return "too-few-correspondences";
    case RegistrationTermination::InvalidInput: return "invalid-input";
    case RegistrationTermination::Diverged: return "diverged";
    case RegistrationTermination::Stalled: return "stalled";
  }
  return "not-converged";
}

std::string join(const std::vector<double>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += fmt::format("{}{:g}", i ? "," : "", v[i]);
  return s;
}

/// Writes the source cloud moved by T (points and normals) to `path`.
void write_aligned(const std::string& path, PointCloud aligned, const Eigen::Matrix4d& T) {
  const Eigen::Matrix3f R = T.topLeftCorner<3, 3>().cast<float>();
  const Eigen::Vector3f t = T.topRightCorner<3, 1>().cast<float>();
  for (auto& p : aligned.points_mut()) p = R * p + t;
  if (aligned.has_normals())
    for (auto& n : aligned.normals_mut()) n = R * n;
  const bool pcd = extension(path) == "pcd";
  write_file_atomically(path, [&](const std::filesystem::path& tmp) {
    if (pcd) {
      write_pcd(tmp.string(), aligned);
    } else {
      write_ply(tmp.string(), aligned);
    }
  });
}

void print_json(const AlignCliOptions& o, const AlignResult& a, int threads, double seconds,
                const std::vector<Issue>& issues) {
  const Eigen::Matrix4d T = a.T_target_source.matrix();
  JsonWriter j;
  j.begin_object();
  j.key("command").value("align");
  j.key("source").value(o.source).key("target").value(o.target);
  j.key("method").value(o.method);
  j.key("voxel").begin_array();
  for (double v : a.voxel_sizes) j.value(v);
  j.end_array();
  j.key("voxel_auto").value(a.voxel_auto);
  if (o.method == "ndt") {
    j.key("resolution").value(o.resolution);
  } else if (a.max_distance > 0) {
    j.key("max_distance").value(a.max_distance);
  } else {
    j.key("distance_factor").value(o.distance_factor);
  }
  j.key("threads").value(threads);
  j.key("source_points").value(static_cast<std::uint64_t>(a.source_points));
  j.key("target_points").value(static_cast<std::uint64_t>(a.target_points));
  j.key("T_target_source").begin_array();
  for (int r = 0; r < 4; ++r) {
    j.begin_array();
    for (int c = 0; c < 4; ++c) j.value(T(r, c));
    j.end_array();
  }
  j.end_array();
  j.key("fitness_m2").value(a.fitness).key("goodness").value(a.goodness);
  j.key("iterations").value(a.iterations).key("max_iterations").value(a.iteration_cap);
  j.key("termination").value(to_string(a.termination));
  j.key("converged").value(succeeded(a.termination));
  j.key("message").value(a.message);
  j.key("levels").value(a.level_messages);
  j.key("seconds").value(seconds);
  if (o.output.empty()) {
    j.key("output").null();
  } else {
    j.key("output").value(o.output);
  }
  write_issues(j, issues);
  j.end_object();
  fmt::print("{}\n", j.str());
}

void print_text(const AlignCliOptions& o, const AlignResult& a, double seconds,
                const std::vector<Issue>& issues) {
  const Eigen::Matrix4d T = a.T_target_source.matrix();
  const std::vector<double>& voxels = a.voxel_sizes;
  const std::string voxel_text =
      voxels.size() == 1 && voxels.front() == 0 ? "none" : join(voxels) + " m";
  for (const auto& m : a.level_messages) fmt::print("{}\n", m);
  fmt::print("T_target_source:\n");
  for (int i = 0; i < 4; ++i)
    fmt::print("{:12.6f} {:12.6f} {:12.6f} {:12.6f}\n", T(i, 0), T(i, 1), T(i, 2), T(i, 3));
  fmt::print("method: {}\nvoxel: {}{}\npoints: source {} target {}\nfitness: {:.6g} m^2\n"
             "goodness: {:.4f}\niterations: {} (cap {}{})\ntime: {:.3f} s\n"
             "termination: {} ({})\n",
             o.method, voxel_text,
             a.voxel_auto ? " (auto, from the target's density; --voxel 0 disables it)" : "",
             a.source_points, a.target_points, a.fitness, a.goodness, a.iterations,
             a.iteration_cap, o.method == "ndt" ? "" : " per level", seconds,
             to_string(a.termination), a.message);
  if (!o.output.empty()) fmt::print("aligned source written to {}\n", printable(o.output));
  fmt::print("issues: {}\n", issues.empty() ? "none" : std::to_string(issues.size()));
}

void run(const AlignCliOptions& o) {
  // Everything the command line names is checked before any work.
  const int threads = resolve_thread_count(o.threads, "--threads");
  std::optional<std::vector<double>> voxels = parse_voxels(o.voxel);
  SE3d init;
  if (!o.init.empty()) init = parse_init(o.init);
  std::vector<std::filesystem::path> inputs{o.source, o.target};
  if (!o.init_file.empty()) inputs.emplace_back(o.init_file);
  if (!o.output.empty()) {
    const std::string e = extension(o.output);
    if (e != "pcd" && e != "ply")
      throw IoError(o.output, "-o: unknown point cloud format (expected .pcd or .ply)");
    check_outputs_distinct(inputs, {o.output});
  }
  if (o.method == "ndt" && voxels && voxels->size() != 1)
    throw ParseError({"--voxel", std::nullopt, std::nullopt, "voxel"},
                     "ndt takes one voxel size, not a coarse-to-fine list");
  if (!o.init_file.empty()) init = read_init_file(o.init_file);
  const PointCloud source_full = read_cloud(o.source, "source cloud");
  const PointCloud target_full = read_cloud(o.target, "target cloud");

  AlignOptions ao;
  ao.method = parse_align_method(o.method);
  ao.voxel_sizes = voxels;
  ao.max_distance = o.max_distance;
  ao.distance_factor = o.distance_factor;
  ao.neighbors = o.neighbors;
  ao.ndt_resolution = o.resolution;
  ao.max_iterations = o.max_iterations;
  ao.num_threads = threads;
  const Stopwatch clock;
  const AlignResult a = align_clouds(target_full.points(), source_full.points(), init, ao);
  const double seconds = clock.elapsed();

  std::vector<Issue> issues;
  if (!succeeded(a.termination)) issues.push_back({issue_code(a.termination), a.message});
  if (!o.output.empty()) write_aligned(o.output, source_full, a.T_target_source.matrix());
  if (o.json) {
    print_json(o, a, threads, seconds, issues);
  } else {
    print_text(o, a, seconds, issues);
  }
  finish(issues);
}

}  // namespace

void add_align_command(CLI::App& app) {
  auto o = std::make_shared<AlignCliOptions>();
  auto* cmd = app.add_subcommand(
      "align", "Register SOURCE onto TARGET (PCD or PLY) and print T_target_source; exit "
               "status 3 when the result is not Converged (the issue is listed)");
  cmd->add_option("source", o->source, "Cloud to move (.pcd or .ply)")->required();
  cmd->add_option("target", o->target, "Reference cloud (.pcd or .ply)")->required();
  cmd->add_option("--method", o->method, "icp | point-to-plane | gicp | ndt")
      ->check(CLI::IsMember({"icp", "point-to-plane", "gicp", "ndt"}))
      ->capture_default_str();
  auto* init = cmd->add_option("--init", o->init,
                               "Initial guess x,y,z,yaw,pitch,roll or x,y,yaw (m, deg; an angle "
                               "may end in 'rad'; R = Rz·Ry·Rx); default identity");
  cmd->add_option("--init-file", o->init_file, "Initial guess as a 4x4 matrix file")
      ->excludes(init);
  cmd->add_option("--voxel", o->voxel,
                  fmt::format("Voxel-grid leaf for both clouds, m: 'auto' picks the finest round "
                              "leaf at which the target fills at most {} voxels (none for a "
                              "smaller cloud) and, for the ICP family, adds a level at {} x it; "
                              "0: no down-sampling; a list coarse to fine, e.g. 0.25,0.1, "
                              "registers level by level (ICP family)",
                              AlignOptions::kAutoVoxels, AlignOptions::kFineRatio))
      ->capture_default_str();
  cmd->add_option("--distance-factor", o->distance_factor,
                  "Coarse to fine: pairing gate = factor x the level's voxel")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--neighbors", o->neighbors,
                  "Neighbours (point included) for normals and GICP covariances")
      ->check(CLI::Range(3, 1000))
      ->capture_default_str();
  cmd->add_option("--max-distance", o->max_distance,
                  "ICP/GICP pairing gate with one voxel size, m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--resolution", o->resolution, "NDT cell size, m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-iterations", o->max_iterations,
                  "Iteration cap (0: the method's, 64 per level for the ICP family, 35 for ndt)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_option("--threads", o->threads,
                  fmt::format("Threads, 1 to {}, 0 for all hardware threads (results do not "
                              "depend on it)",
                              kMaxThreads))
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output,
                  "Write the aligned source cloud (.pcd or .ply; written atomically, never over "
                  "an input); default none");
  cmd->add_flag("--json", o->json, "Print the summary as one JSON object (with an issues array)");
  cmd->callback([o] { run(*o); });
}

}  // namespace rove::cli
