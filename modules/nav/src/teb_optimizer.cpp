// The TEB's least-squares problem over a band and its Levenberg–Marquardt
// solve on the banded normal equations.
#include <algorithm>
#include <cmath>
#include <limits>

#include "banded_cholesky.h"
#include "rove/core/check.h"
#include "rove/nav/teb.h"
#include "rove/nav/teb_edges.h"

namespace rove {

namespace {

using teb::PoseVec;

// The variables: the poses strictly between the fixed ends (x, y, θ) and
// every interval, interleaved pose by pose so that each edge touches a
// window of at most 11 consecutive variables.
struct Layout {
  std::vector<int> pose;  // first variable of pose i, −1 when fixed
  std::vector<int> dt;    // variable of interval i
  int count = 0;
  static constexpr int kBand = 11;

  explicit Layout(std::size_t n) : pose(n, -1), dt(n > 0 ? n - 1 : 0, -1) {
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0 && i + 1 < n) {
        pose[i] = count;
        count += 3;
      }
      if (i + 1 < n) dt[i] = count++;
    }
  }
};

struct ObstacleLink {
  int pose;
  const TebObstacle* obstacle;
};

struct ViaLink {
  int pose;
  Eigen::Vector2d point;
};

// Sums w·|e|² over the edges and, when asked, the normal equations
// H = Σ w·JᵀJ (lower band) and g = Σ w·Jᵀe.
class Problem {
 public:
  Problem(const TebOptions& o, const Twist2& v0, std::vector<PoseVec>& poses, std::vector<double>& dts)
      : o_(o), v0_(v0), p_(poses), dt_(dts), layout_(poses.size()) {}

  const Layout& layout() const { return layout_; }
  std::vector<ObstacleLink> obstacles;
  std::vector<ViaLink> vias;
  double obstacle_weight = 0;

  double evaluate(detail::BandedSystem* H, std::vector<double>* g) const {
    Accumulator acc{H, g};
    const int n = static_cast<int>(p_.size());
    const auto vars = [&](std::initializer_list<int> poses, std::initializer_list<int> dts) {
      std::array<int, 11> idx{};
      int k = 0;
      for (int i : poses) {
        for (int c = 0; c < 3; ++c) idx[static_cast<std::size_t>(k++)] = layout_.pose[static_cast<std::size_t>(i)] < 0 ? -1 : layout_.pose[static_cast<std::size_t>(i)] + c;
      }
      for (int i : dts) idx[static_cast<std::size_t>(k++)] = layout_.dt[static_cast<std::size_t>(i)];
      return idx;
    };
    const bool jac = H != nullptr;
    for (int i = 0; i + 1 < n; ++i) {
      const PoseVec& a = pose(i);
      const PoseVec& b = pose(i + 1);
      Eigen::Matrix<double, 2, 7> J7;
      const Eigen::Vector2d ev = teb::velocity_error(a, b, dt(i), o_, jac ? &J7 : nullptr);
      acc.add<2, 7>(ev, J7, vars({i, i + 1}, {i}), {o_.weight_max_vel_x, o_.weight_max_vel_theta});
      Eigen::Matrix<double, 2, 6> J6;
      const bool car = o_.kinematics == TebKinematics::CarLike;
      const Eigen::Vector2d ek = car ? teb::car_like_error(a, b, o_, jac ? &J6 : nullptr)
                                     : teb::diff_drive_error(a, b, jac ? &J6 : nullptr);
      acc.add<2, 6>(ek, J6, vars({i, i + 1}, {}),
                    {o_.weight_kinematics_nh,
                     car ? o_.weight_kinematics_turning_radius : o_.weight_kinematics_forward_drive});
      double jt = 0;
      const double et = teb::time_optimal_error(dt(i), &jt);
      acc.add<1, 1>(Eigen::Matrix<double, 1, 1>(et), Eigen::Matrix<double, 1, 1>(jt), vars({}, {i}),
                    {o_.weight_optimaltime, 0});
      if (o_.weight_shortest_path > 0) {
        Eigen::Matrix<double, 1, 6> Js;
        const double es = teb::shortest_path_error(a, b, jac ? &Js : nullptr);
        acc.add<1, 6>(Eigen::Matrix<double, 1, 1>(es), Js, vars({i, i + 1}, {}), {o_.weight_shortest_path, 0});
      }
      if (i + 2 < n) {
        Eigen::Matrix<double, 2, 11> J11;
        const Eigen::Vector2d ea =
            teb::acceleration_error(a, b, pose(i + 2), dt(i), dt(i + 1), o_, jac ? &J11 : nullptr);
        acc.add<2, 11>(ea, J11, vars({i, i + 1, i + 2}, {i, i + 1}), {o_.weight_acc_lim_x, o_.weight_acc_lim_theta});
      }
    }
    if (n >= 2) {
      Eigen::Matrix<double, 2, 7> J7;
      const Eigen::Vector2d es =
          teb::acceleration_start_error(pose(0), pose(1), dt(0), v0_.vx, v0_.omega, o_, jac ? &J7 : nullptr);
      acc.add<2, 7>(es, J7, vars({0, 1}, {0}), {o_.weight_acc_lim_x, o_.weight_acc_lim_theta});
      if (!o_.free_goal_vel) {
        const Eigen::Vector2d eg =
            teb::acceleration_goal_error(pose(n - 2), pose(n - 1), dt(n - 2), 0.0, 0.0, o_, jac ? &J7 : nullptr);
        acc.add<2, 7>(eg, J7, vars({n - 2, n - 1}, {n - 2}), {o_.weight_acc_lim_x, o_.weight_acc_lim_theta});
      }
    }
    for (const ObstacleLink& l : obstacles) {
      Eigen::Matrix<double, 1, 3> J3;
      const PoseVec& a = pose(l.pose);
      const double e = teb::obstacle_error(a, closest_point(*l.obstacle, a.head<2>()), o_, jac ? &J3 : nullptr);
      acc.add<1, 3>(Eigen::Matrix<double, 1, 1>(e), J3, vars({l.pose}, {}), {obstacle_weight, 0});
    }
    for (const ViaLink& l : vias) {
      Eigen::Matrix<double, 1, 3> J3;
      const double e = teb::via_point_error(pose(l.pose), l.point, jac ? &J3 : nullptr);
      acc.add<1, 3>(Eigen::Matrix<double, 1, 1>(e), J3, vars({l.pose}, {}), {o_.weight_viapoint, 0});
    }
    return acc.cost;
  }

  // x ← x ⊕ δ (angles wrapped; intervals kept above 1 ms).
  void apply(const std::vector<double>& delta) {
    for (std::size_t i = 0; i < p_.size(); ++i) {
      const int v = layout_.pose[i];
      if (v >= 0) {
        p_[i] += Eigen::Vector3d(delta[static_cast<std::size_t>(v)], delta[static_cast<std::size_t>(v + 1)],
                                 delta[static_cast<std::size_t>(v + 2)]);
        p_[i].z() = teb::wrap_angle(p_[i].z());
      }
      if (i < dt_.size()) dt_[i] = std::max(1e-3, dt_[i] + delta[static_cast<std::size_t>(layout_.dt[i])]);
    }
  }

 private:
  struct Accumulator {
    detail::BandedSystem* H;
    std::vector<double>* g;
    double cost = 0;
    template <int M, int K>
    void add(const Eigen::Matrix<double, M, 1>& e, const Eigen::Matrix<double, M, K>& J,
             const std::array<int, 11>& idx, std::array<double, 2> w) {
      for (int r = 0; r < M; ++r) cost += w[static_cast<std::size_t>(r)] * e(r) * e(r);
      if (!H) return;
      for (int a = 0; a < K; ++a) {
        const int ia = idx[static_cast<std::size_t>(a)];
        if (ia < 0) continue;
        double ga = 0;
        for (int r = 0; r < M; ++r) ga += w[static_cast<std::size_t>(r)] * J(r, a) * e(r);
        (*g)[static_cast<std::size_t>(ia)] += ga;
        for (int b = 0; b < K; ++b) {
          const int ib = idx[static_cast<std::size_t>(b)];
          if (ib < 0 || ib > ia) continue;
          double h = 0;
          for (int r = 0; r < M; ++r) h += w[static_cast<std::size_t>(r)] * J(r, a) * J(r, b);
          H->at(ia, ib) += h;
        }
      }
    }
  };

  const PoseVec& pose(int i) const { return p_[static_cast<std::size_t>(i)]; }
  double dt(int i) const { return dt_[static_cast<std::size_t>(i)]; }

  const TebOptions& o_;
  Twist2 v0_;
  std::vector<PoseVec>& p_;
  std::vector<double>& dt_;
  Layout layout_;
};

// teb's obstacle association: every obstacle nearer to a pose than the
// inclusion distance, and beyond it the nearest on each side of the pose
// (left and right of its heading) within the cutoff distance.
void associate_obstacles(Problem& problem, const std::vector<PoseVec>& poses,
                         const std::vector<TebObstacle>& obstacles, const TebOptions& o) {
  problem.obstacles.clear();
  const double include = o.obstacle_association_force_inclusion_factor * o.min_obstacle_dist;
  const double cutoff = o.obstacle_association_cutoff_factor * o.min_obstacle_dist;
  for (int i = 1; i + 1 < static_cast<int>(poses.size()); ++i) {
    const PoseVec& p = poses[static_cast<std::size_t>(i)];
    const Eigen::Vector2d heading(std::cos(p.z()), std::sin(p.z()));
    double left = cutoff, right = cutoff;
    const TebObstacle* nearest_left = nullptr;
    const TebObstacle* nearest_right = nullptr;
    for (const TebObstacle& ob : obstacles) {
      const Eigen::Vector2d c = closest_point(ob, p.head<2>());
      const Eigen::Vector2d to = c - p.head<2>();
      const double d = to.norm() - o.robot_radius;
      if (d < include) {
        problem.obstacles.push_back({i, &ob});
        continue;
      }
      if (d >= cutoff) continue;
      const bool is_left = heading.x() * to.y() - heading.y() * to.x() > 0;
      if (is_left && d < left) left = d, nearest_left = &ob;
      if (!is_left && d < right) right = d, nearest_right = &ob;
    }
    if (nearest_left) problem.obstacles.push_back({i, nearest_left});
    if (nearest_right) problem.obstacles.push_back({i, nearest_right});
  }
}

void associate_vias(Problem& problem, const std::vector<PoseVec>& poses,
                    const std::vector<Eigen::Vector2d>& vias) {
  problem.vias.clear();
  if (poses.size() < 3) return;
  for (const Eigen::Vector2d& v : vias) {
    int best = 1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int i = 1; i + 1 < static_cast<int>(poses.size()); ++i) {
      const double d = (poses[static_cast<std::size_t>(i)].head<2>() - v).squaredNorm();
      if (d < best_d) best_d = d, best = i;
    }
    problem.vias.push_back({best, v});
  }
}

// Levenberg–Marquardt (Marquardt's diagonal scaling) for `iterations`
// iterations; returns the iterations run and updates `lambda`.
int levenberg_marquardt(Problem& problem, std::vector<PoseVec>& poses, std::vector<double>& dts,
                        int iterations, double& lambda) {
  const int n = problem.layout().count;
  if (n == 0) return 0;
  detail::BandedSystem H(n, Layout::kBand), A(n, Layout::kBand);
  std::vector<double> g(static_cast<std::size_t>(n)), step(static_cast<std::size_t>(n));
  int run = 0;
  for (int it = 0; it < iterations; ++it) {
    ++run;
    H.clear();
    std::fill(g.begin(), g.end(), 0.0);
    const double cost = problem.evaluate(&H, &g);
    if (cost <= 0) break;
    const std::vector<PoseVec> saved_poses = poses;
    const std::vector<double> saved_dts = dts;
    bool accepted = false;
    for (int attempt = 0; attempt < 8 && !accepted; ++attempt) {
      A = H;
      for (int i = 0; i < n; ++i) A.at(i, i) += lambda * (H.at(i, i) + 1e-9);
      if (!A.factor()) {
        lambda *= 10;
        continue;
      }
      for (int i = 0; i < n; ++i) step[static_cast<std::size_t>(i)] = -g[static_cast<std::size_t>(i)];
      A.solve(step);
      problem.apply(step);
      const double trial = problem.evaluate(nullptr, nullptr);
      if (std::isfinite(trial) && trial < cost) {
        accepted = true;
        lambda = std::max(lambda / 3, 1e-12);
      } else {
        poses = saved_poses;
        dts = saved_dts;
        lambda *= 4;
      }
    }
    if (!accepted) break;
  }
  return run;
}

}  // namespace

TebResult TebPlanner::optimize(TimedElasticBand& band, const Twist2& start_velocity,
                               const std::vector<TebObstacle>& obstacles,
                               const std::vector<Eigen::Vector2d>& via_points) const {
  ROVE_CHECK_GE(band.poses.size(), std::size_t{2});
  ROVE_CHECK_EQ(band.dts.size(), band.poses.size() - 1);
  const TebOptions& o = options_;
  TebResult r;
  double lambda = 1e-4;
  for (int outer = 0; outer < o.no_outer_iterations; ++outer) {
    resize_band(band, o);
    std::vector<PoseVec> poses(band.poses.size());
    for (std::size_t i = 0; i < poses.size(); ++i) {
      poses[i] = PoseVec(band.poses[i].translation().x(), band.poses[i].translation().y(), band.poses[i].angle());
    }
    std::vector<double>& dts = band.dts;
    Problem problem(o, start_velocity, poses, dts);
    problem.obstacle_weight = o.weight_obstacle * std::pow(o.weight_adapt_factor, outer);
    associate_obstacles(problem, poses, obstacles, o);
    associate_vias(problem, poses, via_points);
    if (outer == 0) r.initial_cost = problem.evaluate(nullptr, nullptr);
    r.iterations += levenberg_marquardt(problem, poses, dts, o.no_inner_iterations, lambda);
    r.cost = problem.evaluate(nullptr, nullptr);
    r.obstacle_edges = static_cast<int>(problem.obstacles.size());
    for (std::size_t i = 0; i < poses.size(); ++i) band.poses[i] = SE2d(poses[i].x(), poses[i].y(), poses[i].z());
  }
  r.poses = static_cast<int>(band.poses.size());
  r.termination = TebTermination::Optimized;
  return r;
}

}  // namespace rove
