#include "rove/registration/align.h"

#include <cmath>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/parallel.h"
#include "rove/maps/point_cloud.h"
#include "rove/maps/voxel_grid.h"
#include "rove/registration/icp_3d_multi_resolution.h"
#include "rove/registration/ndt.h"
#include "rove/registration/voxel_size.h"

namespace rove {

std::string_view to_string(AlignMethod method) noexcept {
  switch (method) {
    case AlignMethod::PointToPoint:
      return "icp";
    case AlignMethod::PointToPlane:
      return "point-to-plane";
    case AlignMethod::Gicp:
      return "gicp";
    case AlignMethod::Ndt:
      return "ndt";
  }
  return "unknown";
}

AlignMethod parse_align_method(std::string_view text) {
  for (const AlignMethod m :
       {AlignMethod::PointToPoint, AlignMethod::PointToPlane, AlignMethod::Gicp, AlignMethod::Ndt})
    if (text == to_string(m)) return m;
  ROVE_CHECK_MSG(false, "method '{}' is not one of icp, point-to-plane, gicp, ndt", text);
  return AlignMethod::Gicp;
}

void AlignOptions::check() const {
  if (voxel_sizes) {
    ROVE_CHECK_MSG(!voxel_sizes->empty(),
                   "voxel_sizes must list at least one size (or be unset: auto)");
    for (const double v : *voxel_sizes)
      ROVE_CHECK_MSG(std::isfinite(v) && v >= 0, "voxel sizes must be finite and >= 0, got {}", v);
    ROVE_CHECK_MSG(method != AlignMethod::Ndt || voxel_sizes->size() == 1,
                   "ndt takes one voxel size, not a coarse-to-fine list of {}",
                   voxel_sizes->size());
  }
  ROVE_CHECK_MSG(std::isfinite(max_distance) && max_distance > 0,
                 "max_distance must be finite and > 0, got {}", max_distance);
  ROVE_CHECK_MSG(std::isfinite(distance_factor) && distance_factor > 0,
                 "distance_factor must be finite and > 0, got {}", distance_factor);
  ROVE_CHECK_MSG(neighbors >= 3 && neighbors <= 1000, "neighbors must be in [3, 1000], got {}",
                 neighbors);
  ROVE_CHECK_MSG(std::isfinite(ndt_resolution) && ndt_resolution > 0,
                 "ndt_resolution must be finite and > 0, got {}", ndt_resolution);
  ROVE_CHECK_MSG(max_iterations >= 0, "max_iterations must be >= 0, got {}", max_iterations);
}

namespace {

AlignResult run_ndt(std::span<const Eigen::Vector3f> target_full,
                    std::span<const Eigen::Vector3f> source_full, const SE3d& init,
                    const AlignOptions& o, double leaf, int threads) {
  // Down-sampling copies (voxel_downsample works on PointCloud); without it
  // the caller's points are used as they are.
  PointCloud target_down, source_down;
  std::span<const Eigen::Vector3f> target = target_full, source = source_full;
  if (leaf > 0) {
    const auto down = [leaf](std::span<const Eigen::Vector3f> pts) {
      return voxel_downsample(PointCloud(std::vector<Eigen::Vector3f>(pts.begin(), pts.end())),
                              static_cast<float>(leaf));
    };
    target_down = down(target_full);
    source_down = down(source_full);
    target = target_down.points();
    source = source_down.points();
  }
  AlignResult out;
  out.source_points = source.size();
  out.target_points = target.size();
  NdtGridOptions go;
  go.resolution = o.ndt_resolution;
  const NdtGrid3D grid(target, go);
  NdtOptions no;
  no.num_threads = threads;
  if (o.max_iterations > 0) no.max_iterations = o.max_iterations;
  out.iteration_cap = no.max_iterations;
  const Ndt3dResult r = ndt_3d(grid, source, init, no);
  out.T_target_source = r.T_target_source;
  out.fitness = r.fitness;
  out.goodness = r.goodness;
  out.iterations = r.iterations;
  out.termination = r.termination;
  out.message = r.message;
  return out;
}

AlignResult run_icp(std::span<const Eigen::Vector3f> target,
                    std::span<const Eigen::Vector3f> source, const SE3d& init,
                    const AlignOptions& o, const std::vector<double>& voxels, int threads) {
  AlignResult out;
  // One voxel size: one level, gate max_distance. Several: coarse to fine,
  // gate distance_factor × voxel at each level.
  Icp3dMultiResolutionOptions mo;
  mo.voxel_sizes = voxels;
  mo.neighbors = o.neighbors;
  if (voxels.size() == 1) {
    if (voxels.front() > 0) {
      mo.distance_factor = o.max_distance / voxels.front();
    } else {
      mo.full_resolution_distance = o.max_distance;
    }
    out.max_distance = o.max_distance;
  } else {
    mo.distance_factor = o.distance_factor;
  }
  mo.icp.method = o.method == AlignMethod::PointToPoint   ? Icp3dMethod::PointToPoint
                  : o.method == AlignMethod::PointToPlane ? Icp3dMethod::PointToPlane
                                                          : Icp3dMethod::Gicp;
  mo.icp.num_threads = threads;
  if (o.max_iterations > 0) mo.icp.max_iterations = o.max_iterations;
  out.iteration_cap = mo.icp.max_iterations;
  const Icp3dMultiResolutionResult rr = icp_3d_multi_resolution(target, source, init, mo);
  for (const auto& level : rr.levels) out.level_messages.push_back(level.message);
  const Icp3dResult& r = rr.result;
  out.T_target_source = r.T_target_source;
  out.fitness = r.fitness;
  out.goodness = r.goodness;
  out.iterations = rr.total_iterations;
  out.termination = r.termination;
  out.message = r.message;
  out.source_points = rr.source_points.back();
  out.target_points = rr.target_points.back();
  return out;
}

}  // namespace

AlignResult align_clouds(std::span<const Eigen::Vector3f> target,
                         std::span<const Eigen::Vector3f> source, const SE3d& T_init,
                         const AlignOptions& options) {
  options.check();
  const int threads = resolve_thread_count(options.num_threads, "num_threads");
  std::vector<double> voxels;
  if (options.voxel_sizes) {
    voxels = *options.voxel_sizes;
  } else {
    const double v = suggest_voxel_size(target, AlignOptions::kAutoVoxels);
    if (v == 0 || options.method == AlignMethod::Ndt) {
      voxels = {v};
    } else {
      voxels = {v, std::round(v * AlignOptions::kFineRatio * 1e4) / 1e4};
    }
  }
  AlignResult r = options.method == AlignMethod::Ndt
                      ? run_ndt(target, source, T_init, options, voxels.front(), threads)
                      : run_icp(target, source, T_init, options, voxels, threads);
  r.voxel_sizes = std::move(voxels);
  r.voxel_auto = !options.voxel_sizes;
  return r;
}

}  // namespace rove
