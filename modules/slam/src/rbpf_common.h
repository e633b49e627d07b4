#pragma once
// What the Rao-Blackwellized particle filters share (grid mapping,
// rove/slam/rbpf_slam.h, and range-only SLAM, rove/slam/ro_slam.h): the
// Gaussian of a pose increment, path nodes, groups of copies made by
// resampling, the check of an odometry increment, and the reweighting and
// adaptive resampling of one update.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <numbers>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "rove/bayes/log_weights.h"
#include "rove/bayes/random.h"
#include "rove/bayes/resampling.h"
#include "rove/core/check.h"
#include "rove/math/se2.h"
#include "rove/slam/rbpf_slam.h"

namespace rove::detail {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

inline double wrap_angle(double a) {
  // std::remainder gives a itself there; it was 2 % of rbpf-slam's time.
  if (a >= -std::numbers::pi && a <= std::numbers::pi) return a;
  return std::remainder(a, 2.0 * std::numbers::pi);
}

/// x ⊕ (Δx, Δy, Δφ): the pose reached by an increment in x's frame.
inline SE2d apply_increment(const SE2d& x, const Vec3& v) { return x * SE2d(v.x(), v.y(), v.z()); }

/// The diagonal covariance of standard deviations s.
inline Mat3 diag_sq(const Vec3& s) {
  Mat3 m = Mat3::Zero();
  m.diagonal() = s.cwiseAbs2();
  return m;
}

/// A Gaussian over pose increments (Δx, Δy, Δφ), the angle difference wrapped.
struct Gaussian3 {
  Vec3 mean = Vec3::Zero();
  Mat3 lower = Mat3::Identity();  // Cholesky factor of the covariance
  Mat3 information = Mat3::Identity();
  double log_norm = 0.0;  // −½ log det(2πΣ)

  static Gaussian3 of(const Vec3& mean, const Mat3& covariance) {
    Gaussian3 g;
    g.mean = mean;
    const Eigen::LLT<Mat3> llt(covariance);
    ROVE_CHECK_MSG(llt.info() == Eigen::Success, "a covariance is not positive definite");
    g.lower = llt.matrixL();
    g.information = llt.solve(Mat3::Identity());
    const double log_det = 2.0 * g.lower.diagonal().array().log().sum();
    g.log_norm = -0.5 * (log_det + 3.0 * std::log(2.0 * std::numbers::pi));
    return g;
  }
  double log_density(const Vec3& v) const {
    Vec3 d = v - mean;
    d.z() = wrap_angle(d.z());
    return log_norm - 0.5 * d.dot(information * d);
  }
  Vec3 sample(Rng& rng) const {
    const auto a = rng.normal_pair();
    const Vec3 z(a[0], a[1], rng.normal());
    return mean + lower * z;
  }
};

/// The motion prior of an update: the increment's Gaussian with `floor`
/// added to its (symmetrized) covariance. Throws InvalidArgument if the
/// increment is not finite or its covariance not symmetric positive
/// semidefinite.
inline Gaussian3 motion_prior(const OdometryIncrement& motion, const Mat3& floor) {
  const Eigen::Vector2d& dt = motion.mean.translation();
  ROVE_CHECK_MSG(dt.allFinite() && std::isfinite(motion.mean.angle()) && motion.covariance.allFinite(),
                 "the odometry increment is not finite");
  ROVE_CHECK_MSG((motion.covariance - motion.covariance.transpose()).cwiseAbs().maxCoeff() <=
                     1e-9 * (1.0 + motion.covariance.cwiseAbs().maxCoeff()),
                 "the odometry covariance is not symmetric");
  const Mat3 cov = 0.5 * (motion.covariance + motion.covariance.transpose()) + floor;
  ROVE_CHECK_MSG(Eigen::LLT<Mat3>(cov).info() == Eigen::Success,
                 "the odometry covariance is not positive semidefinite");
  return Gaussian3::of(Vec3(dt.x(), dt.y(), motion.mean.angle()), cov);
}

inline std::shared_ptr<const RbpfPathNode> make_node(const SE2d& pose, std::uint64_t step,
                                                     std::shared_ptr<const RbpfPathNode> previous) {
  return std::make_shared<RbpfPathNode>(pose, step, std::move(previous));
}

/// Particles with the same path node are copies of one particle (made by
/// resampling): the same pose and map. The groups of copies, each listing
/// its members' indices, in order of first member.
template <typename Particle>
std::vector<std::vector<std::size_t>> copy_groups(const std::vector<Particle>& particles) {
  std::vector<std::vector<std::size_t>> groups;
  std::map<const RbpfPathNode*, std::size_t> group_of;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const auto [it, fresh] = group_of.try_emplace(particles[i].path.get(), groups.size());
    if (fresh) groups.emplace_back();
    groups[it->second].push_back(i);
  }
  return groups;
}

/// How the weights of one update came out.
struct Reweighting {
  double ess = 1.0;      // ESS/N, before any resampling
  std::size_t best = 0;  // the most likely particle
};

/// Moves every particle to its new pose (extending its path with `step`),
/// adds pow_factor × its log-factor to its log-weight and normalizes.
/// Throws InvalidArgument if a log-factor is NaN.
template <typename Particle>
Reweighting reweigh(std::vector<Particle>& particles, std::vector<double>& log_weights,
                    const std::vector<SE2d>& poses, const std::vector<double>& log_factors,
                    std::uint64_t step, double pow_factor) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    ROVE_CHECK_MSG(!std::isnan(log_factors[i]), "particle {} got a NaN weight", i);
    particles[i].pose = poses[i];
    particles[i].path = make_node(poses[i], step, particles[i].path);
    log_weights[i] += pow_factor * log_factors[i];
  }
  const LogWeightSummary summary = summarize_log_weights(log_weights);
  for (double& w : log_weights) w -= summary.log_sum;
  return {summary.normalized_ess, summary.max_index};
}

/// Resamples the particles (method, numbers from the stream ~0 of `seed`)
/// and equalizes the weights.
template <typename Particle>
void resample(std::vector<Particle>& particles, std::vector<double>& log_weights,
              ResamplingMethod method, std::uint64_t seed) {
  const std::size_t n = particles.size();
  Rng rng = Rng::stream(seed, ~std::uint64_t{0});
  const std::vector<std::size_t> idx = resample_indices(method, log_weights, n, rng);
  std::vector<Particle> next;
  next.reserve(n);
  for (const std::size_t i : idx) next.push_back(particles[i]);
  particles = std::move(next);
  log_weights.assign(n, -std::log(static_cast<double>(n)));
}

}  // namespace rove::detail
