#include "rove/registration/icp_3d_multi_resolution.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/maps/point_cloud.h"
#include "rove/maps/voxel_grid.h"
#include "rove/registration/prepared_cloud.h"

namespace rove {

void Icp3dMultiResolutionOptions::check() const {
  ROVE_CHECK_MSG(!voxel_sizes.empty(), "voxel_sizes must list at least one level");
  for (double v : voxel_sizes)
    ROVE_CHECK_MSG(std::isfinite(v) && v >= 0, "voxel sizes must be finite and >= 0, got {}", v);
  ROVE_CHECK_MSG(std::isfinite(distance_factor) && distance_factor > 0,
                 "distance_factor must be finite and > 0, got {}", distance_factor);
  ROVE_CHECK_MSG(std::isfinite(full_resolution_distance) && full_resolution_distance > 0,
                 "full_resolution_distance must be finite and > 0, got {}",
                 full_resolution_distance);
  ROVE_CHECK_GE(neighbors, std::size_t{3});
  ROVE_CHECK_MSG(gicp_epsilon > 0 && gicp_epsilon <= 1, "gicp_epsilon must be in (0, 1], got {}",
                 gicp_epsilon);
  icp.check();
}

namespace {

std::vector<Eigen::Vector3f> level_points(std::span<const Eigen::Vector3f> points, double voxel) {
  std::vector<Eigen::Vector3f> all(points.begin(), points.end());
  if (voxel == 0) return all;
  std::erase_if(all, [](const Eigen::Vector3f& p) { return !p.allFinite(); });
  const PointCloud down = voxel_downsample(PointCloud(std::move(all)), static_cast<float>(voxel));
  return down.points();
}

}  // namespace

Icp3dMultiResolutionResult icp_3d_multi_resolution(std::span<const Eigen::Vector3f> target,
                                                   std::span<const Eigen::Vector3f> source,
                                                   const SE3d& initial,
                                                   const Icp3dMultiResolutionOptions& o) {
  o.check();
  Icp3dMultiResolutionResult out;
  SE3d T = initial;
  PrepareOptions target_prep;
  target_prep.neighbors = o.neighbors;
  target_prep.gicp_epsilon = o.gicp_epsilon;
  target_prep.num_threads = o.icp.num_threads;
  target_prep.normals = o.icp.method == Icp3dMethod::PointToPlane;
  target_prep.covariances = o.icp.method == Icp3dMethod::Gicp;
  PrepareOptions source_prep = target_prep;
  source_prep.normals = false;
  source_prep.neighborhoods = false;  // only a target's are walked
  for (std::size_t level = 0; level < o.voxel_sizes.size(); ++level) {
    const double voxel = o.voxel_sizes[level];
    const PreparedCloud3D t(level_points(target, voxel), target_prep);
    const PreparedCloud3D s(level_points(source, voxel), source_prep);
    out.target_points.push_back(t.size());
    out.source_points.push_back(s.size());
    Icp3dOptions io = o.icp;
    io.max_correspondence_distance = voxel > 0 ? o.distance_factor * voxel : o.full_resolution_distance;
    Icp3dResult r = icp_3d(t, s, T, io);
    out.total_iterations += r.iterations;
    r.message = fmt::format("level {} (voxel {:g} m, gate {:g} m): {}", level, voxel,
                            io.max_correspondence_distance, r.message);
    out.levels.push_back(r);
    // A level that stopped short of its tolerances (the iteration cap, a
    // stalled step) still hands the finer level a better start.
    const bool go_on = r.termination == RegistrationTermination::Converged ||
                       r.termination == RegistrationTermination::MaxIterations ||
                       r.termination == RegistrationTermination::Stalled;
    if (!go_on) break;
    T = r.T_target_source;
  }
  out.result = out.levels.back();
  return out;
}

}  // namespace rove
