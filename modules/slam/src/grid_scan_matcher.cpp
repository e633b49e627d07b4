#include "rove/slam/grid_scan_matcher.h"

#include <cmath>
#include <string>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {
namespace {

// Catmull–Rom weights of the four nodes around t ∈ [0, 1) and their
// derivatives (the cubic Hermite spline with central-difference tangents).
struct CubicWeights {
  double w[4], d[4];
  explicit CubicWeights(double t) {
    const double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t + 2 * t2 - t3);
    w[1] = 0.5 * (2 - 5 * t2 + 3 * t3);
    w[2] = 0.5 * (t + 4 * t2 - 3 * t3);
    w[3] = 0.5 * (-t2 + t3);
    d[0] = 0.5 * (-1 + 4 * t - 3 * t2);
    d[1] = 0.5 * (-10 * t + 9 * t2);
    d[2] = 0.5 * (1 + 8 * t - 9 * t2);
    d[3] = 0.5 * (-2 * t + 3 * t2);
  }
};

// Value and gradient (per cell) of the interpolation at continuous cell
// coordinates u (cell centers at integers).
double interpolate_cells(const ProbabilityGrid& grid, double ux, double uy, double* gx,
                         double* gy) {
  const double fx = std::floor(ux), fy = std::floor(uy);
  const int i = static_cast<int>(fx), j = static_cast<int>(fy);
  const CubicWeights wx(ux - fx), wy(uy - fy);
  double f[4][4];
  if (i >= 1 && j >= 1 && i + 2 < grid.size_x() && j + 2 < grid.size_y()) {
    const std::uint16_t* v = grid.values().data();
    for (int b = 0; b < 4; ++b) {
      const std::uint16_t* row = v + grid.index(i - 1, j - 1 + b);
      for (int a = 0; a < 4; ++a) f[b][a] = ProbabilityGrid::value_to_probability(row[a]);
    }
  } else {
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) f[b][a] = grid.probability(i - 1 + a, j - 1 + b);
  }
  double value = 0.0, dx = 0.0, dy = 0.0;
  for (int b = 0; b < 4; ++b) {
    double rv = 0.0, rd = 0.0;
    for (int a = 0; a < 4; ++a) {
      rv += wx.w[a] * f[b][a];
      rd += wx.d[a] * f[b][a];
    }
    value += wy.w[b] * rv;
    dx += wy.w[b] * rd;
    dy += wy.d[b] * rv;
  }
  if (gx) *gx = dx;
  if (gy) *gy = dy;
  return value;
}

struct Problem {
  const ProbabilityGrid& grid;
  std::span<const Eigen::Vector2d> points;  // finite only
  Eigen::Vector3d prior;                   // x, y, θ
  const GridScanMatcherOptions& o;
  double scale2 = 0.0;  // w_occ² / N

  Eigen::Vector2d cell_coords(const Eigen::Vector2d& q) const {
    return q / grid.resolution() - grid.offset().cast<double>() - Eigen::Vector2d::Constant(0.5);
  }

  double prior_cost(const Eigen::Vector3d& x) const {
    return o.translation_weight * o.translation_weight * (x.head<2>() - prior.head<2>()).squaredNorm() +
           o.rotation_weight * o.rotation_weight * (x.z() - prior.z()) * (x.z() - prior.z());
  }

  double cost(const Eigen::Vector3d& x) const {
    const double c = std::cos(x.z()), s = std::sin(x.z());
    double sum = 0.0;
    for (const auto& p : points) {
      const Eigen::Vector2d u = cell_coords({c * p.x() - s * p.y() + x.x(), s * p.x() + c * p.y() + x.y()});
      const double m = interpolate_cells(grid, u.x(), u.y(), nullptr, nullptr);
      sum += (1.0 - m) * (1.0 - m);
    }
    return scale2 * sum + prior_cost(x);
  }

  // Gauss–Newton normal equations at x (H = JᵀJ, g = Jᵀr) and the cost.
  double linearize(const Eigen::Vector3d& x, Eigen::Matrix3d& H, Eigen::Vector3d& g) const {
    const double c = std::cos(x.z()), s = std::sin(x.z());
    const double inv_res = 1.0 / grid.resolution();
    H.setZero();
    g.setZero();
    double sum = 0.0;
    for (const auto& p : points) {
      const Eigen::Vector2d u = cell_coords({c * p.x() - s * p.y() + x.x(), s * p.x() + c * p.y() + x.y()});
      double gx = 0.0, gy = 0.0;
      const double m = interpolate_cells(grid, u.x(), u.y(), &gx, &gy);
      const double r = 1.0 - m;
      // r = 1 − M(R(θ)p + t): dr/dt = −∇M, dr/dθ = −∇M · R'(θ)p.
      const Eigen::Vector3d J(-gx * inv_res, -gy * inv_res,
                              -(gx * (-s * p.x() - c * p.y()) + gy * (c * p.x() - s * p.y())) * inv_res);
      H.noalias() += J * J.transpose();
      g += J * r;
      sum += r * r;
    }
    H *= scale2;
    g *= scale2;
    const double wt2 = o.translation_weight * o.translation_weight;
    const double wr2 = o.rotation_weight * o.rotation_weight;
    H(0, 0) += wt2;
    H(1, 1) += wt2;
    H(2, 2) += wr2;
    g.head<2>() += wt2 * (x.head<2>() - prior.head<2>());
    g.z() += wr2 * (x.z() - prior.z());
    return scale2 * sum + prior_cost(x);
  }
};

}  // namespace

void GridScanMatcherOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(occupied_space_weight) && occupied_space_weight > 0.0,
                 "occupied_space_weight {} must be > 0", occupied_space_weight);
  ROVE_CHECK_MSG(std::isfinite(translation_weight) && translation_weight >= 0.0,
                 "translation_weight {} must be >= 0", translation_weight);
  ROVE_CHECK_MSG(std::isfinite(rotation_weight) && rotation_weight >= 0.0,
                 "rotation_weight {} must be >= 0", rotation_weight);
  ROVE_CHECK_MSG(max_iterations >= 1, "max_iterations {} must be >= 1", max_iterations);
}

GridScanMatcherOptions GridScanMatcherOptions::from_config(const ConfigSection& section,
                                                           std::string_view prefix,
                                                           const GridScanMatcherOptions& defaults) {
  GridScanMatcherOptions o = defaults;
  const std::string p(prefix);
  o.occupied_space_weight =
      section.get_in_range(p + "occupied_space_weight", o.occupied_space_weight, 1e-9, 1e9);
  o.translation_weight = section.get_in_range(p + "translation_weight", o.translation_weight, 0, 1e9);
  o.rotation_weight = section.get_in_range(p + "rotation_weight", o.rotation_weight, 0, 1e9);
  o.max_iterations = static_cast<int>(
      section.get_in_range(p + "max_iterations", o.max_iterations, 1, 10000));
  return o;
}

double interpolate_probability(const ProbabilityGrid& grid, const Eigen::Vector2d& p,
                               Eigen::Vector2d* gradient) {
  const Eigen::Vector2d u =
      p / grid.resolution() - grid.offset().cast<double>() - Eigen::Vector2d::Constant(0.5);
  double gx = 0.0, gy = 0.0;
  const double v = interpolate_cells(grid, u.x(), u.y(), &gx, &gy);
  if (gradient) *gradient = Eigen::Vector2d(gx, gy) / grid.resolution();
  return v;
}

double grid_match_score(const ProbabilityGrid& grid, std::span<const Eigen::Vector2d> points_robot,
                        const SE2d& T_grid_robot) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& p : points_robot) {
    if (!p.allFinite()) continue;
    const Eigen::Vector2i c = grid.cell_of(T_grid_robot * p);
    sum += grid.probability(c.x(), c.y());
    ++n;
  }
  return n ? sum / static_cast<double>(n) : ProbabilityGrid::kMinProbability;
}

void CorrelativeSearchOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(linear_window) && linear_window >= 0.0,
                 "linear_window {} must be >= 0", linear_window);
  ROVE_CHECK_MSG(angular_window >= 0.0 && angular_window <= 3.14159265358979323846,
                 "angular_window {} must lie in [0, pi]", angular_window);
  ROVE_CHECK_MSG(std::isfinite(angular_step) && angular_step > 0.0, "angular_step {} must be > 0",
                 angular_step);
}

SE2d correlative_search_2d(const ProbabilityGrid& grid, std::span<const Eigen::Vector2d> points_robot,
                           const SE2d& initial_T_grid_robot, const CorrelativeSearchOptions& options) {
  options.check();
  const int w = static_cast<int>(std::ceil(options.linear_window / grid.resolution() - 1e-9));
  const int n = static_cast<int>(std::floor(options.angular_window / options.angular_step + 1e-9));
  std::vector<Eigen::Vector2i> cells;
  cells.reserve(points_robot.size());
  double best = -1.0, best_penalty = 0.0;
  SE2d best_pose = initial_T_grid_robot;
  for (int a = -n; a <= n; ++a) {
    const SE2d T(initial_T_grid_robot.translation().x(), initial_T_grid_robot.translation().y(),
                 initial_T_grid_robot.angle() + a * options.angular_step);
    cells.clear();
    for (const auto& p : points_robot)
      if (p.allFinite()) cells.push_back(grid.cell_of(T * p));
    if (cells.empty()) return initial_T_grid_robot;
    for (int dy = -w; dy <= w; ++dy) {
      for (int dx = -w; dx <= w; ++dx) {
        double sum = 0.0;
        for (const auto& c : cells) sum += grid.probability(c.x() + dx, c.y() + dy);
        const double penalty = dx * dx + dy * dy + a * a;
        if (sum > best || (sum == best && penalty < best_penalty)) {
          best = sum;
          best_penalty = penalty;
          best_pose = SE2d(T.translation().x() + dx * grid.resolution(),
                           T.translation().y() + dy * grid.resolution(), T.angle());
        }
      }
    }
  }
  return best_pose;
}

GridScanMatchResult match_scan_to_grid(const ProbabilityGrid& grid,
                                       std::span<const Eigen::Vector2d> points_robot,
                                       const SE2d& prior_T_grid_robot,
                                       const GridScanMatcherOptions& options) {
  options.check();
  GridScanMatchResult res;
  res.T_grid_robot = prior_T_grid_robot;
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(points_robot.size());
  for (const auto& p : points_robot)
    if (p.allFinite()) pts.push_back(p);
  if (pts.empty()) {
    res.message = "no finite point to match";
    res.score = ProbabilityGrid::kMinProbability;
    return res;
  }
  const Eigen::Vector3d prior(prior_T_grid_robot.translation().x(),
                              prior_T_grid_robot.translation().y(),
                              prior_T_grid_robot.angle());
  Problem pr{grid, pts, prior, options};
  pr.scale2 = options.occupied_space_weight * options.occupied_space_weight /
              static_cast<double>(pts.size());
  Eigen::Vector3d x = prior;
  Eigen::Matrix3d H;
  Eigen::Vector3d g;
  double cost = pr.linearize(x, H, g);
  res.initial_cost = cost;
  double lambda = 1e-4;
  res.termination = RegistrationTermination::MaxIterations;
  res.message = fmt::format("{} iterations without convergence", options.max_iterations);
  bool relinearize = false;
  for (int it = 0; it < options.max_iterations; ++it) {
    res.iterations = it + 1;
    if (relinearize) cost = pr.linearize(x, H, g);
    Eigen::Matrix3d A = H;
    A.diagonal() += lambda * H.diagonal().cwiseMax(1e-12);
    const Eigen::Vector3d step = A.ldlt().solve(-g);
    if (!step.allFinite()) {
      res.termination = RegistrationTermination::Converged;
      res.message = "no descent direction (flat cost)";
      break;
    }
    const Eigen::Vector3d x_new = x + step;
    const double cost_new = pr.cost(x_new);
    const bool small = step.head<2>().norm() < 1e-6 * grid.resolution() && std::abs(step.z()) < 1e-6;
    if (cost_new < cost) {
      x = x_new;
      const bool flat = cost - cost_new <= 1e-10 * cost;
      cost = cost_new;
      lambda = std::max(lambda * 0.3, 1e-9);
      relinearize = true;
      if (small || flat) {
        res.termination = RegistrationTermination::Converged;
        res.message = fmt::format("converged after {} iterations", it + 1);
        break;
      }
    } else {
      lambda *= 10.0;
      relinearize = false;
      if (small || lambda > 1e8) {
        res.termination = RegistrationTermination::Converged;
        res.message = fmt::format("at a minimum after {} iterations (no step lowers the cost)", it + 1);
        break;
      }
    }
  }
  res.final_cost = cost;
  res.T_grid_robot = SE2d(x.x(), x.y(), x.z());
  res.score = grid_match_score(grid, pts, res.T_grid_robot);
  return res;
}

}  // namespace rove
