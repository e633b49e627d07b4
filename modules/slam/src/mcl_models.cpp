#include "mcl_models.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "rove/core/check.h"
#include "rove/maps/beacon_map.h"
#include "rove/maps/grid_logodds.h"
#include "rove/maps/landmark_map.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose3.h"

namespace rove::detail {
namespace {

// A 3x3 matrix S with S·Sᵀ = C for a symmetric positive semi-definite C
// (eigen-decomposition, negative rounding noise clamped to 0): also a
// degenerate covariance (no noise along some axis) has one.
Eigen::Matrix3d psd_sqrt(const Eigen::Matrix3d& C) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (C + C.transpose()));
  const Eigen::Vector3d s = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return es.eigenvectors() * s.asDiagonal();
}

Pose2 to_pose2_unwrapped(const SE2d& T) {
  return Pose2(T.translation().x(), T.translation().y(), T.angle());
}

}  // namespace

MotionSampler::MotionSampler(const RobotMovement2D& motion,
                             const std::optional<MotionModelOptions>& model) {
  const MotionModelOptions& m = model ? *model : motion.motion_model;
  const bool own_estimate = !model && motion.estimated_pose_change.has_value();
  if (!own_estimate && m.model == MotionModel::Thrun) {
    thrun_.emplace(motion.odometry_increment, m.thrun);
    const Pose2& u = motion.odometry_increment;
    mean_ = SE2d(u.x(), u.y(), u.phi());
    return;
  }
  const Pose2Gaussian g = own_estimate ? *motion.estimated_pose_change
                                       : gaussian_motion_model(motion.odometry_increment, m.gaussian);
  const Pose2& mu = g.mean();
  mean_xyphi_ = Eigen::Vector3d(mu.x(), mu.y(), mu.phi());
  sqrt_cov_ = psd_sqrt(g.covariance());
  mean_ = SE2d(mu.x(), mu.y(), mu.phi());
}

SE2d MotionSampler::sample(Rng& rng) const {
  // Normal draws in Box–Muller pairs (the fourth of the Gaussian's is unused).
  if (thrun_) {
    std::array<double, 6> n{};
    for (std::size_t k = 0; k < n.size(); k += 2) {
      const auto pair = rng.normal_pair();
      n[k] = pair[0];
      n[k + 1] = pair[1];
    }
    const ThrunMotionSample s = thrun_->sample(n);
    return SE2d(s.x, s.y, s.phi);
  }
  const auto n01 = rng.normal_pair(), n2 = rng.normal_pair();
  const Eigen::Vector3d n(n01[0], n01[1], n2[0]);
  const Eigen::Vector3d d = mean_xyphi_ + sqrt_cov_ * n;
  return SE2d(d.x(), d.y(), d.z());
}

MapLikelihoods::MapLikelihoods(const MultiMetricMap& map) {
  for (const auto& e : map.entries()) {
    const bool selected = e.params.enable_likelihood &&
                          (!map.likelihood_selection || e.map->kind() == *map.likelihood_selection);
    if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get())) {
      Grid grid;
      grid.grid = &g->grid();
      grid.likelihood = selected;
      if (selected) {
        grid.model = std::make_unique<GridLikelihoodModel<std::int8_t>>(
            g->grid(), g->likelihood_options, g->insert_options);
      }
      grids.push_back(std::move(grid));
    } else if (selected) {
      others.push_back({e.map.get()});
    }
  }
}

FrameLikelihood::FrameLikelihood(const MapLikelihoods& maps, const SensoryFrame& frame) {
  for (const auto& obs : frame.observations) {
    if (const auto* scan = dynamic_cast<const RangeScan2D*>(obs.get())) {
      for (const auto& g : maps.grids) {
        if (g.likelihood) grid_terms_.push_back({g.model.get(), g.model->prepare(*scan)});
      }
    }
    for (const auto& o : maps.others) {
      if (o.map->can_compute_likelihood(*obs)) other_terms_.push_back({o.map, obs.get()});
    }
  }
}

double FrameLikelihood::operator()(const SE2d& T_map_robot) const {
  double sum = 0.0;
  for (const auto& t : grid_terms_) sum += t.model->log_likelihood(t.scan, T_map_robot);
  if (!other_terms_.empty()) {
    const Pose3 pose(to_pose2_unwrapped(T_map_robot));
    for (const auto& t : other_terms_) sum += t.map->log_likelihood(*t.observation, pose);
  }
  return sum;
}

FreeSpaceSampler::FreeSpaceSampler(const OccupancyGrid& grid, double threshold,
                                   const std::optional<Box>& box)
    : grid_(&grid) {
  for (std::uint32_t cy = 0; cy < grid.size_y(); ++cy) {
    const double y = grid.idx_to_y(cy);
    if (box && (y < box->min_y || y > box->max_y)) continue;
    for (std::uint32_t cx = 0; cx < grid.size_x(); ++cx) {
      const double x = grid.idx_to_x(cx);
      if (box && (x < box->min_x || x > box->max_x)) continue;
      if (grid.free_probability(static_cast<int>(cx), static_cast<int>(cy)) >= threshold) {
        cells_.push_back(cx + cy * grid.size_x());
      }
    }
  }
}

SE2d FreeSpaceSampler::sample(Rng& rng, double min_yaw, double max_yaw) const {
  const std::uint32_t c = cells_[rng.uniform_index(cells_.size())];
  const std::uint32_t cx = c % grid_->size_x(), cy = c / grid_->size_x();
  const double half = 0.5 * grid_->resolution();
  const double x = grid_->idx_to_x(cx) + rng.uniform(-half, half);
  const double y = grid_->idx_to_y(cy) + rng.uniform(-half, half);
  return SE2d(x, y, rng.uniform(min_yaw, max_yaw));
}

MapAgreement::MapAgreement(const MapLikelihoods& maps, const ConvergenceOptions& options)
    : maps_(&maps) {
  if (options.min_scan_fit <= 0.0) return;
  for (const auto& g : maps.grids) {
    if (!g.likelihood) continue;
    grid_ = g.grid;
    break;
  }
  if (grid_ == nullptr) return;
  // Occupied: p(free) < 0.5, as the clearance map of rove::maps.
  occupied_below_ = LogOddsLut<std::int8_t>::instance().p2l(0.5f);
  const double r = options.fit_distance / grid_->resolution();
  const int k = static_cast<int>(std::floor(r));
  for (int dy = -k; dy <= k; ++dy) {
    for (int dx = -k; dx <= k; ++dx) {
      if (dx * dx + dy * dy <= r * r) window_.emplace_back(dx, dy);
    }
  }
  near_.assign(grid_->cells().size(), 0);
}

bool MapAgreement::near_wall(int cx, int cy) {
  std::uint8_t& known = near_[grid_->index(cx, cy)];
  if (known == 0) {
    known = 2;
    const std::span<const std::int8_t> cells = grid_->cells();
    for (const Eigen::Vector2i& d : window_) {
      const int x = cx + d.x(), y = cy + d.y();
      if (grid_->contains(x, y) && cells[grid_->index(x, y)] < occupied_below_) {
        known = 1;
        break;
      }
    }
  }
  return known == 1;
}

std::optional<double> MapAgreement::scan_fit(const SensoryFrame& frame, const SE2d& T_map_robot) {
  if (grid_ == nullptr) return std::nullopt;
  std::size_t points = 0, near = 0;
  std::vector<float> xs, ys;
  for (const auto& scan : frame.find_all<RangeScan2D>()) {
    mrpt_scan_points(*scan, 0.0f, xs, ys);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const Eigen::Vector2d p = T_map_robot * Eigen::Vector2d(xs[i], ys[i]);
      const int cx = grid_->x_to_idx_clamped(p.x()), cy = grid_->y_to_idx_clamped(p.y());
      ++points;
      if (grid_->contains(cx, cy) && near_wall(cx, cy)) ++near;
    }
  }
  if (points == 0) return std::nullopt;
  return static_cast<double>(near) / static_cast<double>(points);
}

std::optional<double> MapAgreement::range_residual(const SensoryFrame& frame,
                                                   const SE2d& T_map_robot) const {
  const Pose3 pose(to_pose2_unwrapped(T_map_robot));
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& o : frame.find_all<BeaconRanges>()) {
    for (const auto& m : maps_->others) {
      std::optional<double> sigma;
      for (const auto& r : o->readings) {
        if (!std::isfinite(r.range)) continue;
        std::optional<Eigen::Vector3d> beacon;
        if (const auto* lm = dynamic_cast<const LandmarkMap*>(m.map)) {
          if (const Landmark* l = lm->find(r.beacon_id)) beacon = l->position.mean;
          sigma = lm->likelihood_options.beacon_ranges_use_observation_std
                      ? static_cast<double>(o->std_error)
                      : lm->likelihood_options.beacon_ranges_std;
        } else if (const auto* bm = dynamic_cast<const BeaconMap*>(m.map)) {
          if (const Beacon* b = bm->find(r.beacon_id)) beacon = b->moments().mean;
          sigma = bm->likelihood_options.range_std;
        }
        if (!beacon || !sigma || !(*sigma > 0.0)) continue;
        const Eigen::Vector3d sensor = pose.rotation() * r.position_on_robot + pose.translation();
        const double e = ((*beacon - sensor).norm() - static_cast<double>(r.range)) / *sigma;
        sum += e * e;
        ++n;
      }
    }
  }
  if (n == 0) return std::nullopt;
  return std::sqrt(sum / static_cast<double>(n));
}

}  // namespace rove::detail
