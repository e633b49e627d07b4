#include "rove/maps/height_map.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <fstream>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/memory_budget.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {

HeightMapCreationOptions HeightMapCreationOptions::from_config(const ConfigSection& s) {
  HeightMapCreationOptions o;
  o.min_x = s.get<double>("min_x", o.min_x);
  o.max_x = s.get<double>("max_x", o.max_x);
  o.min_y = s.get<double>("min_y", o.min_y);
  o.max_y = s.get<double>("max_y", o.max_y);
  o.resolution = s.get<double>("resolution", o.resolution);
  if (s.has("mapType")) {
    const std::string t = s.get<std::string>("mapType", "");
    if (t != "mrSimpleAverage" && t != "0") {
      s.fail("mapType", fmt::format("'{}' is not a height map representation (accepted: "
                                    "mrSimpleAverage)", t));
    }
  }
  if (!(o.max_x > o.min_x)) s.fail("max_x", fmt::format("max_x ({}) must exceed min_x ({})", o.max_x, o.min_x));
  if (!(o.max_y > o.min_y)) s.fail("max_y", fmt::format("max_y ({}) must exceed min_y ({})", o.max_y, o.min_y));
  if (!(o.resolution > 0) || !std::isfinite(o.resolution)) {
    s.fail("resolution", fmt::format("must be finite and > 0, got {}", o.resolution));
  }
  for (const auto& [key, v] : {std::pair{"min_x", o.min_x}, std::pair{"max_x", o.max_x},
                               std::pair{"min_y", o.min_y}, std::pair{"max_y", o.max_y}}) {
    if (!std::isfinite(v)) s.fail(key, fmt::format("must be finite, got {}", v));
  }
  // The grid's size as HeightMap's constructor computes it, checked before
  // anything is allocated.
  const double nx = std::round((o.max_x - o.min_x) / o.resolution);
  const double ny = std::round((o.max_y - o.min_y) / o.resolution);
  const std::string what =
      fmt::format("[{}] resolution={} over x [{}, {}] y [{}, {}] m gives a {} \u00d7 {} height grid",
                  s.name(), o.resolution, o.min_x, o.max_x, o.min_y, o.max_y, nx, ny);
  if (!(nx >= 1 && ny >= 1)) s.fail("resolution", what + ": no cell");
  if (!(nx * ny <= 2147483648.0)) s.fail("resolution", what + ", above rove's limit of 2^31 cells");
  check_memory_budget(checked_bytes(static_cast<std::uint64_t>(nx * ny), sizeof(HeightCell)), what);
  return o;
}

HeightMapInsertOptions HeightMapInsertOptions::from_config(const ConfigSection& s) {
  HeightMapInsertOptions o;
  o.filter_by_height = s.get<bool>("filterByHeight", o.filter_by_height);
  o.z_min = s.get<double>("z_min", o.z_min);
  o.z_max = s.get<double>("z_max", o.z_max);
  s.ignore({"colorMap"}, "only colors MRPT's 3D view");
  return o;
}

HeightMapLikelihoodOptions HeightMapLikelihoodOptions::from_config(const ConfigSection& s) {
  HeightMapLikelihoodOptions o;
  o.sigma_z = s.get_in_range("sigma_z", o.sigma_z, 1e-9, 1e9);
  o.outlier_sigmas = s.get_in_range("outlier_sigmas", o.outlier_sigmas, 0.0, 1e6);
  o.decimation = s.get<unsigned>("decimation", o.decimation);
  if (o.decimation < 1) s.fail("decimation", "must be >= 1");
  return o;
}

HeightMap::HeightMap(HeightMapCreationOptions c, HeightMapInsertOptions io,
                     HeightMapLikelihoodOptions lo)
    : insert_options(io), likelihood_options(lo) {
  ROVE_CHECK(std::isfinite(c.min_x) && std::isfinite(c.max_x) && std::isfinite(c.min_y) &&
             std::isfinite(c.max_y) && std::isfinite(c.resolution));
  ROVE_CHECK_GT(c.max_x, c.min_x);
  ROVE_CHECK_GT(c.max_y, c.min_y);
  ROVE_CHECK_GT(c.resolution, 0.0);
  const double nx = std::round((c.max_x - c.min_x) / c.resolution);
  const double ny = std::round((c.max_y - c.min_y) / c.resolution);
  ROVE_CHECK_MSG(nx >= 1 && ny >= 1 && nx * ny <= 2147483648.0,
                 "height grid of {} x {} cells is empty or too large", nx, ny);
  size_x_ = static_cast<std::uint32_t>(nx);
  size_y_ = static_cast<std::uint32_t>(ny);
  x_min_ = c.min_x;
  y_min_ = c.min_y;
  resolution_ = c.resolution;
  cells_.assign(static_cast<std::size_t>(size_x_) * size_y_, HeightCell{});
}

std::ptrdiff_t HeightMap::index_at(double x, double y) const noexcept {
  const double fx = (x - x_min_) / resolution_, fy = (y - y_min_) / resolution_;
  if (!(fx >= 0 && fy >= 0 && fx < size_x_ && fy < size_y_)) return -1;
  const auto cx = static_cast<std::ptrdiff_t>(fx), cy = static_cast<std::ptrdiff_t>(fy);
  return cx + cy * static_cast<std::ptrdiff_t>(size_x_);
}

const HeightCell* HeightMap::cell_at(double x, double y) const noexcept {
  const std::ptrdiff_t i = index_at(x, y);
  return i < 0 ? nullptr : &cells_[static_cast<std::size_t>(i)];
}

const HeightCell& HeightMap::cell(std::uint32_t cx, std::uint32_t cy) const {
  ROVE_CHECK_LT(cx, size_x_);
  ROVE_CHECK_LT(cy, size_y_);
  return cells_[static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * size_x_];
}

bool HeightMap::insert_point(const Eigen::Vector3d& p) {
  const std::ptrdiff_t i = index_at(p.x(), p.y());
  if (i < 0 || !std::isfinite(p.z())) return false;
  HeightCell* c = &cells_[static_cast<std::size_t>(i)];
  if (insert_options.filter_by_height && !(p.z() >= insert_options.z_min && p.z() <= insert_options.z_max)) {
    return true;
  }
  // Welford's running mean and variance (numerically stable; MRPT keeps
  // raw sums, which cancel for heights far from 0).
  if (c->count == 0) ++observed_cells_;
  ++c->count;
  const double mean = c->mean;
  const double delta = p.z() - mean;
  const double new_mean = mean + delta / c->count;
  c->m2 += delta * (p.z() - new_mean);
  c->mean = new_mean;
  c->mean_z = static_cast<float>(new_mean);
  c->variance_z = c->count > 1 ? static_cast<float>(c->m2 / (c->count - 1)) : 0.0f;
  return true;
}

std::vector<Eigen::Vector3d> HeightMap::observation_points(const Observation& obs,
                                                           const Pose3& T) const {
  std::vector<Eigen::Vector3d> pts;
  if (const auto* scan = dynamic_cast<const RangeScan2D*>(&obs)) {
    pts = scan->points_3d(ScanFrame::Robot);
  } else if (const auto* img = dynamic_cast<const RangeImage3D*>(&obs)) {
    pts = img->project().points;
  } else {
    return pts;
  }
  for (auto& p : pts) p = T.rotation() * p + T.translation();
  return pts;
}

bool HeightMap::insert(const Observation& observation, const Pose3& T_map_robot) {
  const auto pts = observation_points(observation, T_map_robot);
  if (pts.empty()) return false;
  for (const auto& p : pts) insert_point(p);
  return true;
}

bool HeightMap::can_compute_likelihood(const Observation& o) const {
  return dynamic_cast<const RangeScan2D*>(&o) != nullptr ||
         dynamic_cast<const RangeImage3D*>(&o) != nullptr;
}

double HeightMap::log_likelihood(const Observation& observation, const Pose3& T_map_robot) const {
  const auto pts = observation_points(observation, T_map_robot);
  if (pts.empty()) return 0.0;
  ROVE_CHECK_GE(likelihood_options.decimation, 1u);
  const double s2 = likelihood_options.sigma_z * likelihood_options.sigma_z;
  const double outlier = -0.5 * likelihood_options.outlier_sigmas * likelihood_options.outlier_sigmas;
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < pts.size(); i += likelihood_options.decimation) {
    const auto& p = pts[i];
    const HeightCell* c = cell_at(p.x(), p.y());
    if (c != nullptr && c->count > 0 && std::isfinite(p.z())) {
      const double d = p.z() - c->mean_z;
      sum += -0.5 * d * d / (s2 + c->variance_z);
    } else {
      sum += outlier;
    }
    ++n;
  }
  return sum / static_cast<double>(n);
}

void HeightMap::clear() {
  std::fill(cells_.begin(), cells_.end(), HeightCell{});
  observed_cells_ = 0;
}

MapBounds HeightMap::bounding_box() const {
  MapBounds b;
  for (std::uint32_t cy = 0; cy < size_y_; ++cy) {
    for (std::uint32_t cx = 0; cx < size_x_; ++cx) {
      const auto& c = cells_[cx + static_cast<std::size_t>(cy) * size_x_];
      if (c.count == 0) continue;
      b.extend(Eigen::Vector3d(x_min_ + cx * resolution_, y_min_ + cy * resolution_, c.mean_z));
      b.extend(Eigen::Vector3d(x_min_ + (cx + 1) * resolution_, y_min_ + (cy + 1) * resolution_,
                               c.mean_z));
    }
  }
  return b;
}

MapStatistics HeightMap::statistics() const {
  MapStatistics s;
  s.elements = observed_cells_;
  s.unit = "cells";
  s.total_cells = cells_.size();
  s.bounds = bounding_box();
  return s;
}

}  // namespace rove
