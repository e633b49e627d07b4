#include "rove/slam/rbpf_slam.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include <Eigen/Cholesky>

#include "rove/bayes/log_weights.h"
#include "rove/bayes/random.h"
#include "rove/core/check.h"
#include "rove/registration/icp_target_2d.h"
#include "rove/slam/scan_consistency.h"
#include "rbpf_common.h"

namespace rove {
namespace {

using detail::apply_increment;
using detail::diag_sq;
using detail::Gaussian3;
using detail::Mat3;
using detail::Vec3;
using detail::wrap_angle;

/// log(exp(a) + exp(b)) without overflow.
double log_add(double a, double b) {
  if (a < b) std::swap(a, b);
  if (b == -std::numeric_limits<double>::infinity()) return a;
  return a + std::log1p(std::exp(b - a));
}

/// What every particle's proposal shares in one update.
struct UpdateContext {
  const RbpfSlamOptions& options;
  const TiledLikelihoodField& field;
  const TiledScanPoints& points;
  const TiledScanPoints& every_point;               // the optimal proposal's refinement
  const std::vector<Eigen::Vector2d>& scan_points;  // ICP's source
  Gaussian3 prior;                                  // of the increment
  Vec3 match_std;                                   // spread around a matched mode
  double reach = 0.0;                               // farthest scan point, m
};

/// A particle's new pose and the log of its (untempered) weight factor.
struct Proposal {
  SE2d pose;
  double log_factor = 0.0;
  bool fallback = false;
};

/// Hill climbing on f from `start`: steps of `step` per axis, halved
/// `levels` − 1 times (the scan matcher of Grisetti et al. 2007, §IV).
/// f(v, floor) may return any value ≤ floor once it knows f(v) is below
/// floor.
template <typename F>
Vec3 climb(const F& f, Vec3 start, Vec3 step, int levels) {
  double best = f(start, -std::numeric_limits<double>::infinity());
  for (int level = 0; level < levels; ++level, step *= 0.5) {
    // The step back to the pose the last move came from (up to rounding):
    // its value is below best, so it is not evaluated again.
    int back_axis = -1;
    double back_sign = 0.0;
    for (int it = 0; it < 16; ++it) {
      bool improved = false;
      for (int axis = 0; axis < 3; ++axis) {
        for (const double sign : {1.0, -1.0}) {
          if (axis == back_axis && sign == back_sign) continue;
          Vec3 v = start;
          v[axis] += sign * step[axis];
          const double fv = f(v, best);
          if (fv > best) {
            best = fv;
            start = v;
            improved = true;
            back_axis = axis;
            back_sign = -sign;
          }
        }
      }
      if (!improved) break;
    }
  }
  return start;
}

/// The mean and covariance of weighted increments v (log-weights lw,
/// log_sum their log-sum-exp), angles taken about `mode` (Grisetti 2007,
/// eq. 18–19); the mean relative to `mode`.
struct Moments {
  Vec3 mean = Vec3::Zero();
  Mat3 covariance = Mat3::Zero();
};
Moments weighted_moments(const std::vector<Vec3>& v, const std::vector<double>& lw, double log_sum,
                         const Vec3& mode) {
  const std::size_t k = v.size();
  Moments m;
  std::vector<double> w(k);
  for (std::size_t j = 0; j < k; ++j) {
    w[j] = std::exp(lw[j] - log_sum);
    Vec3 d = v[j] - mode;
    d.z() = wrap_angle(d.z());
    m.mean += w[j] * d;
  }
  for (std::size_t j = 0; j < k; ++j) {
    Vec3 d = v[j] - mode;
    d.z() = wrap_angle(d.z());
    d -= m.mean;
    m.covariance += w[j] * d * d.transpose();
  }
  return m;
}

Proposal propose_optimal(const RbpfParticle& p, const UpdateContext& c, Rng& rng) {
  // log p(z | x, m) + log p(x | x', u), or a value ≤ floor once it is
  // sure to be below floor (the likelihood field stops early).
  // The poses evaluated lie close together: their points fall in the same
  // cells of the particle's map again and again (the values are the same
  // as without the memo). One memo per point set: its windows follow the
  // points' order.
  thread_local TiledDistanceMemo memo, memo_every;
  const auto target_of = [&](const TiledScanPoints& points, TiledDistanceMemo& m) {
    return [&p, &c, pts = &points, mm = &m](const Vec3& v, double floor) {
      const double prior = c.prior.log_density(v);
      return c.field.log_likelihood_above(p.map, *pts, apply_increment(p.pose, v), floor - prior,
                                          *mm) +
             prior;
    };
  };
  // The mode: a climb on the likelihood of the LF_decimation points in
  // steps of 2 and 1 cells, then on every point of the scan in steps of 1
  // and ½ cell (GMapping's matcher, too, uses every beam). The likelihood
  // of one in LF_decimation points (45 of the Intel log's 180) is constant
  // while they stay in their cells, and on such a plateau the motion prior
  // decides. The Intel log's odometry turns 1.2° too far per update; the
  // climb kept −0.29° of that per update (std 1.1°, against rove
  // lidar-slam's path) and the corridors bent. The sum over every point
  // changes within a cell: over the whole run the heading error per update
  // went from −0.19° ± 1.52° to 0.00° ± 0.89° (docs/filter-slam.md).
  memo.clear();
  memo_every.clear();
  const auto target = target_of(c.points, memo);
  const Vec3 coarse = climb(target, c.prior.mean, 2.0 * c.match_std, 2);
  const Vec3 mode = climb(target_of(c.every_point, memo_every), coarse, c.match_std, 2);
  const Mat3 floor = diag_sq(0.25 * c.match_std);
  const Gaussian3 around = Gaussian3::of(mode, diag_sq(c.match_std));
  // Adaptive defensive importance sampling (population Monte Carlo), in
  // rounds of kRound poses, until the importance weights hold kTargetEss
  // effective samples or search_samples poses were drawn. The first round
  // draws half around the mode and half from the motion prior. Every later
  // round draws 3/4 from the Gaussian of the weighted samples so far (its
  // covariance × 1.5, plus the floor), 1/8 around the mode and 1/8 from
  // the prior. Each pose is weighted by its own round's mixture density,
  // so the mean weight stays an unbiased estimate of η, and the prior's
  // share bounds the weights where the matched mode is wrong. The
  // posterior is a fraction of a cell wide: drawing around the mode (one
  // cell) and from the prior alone took 247 poses per particle and update
  // on the Telecom loop to reach 32 effective samples, adapting takes 121,
  // with the same maps over 10 seeds, Intel's as consistent and the
  // simulated loop's paths as close over 32 seeds (docs/filter-slam.md).
  constexpr std::size_t kRound = 16;
  constexpr double kTargetEss = 32.0;
  const std::size_t k_max = std::max<std::size_t>(kRound, c.options.search_samples / kRound * kRound);
  std::vector<Vec3> v;
  std::vector<double> lw;
  v.reserve(k_max);
  lw.reserve(k_max);
  // A sample whose weight is sure to be below e^-kNegligible times the
  // largest so far is not evaluated to the end (the likelihood field stops
  // early): it keeps the upper bound, a relative error of η below
  // e^-kNegligible per such sample.
  constexpr double kNegligible = 40.0;
  double max_lw = -std::numeric_limits<double>::infinity();
  // The effective sample size (Σw)² / Σw² kept as the samples come, the
  // sums relative to the largest weight so far (rescaled when it grows):
  // summing every round afresh cost as much as a fifth of the samples.
  double sum = 0.0, sum_sq = 0.0;
  std::optional<Gaussian3> fitted;
  const double log_half = std::log(0.5), log_3_4 = std::log(0.75), log_1_8 = std::log(0.125);
  while (v.size() < k_max) {
    for (std::size_t j = 0; j < kRound; ++j) {
      Vec3 x;
      double lq = 0.0;
      if (!fitted) {
        x = j < kRound / 2 ? around.sample(rng) : c.prior.sample(rng);
        lq = log_half + log_add(around.log_density(x), c.prior.log_density(x));
      } else {
        x = j < 3 * kRound / 4   ? fitted->sample(rng)
            : j < 7 * kRound / 8 ? around.sample(rng)
                                 : c.prior.sample(rng);
        lq = log_add(log_3_4 + fitted->log_density(x),
                     log_1_8 + log_add(around.log_density(x), c.prior.log_density(x)));
      }
      v.push_back(x);
      const double l = target(x, max_lw - kNegligible + lq) - lq;
      lw.push_back(l);
      if (l > max_lw) {
        const double r = std::exp(max_lw - l);  // 0 for the first sample
        sum *= r;
        sum_sq *= r * r;
        max_lw = l;
      }
      const double e = std::exp(l - max_lw);
      sum += e;
      sum_sq += e * e;
    }
    if (sum * sum >= kTargetEss * sum_sq) break;
    const Moments m = weighted_moments(v, lw, max_lw + std::log(sum), mode);
    fitted = Gaussian3::of(mode + m.mean, 1.5 * m.covariance + floor);
  }
  Proposal out;
  // η = ∫ p(z | x, m) p(x | x', u) dx ≈ mean of the importance weights
  // (Grisetti 2007, eq. 20).
  const double log_sum = log_sum_exp(lw);
  out.log_factor = log_sum - std::log(static_cast<double>(v.size()));
  // The new pose: the Gaussian of the weighted samples, centred on the
  // refined mode (their weighted mean is the decimated likelihood's, with
  // its plateaus), its covariance plus the floor (invertible even when one
  // sample holds all the weight).
  const Moments m = weighted_moments(v, lw, log_sum, mode);
  const Gaussian3 g = Gaussian3::of(mode, m.covariance + floor);
  out.pose = apply_increment(p.pose, g.sample(rng));
  return out;
}

Proposal propose_standard(const RbpfParticle& p, const UpdateContext& c, Rng& rng) {
  Proposal out;
  out.pose = apply_increment(p.pose, c.prior.sample(rng));
  out.log_factor = c.field.log_likelihood(p.map, c.points, out.pose);
  return out;
}

// The ICP alignment of the scan against the particle's occupied cells near
// the prediction; the new pose drawn from its Gaussian when good enough.
Proposal propose_icp(const RbpfParticle& p, const UpdateContext& c, Rng& rng) {
  const SE2d predicted = apply_increment(p.pose, c.prior.mean);
  const Eigen::Vector2d& t = predicted.translation();
  const double r = c.reach + 1.0;
  std::vector<Eigen::Vector2d> cells = p.map.occupied_points(t.x() - r, t.x() + r, t.y() - r, t.y() + r);
  Proposal out;
  bool accepted = false;
  if (cells.size() >= 3 && c.scan_points.size() >= 3) {
    const IcpTarget2D target(std::move(cells));
    const Icp2dResult icp = icp_2d(target, c.scan_points, predicted, c.options.icp);
    const SE2d& m = icp.T_target_source;
    Mat3 cov = icp.covariance;  // over the right tangent at m
    accepted = icp.goodness >= c.options.icp_min_quality && m.translation().allFinite() &&
               std::isfinite(m.angle()) && cov.allFinite();
    if (accepted) {
      // The new pose m ⊕ δ, δ ~ N(0, Σ) over the right tangent.
      cov = 0.5 * (cov + cov.transpose()) + diag_sq(0.25 * c.match_std);
      const Gaussian3 g = Gaussian3::of(Vec3::Zero(), cov);
      out.pose = m * SE2d::exp(g.sample(rng));
    }
  }
  if (!accepted) {
    out.pose = apply_increment(p.pose, c.prior.sample(rng));
    out.fallback = true;
  }
  out.log_factor = c.field.log_likelihood(p.map, c.points, out.pose);
  return out;
}

/// scan.check(), and no NaN range on a ray flagged valid: malformed data
/// (+inf reads as "no return", MRPT's convention).
void check_scan(const RangeScan2D& scan) {
  scan.check();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    ROVE_CHECK_MSG(!(scan.valid[i] && std::isnan(scan.ranges[i])),
                   "ray {} of the scan has a NaN range flagged valid", i);
  }
}

/// Root-mean-square distance of the points from the robot, clamped to
/// [1, 30] m: the lever arm that turns a rotation into a displacement.
double lever_arm(const TiledScanPoints& pts) {
  double s = 0.0;
  for (std::size_t j = 0; j < pts.xs.size(); ++j) s += pts.xs[j] * pts.xs[j] + pts.ys[j] * pts.ys[j];
  const double rms = pts.xs.empty() ? 1.0 : std::sqrt(s / static_cast<double>(pts.xs.size()));
  return std::clamp(rms, 1.0, 30.0);
}

}  // namespace

std::string_view mrpt_name(RbpfProposal proposal) {
  switch (proposal) {
    case RbpfProposal::Standard: return "pfStandardProposal";
    case RbpfProposal::Optimal: return "pfAuxiliaryPFOptimal";
    case RbpfProposal::Icp: return "pfOptimalProposal";
  }
  return "unknown";
}

void RbpfSlamOptions::check() const {
  ROVE_CHECK_MSG(particles >= 1, "sampleSize must be >= 1, got {}", particles);
  ROVE_CHECK_MSG(beta >= 0.0 && beta <= 1.0, "BETA must be in [0, 1], got {}", beta);
  ROVE_CHECK_MSG(std::isfinite(pow_factor) && pow_factor > 0.0 && pow_factor <= 1.0,
                 "powFactor must be in (0, 1], got {}", pow_factor);
  ROVE_CHECK_MSG(search_samples >= 4,
                 "pfAuxFilterOptimal_MaximumSearchSamples must be >= 4, got {}", search_samples);
  ROVE_CHECK_MSG(std::isfinite(resolution) && resolution > 0.0f, "resolution must be > 0, got {}",
                 resolution);
  ROVE_CHECK_MSG(icp_min_quality >= 0.0 && icp_min_quality <= 1.0,
                 "ICPGlobalAlign_MinQuality must be in [0, 1], got {}", icp_min_quality);
  ROVE_CHECK_MSG(static_cast<int>(resampling) <= 3, "unknown resamplingMethod {}",
                 static_cast<int>(resampling));
  insertion.check();
  likelihood.check();
  if (proposal == RbpfProposal::Icp) icp.check();
  (void)resolve_thread_count(num_threads);
}

struct RbpfSlam::Impl {
  explicit Impl(const RbpfSlamOptions& o)
      : field(o.resolution, o.likelihood, o.insertion),
        every_point_field(o.resolution, every_point(o.likelihood), o.insertion),
        team(resolve_thread_count(o.num_threads)) {}
  // The likelihood options with every point of the scan (LF_decimation 1).
  static GridLikelihoodOptions every_point(GridLikelihoodOptions l) {
    l.lf_decimation = 1;
    return l;
  }
  TiledLikelihoodField field;
  TiledLikelihoodField every_point_field;  // prepares the refinement's points
  ThreadTeam team;

  // Calls body(i) for i in [0, n) on the team, each index once.
  template <typename Body>
  void for_each(std::size_t n, const Body& body) {
    std::atomic<std::size_t> next{0};
    team.run([&](int) {
      for (std::size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) body(i);
    });
  }
};

RbpfSlam::RbpfSlam(RbpfSlamOptions options) : options_(std::move(options)) {
  options_.check();
  impl_ = std::make_unique<Impl>(options_);
  particles_.assign(options_.particles, RbpfParticle{SE2d(), TiledGrid(options_.resolution), nullptr});
  log_weights_.assign(options_.particles, -std::log(static_cast<double>(options_.particles)));
}

RbpfSlam::~RbpfSlam() = default;

std::size_t RbpfSlam::best() const {
  return static_cast<std::size_t>(std::max_element(log_weights_.begin(), log_weights_.end()) -
                                  log_weights_.begin());
}

std::size_t RbpfSlam::distinct_tiles() const {
  std::vector<const TiledGrid*> maps;
  maps.reserve(particles_.size());
  for (const auto& p : particles_) maps.push_back(&p.map);
  return TiledGrid::distinct_tiles(maps);
}

std::size_t RbpfSlam::insert(const RangeScan2D& scan, std::uint64_t step) {
  check_scan(scan);
  for (auto& p : particles_) {
    p.path = detail::make_node(p.pose, step, p.path);
  }
  return insert_all(scan);
}

std::size_t RbpfSlam::insert_all(const RangeScan2D& scan) {
  // Copies of one particle (made by resampling) insert once.
  const std::vector<std::vector<std::size_t>> groups = detail::copy_groups(particles_);
  impl_->for_each(groups.size(), [&](std::size_t g) {
    RbpfParticle& first = particles_[groups[g].front()];
    insert_scan(first.map, scan, first.pose, options_.insertion);
  });
  for (const auto& members : groups) {
    for (std::size_t k = 1; k < members.size(); ++k) {
      particles_[members[k]].map = particles_[members.front()].map;
    }
  }
  return groups.size();
}

RbpfUpdateResult RbpfSlam::update(const OdometryIncrement& motion, const RangeScan2D& scan,
                                  std::uint64_t step, bool insert_scan) {
  check_scan(scan);
  const TiledScanPoints points = impl_->field.prepare(scan);
  const TiledScanPoints every_point = options_.proposal == RbpfProposal::Optimal
                                          ? impl_->every_point_field.prepare(scan)
                                          : TiledScanPoints{};
  const double res = options_.resolution;
  const double lever = lever_arm(points);
  const Vec3 match_std(res, res, res / lever);
  // The motion prior, floored at a quarter of the matcher's spread so that
  // a zero-covariance odometry still gives a density.
  const Gaussian3 prior = detail::motion_prior(motion, diag_sq(0.25 * match_std));
  ++updates_;
  const std::uint64_t seed = derive_seed(options_.seed, updates_);
  const std::vector<Eigen::Vector2d> scan_points =
      options_.proposal == RbpfProposal::Icp ? scan.points_2d() : std::vector<Eigen::Vector2d>{};
  double reach = 0.0;
  for (std::size_t j = 0; j < points.xs.size(); ++j) reach = std::max(reach, std::hypot(points.xs[j], points.ys[j]));
  const UpdateContext ctx{options_, impl_->field, points, every_point, scan_points, prior, match_std, reach};

  const std::size_t n = particles_.size();
  std::vector<Proposal> proposals(n);
  impl_->for_each(n, [&](std::size_t i) {
    Rng rng = Rng::stream(seed, i);
    switch (options_.proposal) {
      case RbpfProposal::Optimal: proposals[i] = propose_optimal(particles_[i], ctx, rng); break;
      case RbpfProposal::Standard: proposals[i] = propose_standard(particles_[i], ctx, rng); break;
      case RbpfProposal::Icp: proposals[i] = propose_icp(particles_[i], ctx, rng); break;
    }
  });
  RbpfUpdateResult result;
  std::vector<SE2d> poses(n);
  std::vector<double> factors(n);
  for (std::size_t i = 0; i < n; ++i) {
    poses[i] = proposals[i].pose;
    factors[i] = proposals[i].log_factor;
    result.fallbacks += proposals[i].fallback ? 1 : 0;
  }
  const detail::Reweighting w =
      detail::reweigh(particles_, log_weights_, poses, factors, step, options_.pow_factor);
  result.ess = w.ess;
  const RbpfParticle& top = particles_[w.best];
  result.fit = top.map.empty() ? 1.0 : impl_->field.fit(top.map, points, top.pose);
  if (!top.map.empty()) {
    const double margin = std::max(kThroughWallsMargin, 4.0 * res);
    result.through_walls = rays_through_occupied(top.map, scan, top.pose, margin).fraction();
  }
  if (result.ess < options_.beta) {
    detail::resample(particles_, log_weights_, options_.resampling, seed);
    result.resampled = true;
  }
  if (insert_scan) result.insertions = insert_all(scan);
  result.distinct_tiles = distinct_tiles();
  return result;
}

RbpfPathNode::~RbpfPathNode() {
  // Nodes are made non-const (make_node) and only viewed as const, so
  // unlinking the chain here is allowed.
  std::shared_ptr<const RbpfPathNode> p = std::move(previous);
  while (p && p.use_count() == 1) {
    std::shared_ptr<const RbpfPathNode> next = std::move(const_cast<RbpfPathNode&>(*p).previous);
    p = std::move(next);
  }
}

std::vector<RbpfPathNode> path_of(const RbpfParticle& particle) { return path_of(particle.path); }

std::vector<RbpfPathNode> path_of(const std::shared_ptr<const RbpfPathNode>& last) {
  std::vector<RbpfPathNode> out;
  for (const RbpfPathNode* n = last.get(); n != nullptr; n = n->previous.get()) out.push_back(*n);
  std::reverse(out.begin(), out.end());
  return out;
}

}  // namespace rove
