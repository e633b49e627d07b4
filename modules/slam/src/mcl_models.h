#pragma once
// Internal pieces of Monte-Carlo localization (mcl.cpp): the motion sampler
// of one odometry action, the likelihood of one sensory frame in the map,
// the free-space sampler and the convergence checks.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "rove/bayes/random.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/math/se2.h"
#include "rove/obs/motion_models.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/slam/mcl_options.h"

namespace rove::detail {

// Samples of the pose increment of one odometry action, in the robot frame
// at the start of the motion: the action's Gaussian (mean + L·n, L·Lᵀ its
// covariance) or Thrun's model, as MRPT's fastDrawSingleSample.
class MotionSampler {
 public:
  // `model` replaces the action's own motion model when set.
  MotionSampler(const RobotMovement2D& motion, const std::optional<MotionModelOptions>& model);
  SE2d sample(Rng& rng) const;
  const SE2d& mean() const noexcept { return mean_; }

 private:
  SE2d mean_;
  Eigen::Vector3d mean_xyphi_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sqrt_cov_ = Eigen::Matrix3d::Zero();
  std::optional<ThrunMotionSampler> thrun_;
};

// The grid maps of a MultiMetricMap with their likelihood models, and its
// other maps, as MultiMetricMap::log_likelihood selects them.
struct MapLikelihoods {
  struct Grid {
    const OccupancyGrid* grid = nullptr;
    std::unique_ptr<GridLikelihoodModel<std::int8_t>> model;
    bool likelihood = false;  // takes part in the weighting
  };
  struct Other {
    const MetricMap* map = nullptr;
  };
  std::vector<Grid> grids;   // every occupancy grid (likelihood or not)
  std::vector<Other> others; // the other maps with likelihood enabled

  explicit MapLikelihoods(const MultiMetricMap& map);
  // The first occupancy grid of the map, or nullptr.
  const OccupancyGrid* first_grid() const noexcept {
    return grids.empty() ? nullptr : grids.front().grid;
  }
};

// log p(frame | T_map_robot): the sum over the frame's observations and the
// selected maps, with every per-scan setup done once.
class FrameLikelihood {
 public:
  FrameLikelihood(const MapLikelihoods& maps, const SensoryFrame& frame);
  // True if some map evaluates some observation.
  bool informative() const noexcept { return !grid_terms_.empty() || !other_terms_.empty(); }
  double operator()(const SE2d& T_map_robot) const;

 private:
  struct GridTerm {
    const GridLikelihoodModel<std::int8_t>* model;
    PreparedGridScan scan;
  };
  struct OtherTerm {
    const MetricMap* map;
    const Observation* observation;
  };
  std::vector<GridTerm> grid_terms_;
  std::vector<OtherTerm> other_terms_;
};

// Poses drawn uniformly over the free cells of a grid (p(free) ≥ threshold),
// optionally only those whose center lies in a box: a cell, then a point
// uniform in it, then a heading uniform in [min_yaw, max_yaw).
class FreeSpaceSampler {
 public:
  struct Box {
    double min_x, max_x, min_y, max_y;
  };
  FreeSpaceSampler(const OccupancyGrid& grid, double threshold, const std::optional<Box>& box);
  std::size_t cells() const noexcept { return cells_.size(); }
  SE2d sample(Rng& rng, double min_yaw, double max_yaw) const;

 private:
  const OccupancyGrid* grid_;
  std::vector<std::uint32_t> cells_;  // cx + cy · size_x
};

// The map checks of ConvergenceOptions at one pose.
class MapAgreement {
 public:
  MapAgreement(const MapLikelihoods& maps, const ConvergenceOptions& options);
  // Fraction of the frame's 2D scan points (every valid ray) within
  // fit_distance of an occupied cell of the first likelihood grid; unset
  // without grid or scan. Not const: it fills the cache of near_wall().
  std::optional<double> scan_fit(const SensoryFrame& frame, const SE2d& T_map_robot);
  // Root-mean-square residual, in range standard deviations, of the
  // frame's beacon ranges to beacons the maps know; unset if none.
  std::optional<double> range_residual(const SensoryFrame& frame, const SE2d& T_map_robot) const;

 private:
  // Whether an occupied cell's center lies within fit_distance of cell
  // (cx, cy)'s center: a search of the cells around it, remembered, so a
  // run pays for the cells its scans touch rather than a distance
  // transform of the whole grid.
  bool near_wall(int cx, int cy);

  const MapLikelihoods* maps_;
  const OccupancyGrid* grid_ = nullptr;
  std::int8_t occupied_below_ = 0;  // raw cell values below it are occupied
  std::vector<Eigen::Vector2i> window_;  // cell offsets within fit_distance
  std::vector<std::uint8_t> near_;  // per cell: 0 not computed, 1 near, 2 not
};

}  // namespace rove::detail
