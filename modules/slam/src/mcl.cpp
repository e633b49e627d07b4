#include "rove/slam/mcl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <Eigen/Eigenvalues>

#include "mcl_models.h"
#include "rove/bayes/resampling.h"
#include "rove/core/check.h"
#include "rove/math/statistics.h"

namespace rove {
namespace {

// Random-stream domains of a step's seed used here (rove::bayes uses 1–5).
constexpr std::uint64_t kInjectionResampleDomain = 100;
constexpr std::uint64_t kInjectionDomain = 101;

// The block diag(R, 1) that takes right-tangent (ρx, ρy, θ) coordinates at
// a pose with rotation R to map-frame (x, y, heading) ones, to first order.
Eigen::Matrix3d tangent_to_world(const SE2d& pose) {
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  J.topLeftCorner<2, 2>() = pose.rotation_matrix();
  return J;
}

// The particle filter's model for one step: motion samples composed on the
// right (the increment is in the robot frame), the frame's likelihood.
struct StepModel {
  const detail::MotionSampler* motion = nullptr;
  const detail::FrameLikelihood* likelihood = nullptr;
  SE2d sample_motion(const SE2d& x, Rng& rng) const { return x * motion->sample(rng); }
  double log_likelihood(const SE2d& x) const { return (*likelihood)(x); }
  SE2d predicted_mean(const SE2d& x) const { return x * motion->mean(); }
};

}  // namespace

Eigen::Matrix3d MclEstimate::world_covariance() const {
  const Eigen::Matrix3d J = tangent_to_world(mean);
  return J * covariance * J.transpose();
}

namespace {

// estimate_of with the normalized weights w of the particles.
MclEstimate estimate_with_weights(const ParticleSet<SE2d>& particles, const std::vector<double>& w) {
  const std::size_t n = particles.size();
  double mx = 0.0, my = 0.0, mc = 0.0, ms = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const SE2d& p = particles.states[i];
    const Eigen::Vector2d cs = p.rotation().unit_complex();
    mx += w[i] * p.translation().x();
    my += w[i] * p.translation().y();
    mc += w[i] * cs.x();
    ms += w[i] * cs.y();
  }
  const double heading = (mc == 0.0 && ms == 0.0) ? 0.0 : std::atan2(ms, mc);
  const double hc = std::cos(heading), hs = std::sin(heading);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (w[i] == 0.0) continue;
    const SE2d& p = particles.states[i];
    const Eigen::Vector2d cs = p.rotation().unit_complex();
    // Heading difference wrapped to (−π, π]: the angle of R(heading)ᵀ·R(θᵢ).
    const double dth = std::atan2(cs.y() * hc - cs.x() * hs, cs.x() * hc + cs.y() * hs);
    const Eigen::Vector3d d(p.translation().x() - mx, p.translation().y() - my, dth);
    C.noalias() += w[i] * d * d.transpose();
  }
  MclEstimate e;
  e.mean = SE2d(mx, my, heading);
  const Eigen::Matrix3d J = tangent_to_world(e.mean);
  e.covariance = J.transpose() * C * J;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C.topLeftCorner<2, 2>());
  e.position_std = std::sqrt(std::max(0.0, es.eigenvalues()(1)));
  e.heading_std = std::sqrt(std::max(0.0, C(2, 2)));
  return e;
}

// mass_near with the normalized weights w of the particles.
double mass_near_with_weights(const ParticleSet<SE2d>& particles, const std::vector<double>& w,
                              const SE2d& center, double radius, double heading_radius) {
  const Eigen::Vector2d cs = center.rotation().unit_complex();
  const double r2 = radius * radius, cos_limit = std::cos(std::min(heading_radius, kPi));
  double mass = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const SE2d& p = particles.states[i];
    // cos of the heading difference, without an atan2 per particle.
    if ((p.translation() - center.translation()).squaredNorm() <= r2 &&
        p.rotation().unit_complex().dot(cs) >= cos_limit) {
      mass += w[i];
    }
  }
  return mass;
}

}  // namespace

MclEstimate estimate_of(const ParticleSet<SE2d>& particles) {
  ROVE_CHECK_MSG(particles.size() > 0, "the estimate of an empty particle set");
  ROVE_CHECK_EQ(particles.log_weights.size(), particles.size());
  return estimate_with_weights(particles, weights_from_log_weights(particles.log_weights));
}

double mass_near(const ParticleSet<SE2d>& particles, const SE2d& center, double radius,
                 double heading_radius) {
  ROVE_CHECK_EQ(particles.log_weights.size(), particles.size());
  return mass_near_with_weights(particles, weights_from_log_weights(particles.log_weights), center,
                                radius, heading_radius);
}

struct MonteCarloLocalization::Impl {
  Impl(const MultiMetricMap& map, const MclOptions& o)
      : maps(map), agreement(maps, o.convergence), team(resolve_thread_count(o.num_threads)) {}

  detail::MapLikelihoods maps;
  detail::MapAgreement agreement;
  std::optional<detail::FreeSpaceSampler> free_space;    // the whole grid
  std::optional<detail::FreeSpaceSampler> initial_box;   // FreeSpaceInBox
  ThreadTeam team;
  // Augmented MCL's averages of the evidence (logarithms of the
  // exponential moving averages started at 0) and the updates they saw.
  double log_w_slow = -std::numeric_limits<double>::infinity();
  double log_w_fast = -std::numeric_limits<double>::infinity();
  std::uint64_t updates = 0;
  double last_injection = 0.0;  // the previous step's injection probability

  void reset_averages() {
    log_w_slow = log_w_fast = -std::numeric_limits<double>::infinity();
    updates = 0;
    last_injection = 0.0;
  }

  // Probabilistic Robotics, Table 8.3, lines 10–11 and 13, in logarithms
  // (the evidence of a scan is far below the smallest double). Thrun's
  // averages start at 0, so w_slow needs about 1/α_slow updates before
  // w_fast can fall below it (1,000 with AMCL's 0.001): no recovery in a
  // shorter run. Here each average is divided by 1 − (1 − α)^t, its weight
  // after t updates (the bias correction of Adam, Kingma & Ba 2015): the
  // mean of the evidence so far at first, the exponential average later.
  double injection_probability(const RecoveryOptions& rec, double log_evidence) {
    const auto update = [&](double& avg, double alpha) {
      avg = log_add_exp(std::log1p(-alpha) + avg, std::log(alpha) + log_evidence);
    };
    update(log_w_slow, rec.alpha_slow);
    update(log_w_fast, rec.alpha_fast);
    ++updates;
    const auto corrected = [&](double avg, double alpha) {
      return avg - std::log(-std::expm1(static_cast<double>(updates) * std::log1p(-alpha)));
    };
    const double ratio = std::exp(corrected(log_w_fast, rec.alpha_fast) -
                                  corrected(log_w_slow, rec.alpha_slow));
    return std::max(0.0, 1.0 - ratio);
  }
};

MonteCarloLocalization::MonteCarloLocalization(const MultiMetricMap& map, MclOptions options)
    : options_(std::move(options)) {
  options_.check();
  impl_ = std::make_unique<Impl>(map, options_);
  const ParticleInit& init = options_.init;
  const bool needs_free_space =
      init.mode == ParticleInitMode::FreeSpace || options_.recovery.enabled();
  const OccupancyGrid* grid = impl_->maps.first_grid();
  if (needs_free_space || init.mode == ParticleInitMode::FreeSpaceInBox) {
    ROVE_CHECK_MSG(grid != nullptr,
                   "particles drawn over free space (init_PDF_mode 0 or 2, or recovery) need an "
                   "occupancy grid in the map");
  }
  if (needs_free_space) {
    impl_->free_space.emplace(*grid, init.free_threshold, std::nullopt);
    ROVE_CHECK_MSG(impl_->free_space->cells() > 0,
                   "the occupancy grid has no free cell (p(free) >= {})", init.free_threshold);
  }
  if (init.mode == ParticleInitMode::FreeSpaceInBox) {
    impl_->initial_box.emplace(
        *grid, init.free_threshold,
        detail::FreeSpaceSampler::Box{init.min_x, init.max_x, init.min_y, init.max_y});
    ROVE_CHECK_MSG(impl_->initial_box->cells() > 0,
                   "no free cell (p(free) >= {}) of the occupancy grid lies in the initial box "
                   "x [{}, {}] m, y [{}, {}] m",
                   init.free_threshold, init.min_x, init.max_x, init.min_y, init.max_y);
  }
}

MonteCarloLocalization::~MonteCarloLocalization() = default;

void MonteCarloLocalization::initialize() {
  const ParticleInit& init = options_.init;
  std::vector<SE2d> states(init.count);
  const std::uint64_t seed = derive_seed(options_.seed, 0);
  parallel_for(states.size(), impl_->team, [&](std::size_t i) {
    Rng rng = Rng::stream(seed, i);
    switch (init.mode) {
      case ParticleInitMode::FreeSpaceInBox:
        states[i] = impl_->initial_box->sample(rng, init.min_yaw, init.max_yaw);
        return;
      case ParticleInitMode::UniformInBox: {
        const double x = rng.uniform(init.min_x, init.max_x);
        const double y = rng.uniform(init.min_y, init.max_y);
        states[i] = SE2d(x, y, rng.uniform(init.min_yaw, init.max_yaw));
        return;
      }
      case ParticleInitMode::FreeSpace:
        states[i] = impl_->free_space->sample(rng, -kPi, kPi);
        return;
      case ParticleInitMode::AroundPose: {
        const Eigen::Vector2d& t = init.pose.translation();
        const double x = rng.normal(t.x(), init.std_xy);
        const double y = rng.normal(t.y(), init.std_xy);
        states[i] = SE2d(x, y, rng.normal(init.pose.angle(), init.std_yaw));
        return;
      }
    }
  });
  set_particles(ParticleSet<SE2d>::uniform(std::move(states)));
}

void MonteCarloLocalization::set_particles(ParticleSet<SE2d> particles) {
  ROVE_CHECK_MSG(particles.size() > 0, "a particle set needs at least one particle");
  ROVE_CHECK_EQ(particles.log_weights.size(), particles.size());
  particles_ = std::move(particles);
  steps_ = 0;
  impl_->reset_averages();
}

MclStepResult MonteCarloLocalization::step(const RobotMovement2D* motion,
                                           const SensoryFrame& frame) {
  ROVE_CHECK_MSG(particles_.size() > 0, "MonteCarloLocalization::step before initialize()");
  ++steps_;
  const std::uint64_t step_seed = derive_seed(options_.seed, steps_);
  std::optional<detail::MotionSampler> sampler;
  if (motion != nullptr) sampler.emplace(*motion, options_.motion_model);
  const detail::FrameLikelihood likelihood(impl_->maps, frame);
  const StepModel model{sampler ? &*sampler : nullptr, &likelihood};
  ParticleFilterStepInput input;
  input.seed = step_seed;
  input.has_motion = sampler.has_value();
  input.has_observation = likelihood.informative();

  MclStepResult r;
  r.informative = input.has_observation;
  r.filter = particle_filter_step(particles_, model, options_.pf, options_.kld, input, impl_->team);
  const std::vector<double> weights = weights_from_log_weights(particles_.log_weights);
  r.estimate = estimate_with_weights(particles_, weights);
  const ConvergenceOptions& c = options_.convergence;
  if (r.informative) {
    r.scan_fit = impl_->agreement.scan_fit(frame, r.estimate.mean);
    r.range_residual = impl_->agreement.range_residual(frame, r.estimate.mean);
  }
  r.mass_near =
      mass_near_with_weights(particles_, weights, r.estimate.mean, c.radius, c.heading_radius);
  r.concentrated = r.mass_near >= c.min_mass;
  r.fits = (!r.scan_fit || *r.scan_fit >= c.min_scan_fit) &&
           (!r.range_residual || *r.range_residual <= c.max_range_residual);

  const RecoveryOptions& rec = options_.recovery;
  if (rec.enabled() && r.filter.termination == ParticleFilterTermination::Updated) {
    // The evidence of the particles the last injection kept: the random
    // share p explains next to nothing and would otherwise hold the
    // short-term average down, and the injection up, after a recovery.
    const double kept = std::log1p(-impl_->last_injection);
    r.injection_probability = impl_->injection_probability(rec, r.filter.log_evidence - kept);
  }
  if (r.injection_probability > 0.0) r.injected = inject(step_seed, r.injection_probability);
  impl_->last_injection = r.injection_probability;
  r.particles = particles_.size();
  return r;
}

std::size_t MonteCarloLocalization::inject(std::uint64_t step_seed, double p) {
  const std::uint64_t seed = derive_seed(step_seed, kInjectionDomain);
  const detail::FreeSpaceSampler& uniform = *impl_->free_space;
  if (options_.pf.adaptive_sample_size) {
    // The mixture (1 − p)·belief + p·uniform (Table 8.3's resampling, in
    // expectation) kept as weights: the particles stay with their weights
    // times 1 − p, and K = p·KLD_maxSampleSize random poses share p. With
    // KLD the set may hold a few hundred particles; drawing the uniform part
    // with as many poses as the filter may grow to covers the map, and its
    // small weights leave the tracked particles in charge until the
    // observations favour a random one. The next step's KLD-sampling
    // draws from the mixture.
    const auto k =
        static_cast<std::size_t>(std::round(p * static_cast<double>(options_.kld.max_sample_size)));
    if (k == 0) return 0;
    const std::size_t n = particles_.size();
    for (double& w : particles_.log_weights) w += std::log1p(-p);
    particles_.states.resize(n + k);
    particles_.log_weights.resize(n + k, std::log(p) - std::log(static_cast<double>(k)));
    parallel_for(k, impl_->team, [&](std::size_t i) {
      Rng g = Rng::stream(seed, i);
      particles_.states[n + i] = uniform.sample(g, -kPi, kPi);
    });
    return k;
  }
  // Table 8.3, lines 12–16: resample, each new particle replaced by a
  // random pose with probability p.
  const std::size_t n = particles_.size();
  Rng rng = Rng::stream(derive_seed(step_seed, kInjectionResampleDomain), 0);
  const std::vector<std::size_t> idx =
      resample_indices(options_.pf.resampling_method, particles_.log_weights, n, rng);
  std::vector<SE2d> states(n);
  std::vector<char> injected(n, 0);
  parallel_for(n, impl_->team, [&](std::size_t i) {
    Rng g = Rng::stream(seed, i);
    if (g.uniform() < p) {
      states[i] = uniform.sample(g, -kPi, kPi);
      injected[i] = 1;
    } else {
      states[i] = particles_.states[idx[i]];
    }
  });
  particles_ = ParticleSet<SE2d>::uniform(std::move(states));
  return static_cast<std::size_t>(std::count(injected.begin(), injected.end(), 1));
}

}  // namespace rove
