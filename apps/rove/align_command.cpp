// `rove align SOURCE TARGET`: register two point clouds (PCD or PLY) and
// print T_target_source.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "commands.h"
#include "rove/core/error.h"
#include "rove/maps/pcd.h"
#include "rove/maps/ply.h"
#include "rove/maps/voxel_grid.h"
#include "rove/registration/icp_3d.h"
#include "rove/registration/icp_3d_multi_resolution.h"
#include "rove/registration/ndt.h"

namespace rove::cli {

namespace {

struct AlignOptions {
  std::string source, target, method = "gicp", init, init_file, output;
  std::string voxel = "0";
  double max_distance = 1.0;
  double distance_factor = 3.0;
  std::size_t neighbors = 10;
  double resolution = 1.0;
  int max_iterations = 0;
  int threads = 1;
};

std::string extension(const std::string& path) {
  const auto dot = path.rfind('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

PointCloud read_cloud(const std::string& path) {
  const std::string e = extension(path);
  if (e == "pcd") return read_pcd(path);
  if (e == "ply") return read_ply(path);
  throw IoError(path, "unknown point cloud format (expected .pcd or .ply)");
}

void write_cloud(const std::string& path, const PointCloud& cloud) {
  const std::string e = extension(path);
  if (e == "pcd") return write_pcd(path, cloud);
  if (e == "ply") return write_ply(path, cloud);
  throw IoError(path, "unknown point cloud format (expected .pcd or .ply)");
}

/// "0.25,0.1" (meters, coarse to fine) as voxel sizes, each finite and ≥ 0.
std::vector<double> parse_voxels(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (used == 0 || used != item.size() || !std::isfinite(x) || x < 0)
      throw ParseError({"--voxel", std::nullopt, std::nullopt, "voxel"},
                       fmt::format("'{}' is not a finite number >= 0", item));
    v.push_back(x);
  }
  if (v.empty())
    throw ParseError({"--voxel", std::nullopt, std::nullopt, "voxel"}, "no voxel size given");
  return v;
}

/// "x,y,z,roll,pitch,yaw" (meters, radians) as a transform, R = Rz·Ry·Rx.
Eigen::Isometry3d parse_init(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (used == 0 || used != item.size() || !std::isfinite(x))
      throw ParseError({"--init", std::nullopt, std::nullopt, "init"},
                       fmt::format("'{}' is not a finite number", item));
    v.push_back(x);
  }
  if (v.size() != 6)
    throw ParseError({"--init", std::nullopt, std::nullopt, "init"},
                     fmt::format("expected 6 values x,y,z,roll,pitch,yaw, got {}", v.size()));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return T;
}

/// A 4×4 matrix of 16 numbers (rows), e.g. small_gicp's T_target_source.txt.
Eigen::Isometry3d read_init_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open");
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
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = M.topRightCorner<3, 1>();
  return T;
}

void run(const AlignOptions& o) {
  const PointCloud source_full = read_cloud(o.source);
  const PointCloud target_full = read_cloud(o.target);
  const std::vector<double> voxels = parse_voxels(o.voxel);
  Eigen::Isometry3d init = Eigen::Isometry3d::Identity();
  if (!o.init.empty()) init = parse_init(o.init);
  if (!o.init_file.empty()) init = read_init_file(o.init_file);

  Eigen::Matrix4d T;
  double fitness = 0, goodness = 0;
  int iterations = 0;
  std::size_t source_points = 0, target_points = 0;
  RegistrationTermination termination;
  std::string message;
  if (o.method == "ndt") {
    if (voxels.size() != 1)
      throw ParseError({"--voxel", std::nullopt, std::nullopt, "voxel"},
                       "ndt takes one voxel size, not a coarse-to-fine list");
    const auto down = [&](const PointCloud& c) {
      return voxels[0] > 0 ? voxel_downsample(c, static_cast<float>(voxels[0])) : c;
    };
    const PointCloud source = down(source_full);
    const PointCloud target = down(target_full);
    source_points = source.size();
    target_points = target.size();
    NdtGridOptions go;
    go.resolution = o.resolution;
    const NdtGrid3D grid(std::span<const Eigen::Vector3f>(target.points()), go);
    NdtOptions no;
    no.num_threads = o.threads;
    if (o.max_iterations > 0) no.max_iterations = o.max_iterations;
    const auto r = ndt_3d(grid, source.points(), init, no);
    T = r.matrix;
    fitness = r.fitness;
    goodness = r.goodness;
    iterations = r.iterations;
    termination = r.termination;
    message = r.message;
  } else {
    // One voxel size: one level, gate --max-distance. Several: coarse to
    // fine, gate --distance-factor × voxel at each level.
    Icp3dMultiResolutionOptions mo;
    mo.voxel_sizes = voxels;
    mo.neighbors = o.neighbors;
    if (voxels.size() == 1) {
      if (voxels[0] > 0) {
        mo.distance_factor = o.max_distance / voxels[0];
      } else {
        mo.full_resolution_distance = o.max_distance;
      }
    } else {
      mo.distance_factor = o.distance_factor;
    }
    if (o.method == "icp") {
      mo.icp.method = Icp3dMethod::PointToPoint;
    } else if (o.method == "point-to-plane") {
      mo.icp.method = Icp3dMethod::PointToPlane;
    } else {
      mo.icp.method = Icp3dMethod::Gicp;
    }
    mo.icp.num_threads = o.threads;
    if (o.max_iterations > 0) mo.icp.max_iterations = o.max_iterations;
    const auto rr = icp_3d_multi_resolution(target_full.points(), source_full.points(), init, mo);
    for (const auto& level : rr.levels) fmt::print("{}\n", level.message);
    const auto& r = rr.result;
    T = r.matrix;
    fitness = r.fitness;
    goodness = r.goodness;
    iterations = rr.total_iterations;
    termination = r.termination;
    message = r.message;
    source_points = rr.source_points.back();
    target_points = rr.target_points.back();
  }
  fmt::print("T_target_source:\n");
  for (int i = 0; i < 4; ++i)
    fmt::print("{:12.6f} {:12.6f} {:12.6f} {:12.6f}\n", T(i, 0), T(i, 1), T(i, 2), T(i, 3));
  fmt::print("method: {}\npoints: source {} target {}\nfitness: {:.6g} m^2\ngoodness: {:.4f}\n"
             "iterations: {}\ntermination: {} ({})\n",
             o.method, source_points, target_points, fitness, goodness, iterations,
             to_string(termination), message);
  if (!o.output.empty()) {
    PointCloud aligned = source_full;
    const Eigen::Matrix3f R = T.topLeftCorner<3, 3>().cast<float>();
    const Eigen::Vector3f t = T.topRightCorner<3, 1>().cast<float>();
    for (auto& p : aligned.points_mut()) p = R * p + t;
    if (aligned.has_normals())
      for (auto& n : aligned.normals_mut()) n = R * n;
    write_cloud(o.output, aligned);
    fmt::print("aligned source written to {}\n", o.output);
  }
  if (!succeeded(termination)) throw CLI::RuntimeError(3);
}

}  // namespace

void add_align_command(CLI::App& app) {
  auto o = std::make_shared<AlignOptions>();
  auto* cmd = app.add_subcommand(
      "align", "Register SOURCE onto TARGET (PCD or PLY) and print T_target_source; exit "
               "status 3 when the result is not Converged");
  cmd->add_option("source", o->source, "Cloud to move (.pcd or .ply)")->required()->check(CLI::ExistingFile);
  cmd->add_option("target", o->target, "Reference cloud (.pcd or .ply)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--method", o->method, "icp | point-to-plane | gicp | ndt")
      ->check(CLI::IsMember({"icp", "point-to-plane", "gicp", "ndt"}))
      ->capture_default_str();
  auto* init = cmd->add_option("--init", o->init,
                               "Initial guess x,y,z,roll,pitch,yaw (m, rad; R = Rz·Ry·Rx)");
  cmd->add_option("--init-file", o->init_file, "Initial guess as a 4x4 matrix file")
      ->check(CLI::ExistingFile)
      ->excludes(init);
  cmd->add_option("--voxel", o->voxel,
                  "Voxel-grid leaf for both clouds, m (0: none); a list coarse to fine, e.g. "
                  "0.25,0.1, registers level by level (ICP family)")
      ->capture_default_str();
  cmd->add_option("--distance-factor", o->distance_factor,
                  "Coarse to fine: pairing gate = factor x the level's voxel")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--neighbors", o->neighbors,
                  "Neighbours (point included) for normals and GICP covariances")
      ->check(CLI::Range(3, 1000))
      ->capture_default_str();
  cmd->add_option("--max-distance", o->max_distance, "ICP/GICP pairing gate with one voxel size, m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--resolution", o->resolution, "NDT cell size, m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-iterations", o->max_iterations, "Iteration cap (0: method default)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", o->threads, "Threads (results do not depend on it)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output, "Write the aligned source cloud (.pcd or .ply)");
  cmd->callback([o] {
    try {
      run(*o);
    } catch (const Error& e) {
      fmt::print(stderr, "rove align: {}\n", e.message());
      throw CLI::RuntimeError(1);
    }
  });
}

}  // namespace rove::cli
