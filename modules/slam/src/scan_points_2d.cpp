#include "rove/slam/scan_points_2d.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <unordered_map>

#include "rove/core/check.h"

namespace rove {

void ScanPointsOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(min_range) && min_range >= 0.0, "min_range {} must be >= 0",
                 min_range);
  ROVE_CHECK_MSG(std::isfinite(max_range) && max_range > min_range,
                 "max_range {} must be finite and > min_range {}", max_range, min_range);
  ROVE_CHECK_MSG(std::isfinite(voxel_size) && voxel_size >= 0.0, "voxel_size {} must be >= 0",
                 voxel_size);
}

ScanPointsOptions ScanPointsOptions::from_config(const ConfigSection& section) {
  ScanPointsOptions o;
  o.min_range = section.get_in_range("min_range", o.min_range, 0.0, 1e6);
  o.max_range = section.get_in_range("max_range", o.max_range, 1e-3, 1e6);
  o.voxel_size = section.get_in_range("voxel_size", o.voxel_size, 0.0, 100.0);
  if (o.max_range <= o.min_range) section.fail("max_range", "must be greater than min_range");
  return o;
}

ScanPoints2D scan_points_2d(const RangeScan2D& scan, const ScanPointsOptions& options) {
  options.check();
  scan.check();
  ScanPoints2D out;
  out.rays = scan.size();
  out.sensor_origin = Eigen::Vector2d(scan.T_robot_sensor.x(), scan.T_robot_sensor.y());
  const std::vector<std::size_t> rays = scan.point_ray_indices();
  out.valid_rays = rays.size();
  if (rays.empty()) return out;
  const std::vector<Eigen::Vector2d> pts = scan.points_2d(ScanFrame::Robot);
  std::vector<Eigen::Vector2d> kept;
  kept.reserve(pts.size());
  for (std::size_t k = 0; k < rays.size(); ++k) {
    const double r = scan.ranges[rays[k]];
    if (r < options.min_range || r >= options.max_range) continue;
    kept.push_back(pts[k]);
  }
  out.in_range_rays = kept.size();
  out.points = voxel_filter_2d(kept, options.voxel_size);
  for (const auto& p : out.points) out.max_point_range = std::max(out.max_point_range, p.norm());
  return out;
}

std::vector<Eigen::Vector2d> voxel_filter_2d(std::span<const Eigen::Vector2d> points,
                                             double voxel_size) {
  ROVE_CHECK_MSG(std::isfinite(voxel_size) && voxel_size >= 0.0,
                 "voxel_size {} must be finite and >= 0", voxel_size);
  std::vector<Eigen::Vector2d> out;
  if (voxel_size == 0.0) {
    for (const auto& p : points)
      if (p.allFinite()) out.push_back(p);
    return out;
  }
  // Sum the points of each voxel (hashing), then order the voxels.
  struct Voxel {
    std::int64_t ky, kx;
    Eigen::Vector2d sum;
    std::size_t n;
  };
  std::vector<Voxel> voxels;
  std::unordered_map<std::uint64_t, std::size_t> index;
  index.reserve(points.size());
  const double inv = 1.0 / voxel_size;
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) continue;
    const double kx = std::floor(p.x() * inv), ky = std::floor(p.y() * inv);
    ROVE_CHECK_MSG(std::abs(kx) < 2e9 && std::abs(ky) < 2e9,
                   "point ({}, {}) is too far for voxels of {} m", p.x(), p.y(), voxel_size);
    const auto ix = static_cast<std::int64_t>(kx), iy = static_cast<std::int64_t>(ky);
    const std::uint64_t key = (static_cast<std::uint64_t>(iy) << 32) ^
                              (static_cast<std::uint64_t>(ix) & 0xffffffffu);
    const auto [it, inserted] = index.try_emplace(key, voxels.size());
    if (inserted) {
      voxels.push_back({iy, ix, p, 1});
    } else {
      voxels[it->second].sum += p;
      ++voxels[it->second].n;
    }
  }
  std::sort(voxels.begin(), voxels.end(), [](const Voxel& a, const Voxel& b) {
    return a.ky != b.ky ? a.ky < b.ky : a.kx < b.kx;
  });
  out.reserve(voxels.size());
  for (const Voxel& v : voxels) out.push_back(v.sum / static_cast<double>(v.n));
  return out;
}

void AdaptiveVoxelFilterOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(max_length) && max_length > 0.0, "max_length {} must be > 0",
                 max_length);
  ROVE_CHECK_MSG(min_num_points >= 1, "min_num_points must be >= 1");
  ROVE_CHECK_MSG(std::isfinite(max_range) && max_range > 0.0, "max_range {} must be > 0",
                 max_range);
}

AdaptiveVoxelFilterOptions AdaptiveVoxelFilterOptions::from_config(
    const ConfigSection& section, std::string_view prefix,
    const AdaptiveVoxelFilterOptions& defaults) {
  AdaptiveVoxelFilterOptions o = defaults;
  const std::string p(prefix);
  o.max_length = section.get_in_range(p + "max_length", o.max_length, 1e-4, 1e3);
  o.min_num_points = static_cast<std::size_t>(
      section.get_in_range(p + "min_num_points", static_cast<double>(o.min_num_points), 1, 1e6));
  o.max_range = section.get_in_range(p + "max_range", o.max_range, 1e-3, 1e6);
  return o;
}

std::vector<Eigen::Vector2d> adaptive_voxel_filter_2d(std::span<const Eigen::Vector2d> points,
                                                      const AdaptiveVoxelFilterOptions& options) {
  options.check();
  std::vector<Eigen::Vector2d> near;
  near.reserve(points.size());
  const double r2 = options.max_range * options.max_range;
  for (const auto& p : points)
    if (p.allFinite() && p.squaredNorm() <= r2) near.push_back(p);
  if (near.size() <= options.min_num_points) return near;
  std::vector<Eigen::Vector2d> best = voxel_filter_2d(near, options.max_length);
  if (best.size() >= options.min_num_points) return best;
  // Bisection on the voxel side: `hi` leaves too few points, `lo` enough.
  double lo = 0.0, hi = options.max_length;
  best = near;
  while (hi - lo > 0.01 * options.max_length) {
    const double mid = 0.5 * (lo + hi);
    std::vector<Eigen::Vector2d> f = voxel_filter_2d(near, mid);
    if (f.size() >= options.min_num_points) {
      lo = mid;
      best = std::move(f);
    } else {
      hi = mid;
    }
  }
  return best;
}

}  // namespace rove
