#include "rove/bayes/particle_filter.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr ParticleFilterAlgorithm kAlgorithms[] = {
    ParticleFilterAlgorithm::StandardProposal, ParticleFilterAlgorithm::AuxiliaryPFStandard,
    ParticleFilterAlgorithm::OptimalProposal, ParticleFilterAlgorithm::AuxiliaryPFOptimal};

// x_t = x_{t−1} + u + N(0, q²), z = x_t + N(0, r²): the Kalman filter is the
// exact posterior. log_likelihood drops the constant −½ log(2π r²).
struct Linear1D {
  double u = 1.0, q = 0.5, z = 0.0, r = 0.7;
  double sample_motion(double x, Rng& rng) const { return x + u + q * rng.normal(); }
  double log_likelihood(double x) const {
    const double e = (z - x) / r;
    return -0.5 * e * e;
  }
  double predicted_mean(double x) const { return x + u; }
  KldBin kld_bin(double x) const { return {static_cast<std::int64_t>(std::llround(x / 0.05)), 0, 0}; }
};

struct Gaussian {
  double mean, var;
};

// One Kalman predict + update, and log p(z) + ½ log(2π r²) (the evidence in
// the units of Linear1D::log_likelihood).
Gaussian kalman(const Gaussian& g, const Linear1D& m, double* log_evidence) {
  const double mp = g.mean + m.u, pp = g.var + m.q * m.q;
  const double s = pp + m.r * m.r;
  *log_evidence = -0.5 * (m.z - mp) * (m.z - mp) / s - 0.5 * std::log(s / (m.r * m.r));
  const double k = pp / s;
  return {mp + k * (m.z - mp), (1 - k) * pp};
}

Gaussian moments(const ParticleSet<double>& p) {
  const auto w = weights_from_log_weights(p.log_weights);
  double mean = 0, var = 0;
  for (std::size_t i = 0; i < p.size(); ++i) mean += w[i] * p.states[i];
  for (std::size_t i = 0; i < p.size(); ++i) var += w[i] * (p.states[i] - mean) * (p.states[i] - mean);
  return {mean, var};
}

ParticleSet<double> gaussian_particles(const Gaussian& g, std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<double> x(n);
  for (auto& v : x) v = rng.normal(g.mean, std::sqrt(g.var));
  return ParticleSet<double>::uniform(std::move(x));
}

ParticleFilterOptions options_for(ParticleFilterAlgorithm a, double beta) {
  ParticleFilterOptions o;
  o.algorithm = a;
  o.resampling_method = ResamplingMethod::Systematic;
  o.beta = beta;
  o.max_search_samples = 50;
  return o;
}

// Every algorithm, with and without ancestor selection, tracks the exact
// posterior of a linear-Gaussian system over three steps: mean within 6
// standard errors, variance within 6 %, evidence within 0.03 (log).
TEST(ParticleFilter, EveryAlgorithmMatchesTheKalmanFilter) {
  const std::size_t n = 20000;
  const double zs[] = {2.6, 2.9, 5.2};  // the last one 2σ off the prediction
  ThreadTeam team(2);
  for (const auto algorithm : kAlgorithms) {
    for (const double beta : {0.0, 1.0}) {
      const auto options = options_for(algorithm, beta);
      Gaussian exact{0.0, 1.0};
      auto particles = gaussian_particles(exact, n, 1);
      for (int t = 0; t < 3; ++t) {
        Linear1D model;
        model.z = zs[t];
        double log_evidence = 0;
        exact = kalman(exact, model, &log_evidence);
        const auto r = particle_filter_step(particles, model, options, KldOptions{},
                                            {derive_seed(7, t), true, true}, team);
        ASSERT_EQ(r.termination, ParticleFilterTermination::Updated) << r.message;
        const Gaussian est = moments(particles);
        const double ess = effective_sample_size(particles.log_weights);
        const std::string what = std::string(mrpt_name(algorithm)) + " beta " +
                                 std::to_string(beta) + " step " + std::to_string(t);
        EXPECT_NEAR(est.mean, exact.mean, 6 * std::sqrt(exact.var / ess)) << what;
        EXPECT_NEAR(est.var, exact.var, 0.06 * exact.var) << what;
        EXPECT_NEAR(r.log_evidence, log_evidence, 0.03) << what << " ess " << ess << " discarded " << r.discarded_ancestors;
      }
    }
  }
}

TEST(ParticleFilter, StandardProposalResamplesOnlyBelowBeta) {
  ThreadTeam team(1);
  Linear1D model;
  model.z = 1.0;  // close to the prediction: ESS/N stays high
  for (const double beta : {0.0, 0.3, 1.0}) {
    auto p = gaussian_particles({0.0, 1.0}, 2000, 3);
    const auto r = particle_filter_step(p, model, options_for(ParticleFilterAlgorithm::StandardProposal, beta),
                                        KldOptions{}, {1, true, true}, team);
    EXPECT_EQ(r.resampled, r.ess_before_resampling < beta) << beta;
    if (r.resampled) {
      EXPECT_NEAR(effective_sample_size(p.log_weights), 2000.0, 1e-6);
    }
  }
}

TEST(ParticleFilter, ResultDependsOnTheSeedNotOnTheThreadCount) {
  Linear1D model;
  model.z = 3.0;
  for (const auto algorithm : kAlgorithms) {
    for (const bool adaptive : {false, true}) {
      auto options = options_for(algorithm, 0.5);
      if (adaptive) {
        options.adaptive_sample_size = true;
        options.resampling_method = ResamplingMethod::Multinomial;
      }
      KldOptions kld;
      kld.min_sample_size = 300;
      std::vector<ParticleSet<double>> results;
      for (const int threads : {1, 2, 5}) {
        ThreadTeam team(threads);
        auto p = gaussian_particles({0.0, 1.0}, 3000, 4);
        for (int t = 0; t < 2; ++t)
          (void)particle_filter_step(p, model, options, kld, {derive_seed(11, t), true, true}, team);
        results.push_back(std::move(p));
      }
      for (std::size_t k = 1; k < results.size(); ++k) {
        EXPECT_EQ(results[k].states, results[0].states) << mrpt_name(algorithm) << adaptive;
        EXPECT_EQ(results[k].log_weights, results[0].log_weights) << mrpt_name(algorithm);
      }
      ThreadTeam team(2);
      auto other = gaussian_particles({0.0, 1.0}, 3000, 4);
      (void)particle_filter_step(other, model, options, kld, {derive_seed(12, 0), true, true}, team);
      EXPECT_NE(other.states, results[0].states) << "another seed gives other draws";
    }
  }
}

// The adaptive count is exactly the sequential KLD rule: every prefix of c
// particles (in the order made) still wanted more, and the full set is
// enough (or hit the maximum).
TEST(ParticleFilter, AdaptiveSampleSizeFollowsTheKldRule) {
  Linear1D model;
  KldOptions kld;
  kld.min_sample_size = 100;
  kld.max_sample_size = 100000;
  kld.epsilon = 0.05;
  ThreadTeam team(3);
  for (const auto algorithm : kAlgorithms) {
    auto options = options_for(algorithm, 0.5);
    options.adaptive_sample_size = true;
    options.resampling_method = ResamplingMethod::Multinomial;
    for (const double spread : {0.01, 1.0, 4.0}) {
      auto p = gaussian_particles({0.0, spread * spread}, 500, 5);
      model.z = 1.0;
      const auto r = particle_filter_step(p, model, options, kld, {9, true, true}, team);
      ASSERT_EQ(r.particles_after, p.size());
      KldBinSet bins;
      for (std::size_t c = 0; c < p.size(); ++c) {
        ASSERT_LT(c, kld_target_count(bins.size(), 0, kld)) << "stopped late at " << c;
        bins.insert(model.kld_bin(p.states[c]));
      }
      EXPECT_EQ(bins.size(), r.kld_bins);
      EXPECT_GE(p.size(), kld_target_count(bins.size(), 0, kld));
      EXPECT_GT(p.size(), 100u);
    }
  }
}

TEST(ParticleFilter, ZeroLikelihoodEverywhereKeepsThePriorWeights) {
  struct Blind : Linear1D {
    double log_likelihood(double) const { return -kInf; }
  };
  ThreadTeam team(2);
  for (const auto algorithm : kAlgorithms) {
    auto p = gaussian_particles({0.0, 1.0}, 500, 6);
    for (std::size_t i = 0; i < p.size(); ++i) p.log_weights[i] = 0.001 * static_cast<double>(i);
    auto expected_w = p.log_weights;
    normalize_log_weights(expected_w);
    const auto r = particle_filter_step(p, Blind{}, options_for(algorithm, 0.0), KldOptions{},
                                        {1, true, true}, team);
    EXPECT_EQ(r.termination, ParticleFilterTermination::Degenerate) << mrpt_name(algorithm);
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.log_evidence, -kInf);
    for (std::size_t i = 0; i < p.size(); ++i) EXPECT_NEAR(p.log_weights[i], expected_w[i], 1e-12);
  }
}

TEST(ParticleFilter, PredictionOnlyMovesAndKeepsWeights) {
  ThreadTeam team(1);
  Linear1D model;
  auto p = gaussian_particles({0.0, 1.0}, 1000, 7);
  const auto before = p.states;
  const auto r = particle_filter_step(p, model, options_for(ParticleFilterAlgorithm::AuxiliaryPFOptimal, 0.5),
                                      KldOptions{}, {1, true, false}, team);
  EXPECT_EQ(r.termination, ParticleFilterTermination::Predicted);
  EXPECT_TRUE(r.ok());
  EXPECT_NEAR(moments(p).mean, 1.0, 0.1);
  EXPECT_NEAR(effective_sample_size(p.log_weights), 1000.0, 1e-6);
  const auto r2 = particle_filter_step(p, model, options_for(ParticleFilterAlgorithm::StandardProposal, 0.5),
                                       KldOptions{}, {2, false, false}, team);
  EXPECT_EQ(r2.termination, ParticleFilterTermination::Predicted);
  (void)before;
}

TEST(ParticleFilter, RejectsBadModelsAndInputs) {
  ThreadTeam team(2);
  struct Broken : Linear1D {
    double log_likelihood(double x) const { return x > 0.5 ? std::nan("") : 0.0; }
  };
  auto p = gaussian_particles({0.0, 1.0}, 300, 8);
  EXPECT_THROW(particle_filter_step(p, Broken{}, options_for(ParticleFilterAlgorithm::StandardProposal, 0.5),
                                    KldOptions{}, {1, true, true}, team),
               InvalidArgument);
  struct NoMean {
    double sample_motion(double x, Rng& rng) const { return x + rng.normal(); }
    double log_likelihood(double x) const { return -x * x; }
  };
  auto aux = options_for(ParticleFilterAlgorithm::AuxiliaryPFStandard, 0.5);
  EXPECT_THROW(particle_filter_step(p, NoMean{}, aux, KldOptions{}, {1, true, true}, team),
               InvalidArgument);
  aux.first_stage_weights_monte_carlo = true;
  EXPECT_NO_THROW(particle_filter_step(p, NoMean{}, aux, KldOptions{}, {1, true, true}, team));
  auto adaptive = options_for(ParticleFilterAlgorithm::StandardProposal, 0.5);
  adaptive.adaptive_sample_size = true;
  adaptive.resampling_method = ResamplingMethod::Multinomial;
  EXPECT_THROW(particle_filter_step(p, NoMean{}, adaptive, KldOptions{}, {1, true, true}, team),
               InvalidArgument);  // no KLD bin for double without kld_bin()
  ParticleSet<double> empty;
  EXPECT_THROW(particle_filter_step(empty, Linear1D{}, ParticleFilterOptions{}, KldOptions{},
                                    {1, true, true}, team),
               InvalidArgument);
  auto mismatched = p;
  mismatched.log_weights.pop_back();
  EXPECT_THROW(particle_filter_step(mismatched, Linear1D{}, ParticleFilterOptions{}, KldOptions{},
                                    {1, true, true}, team),
               InvalidArgument);
}

// SE2d particles use MRPT's (x, y, phi) KLD bins without any model support:
// a robot at the origin seeing a range to a landmark at (5, 0).
struct RangeModel {
  double range = 5.0, sigma = 0.1;
  SE2d sample_motion(const SE2d& x, Rng& rng) const {
    return x * SE2d::exp({0.1 + 0.02 * rng.normal(), 0.02 * rng.normal(), 0.01 * rng.normal()});
  }
  double log_likelihood(const SE2d& x) const {
    const double d = (x.translation() - Eigen::Vector2d(5.0, 0.0)).norm() - range;
    return -0.5 * d * d / (sigma * sigma);
  }
};

TEST(ParticleFilter, Se2ParticlesWithKld) {
  ParticleFilterOptions options;
  options.adaptive_sample_size = true;
  KldOptions kld;
  kld.min_sample_size = 200;
  kld.max_sample_size = 5000;
  Rng rng(3);
  std::vector<SE2d> init;
  for (int i = 0; i < 1000; ++i)
    init.push_back(SE2d::exp({rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-3, 3)}));
  auto p = ParticleSet<SE2d>::uniform(init);
  ThreadTeam team(2);
  RangeModel model;
  model.range = 4.9;
  const auto r = particle_filter_step(p, model, options, kld, {5, true, true}, team);
  EXPECT_TRUE(r.ok());
  EXPECT_GE(p.size(), 200u);
  EXPECT_LE(p.size(), 5000u);
  EXPECT_GT(r.kld_bins, 10u);
}

}  // namespace
}  // namespace rove
