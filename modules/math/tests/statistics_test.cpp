#include "rove/math/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "rove/core/error.h"

namespace rove {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
const double kNan = std::numeric_limits<double>::quiet_NaN();

double naive_log_sum_exp(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += std::exp(v);
  return std::log(s);
}

std::vector<double> random_values(std::size_t n, double lo, double hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> v(n);
  for (double& x : v) x = u(rng);
  return v;
}

TEST(LogSumExp, AgreesWithNaiveEvaluationOnModerateInputs) {
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const auto x = random_values(1 + seed * 7, -30.0, 30.0, seed);
    EXPECT_NEAR(log_sum_exp(x), naive_log_sum_exp(x),
                1e-12 * std::abs(naive_log_sum_exp(x)) + 1e-13);
  }
}

TEST(LogSumExp, FiniteForHugeMagnitudes) {
  // exp(±1e4) over/underflows; the shifted sum does not.
  EXPECT_DOUBLE_EQ(log_sum_exp(std::vector<double>{1e4, 1e4}), 1e4 + std::log(2.0));
  EXPECT_DOUBLE_EQ(log_sum_exp(std::vector<double>{-1e4, -1e4, -1e4}), -1e4 + std::log(3.0));
  EXPECT_DOUBLE_EQ(log_sum_exp(std::vector<double>{1e4, -1e4}), 1e4);
  // Shift invariance: lse(x + c) = lse(x) + c.
  const auto x = random_values(50, -5.0, 5.0, 3);
  std::vector<double> shifted = x;
  for (double& v : shifted) v += 1e4;
  EXPECT_NEAR(log_sum_exp(shifted), log_sum_exp(x) + 1e4, 1e-9);
  for (double& v : shifted) v -= 2e4;
  EXPECT_NEAR(log_sum_exp(shifted), log_sum_exp(x) - 1e4, 1e-9);
}

TEST(LogSumExp, MinusInfinityIsAZeroTerm) {
  EXPECT_DOUBLE_EQ(log_sum_exp(std::vector<double>{std::log(2.0), -kInf, std::log(3.0)}),
                   std::log(5.0));
  EXPECT_EQ(log_sum_exp(std::vector<double>{-kInf, -kInf}), -kInf);
}

TEST(LogSumExp, RejectsEmptyNanAndPlusInfinity) {
  EXPECT_THROW(log_sum_exp(std::vector<double>{}), InvalidArgument);
  try {
    log_sum_exp(std::vector<double>{0.0, 1.0, kNan});
    ADD_FAILURE() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("x[2]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(log_sum_exp(std::vector<double>{0.0, kInf}), InvalidArgument);
}

TEST(LogAddExp, MatchesLogSumExp) {
  for (double a : {-1e4, -30.0, -1.0, 0.0, 2.5, 700.0, 1e4}) {
    for (double b : {-kInf, -40.0, 0.0, 1.0, 800.0}) {
      const double expected = b == -kInf ? a : log_sum_exp(std::vector<double>{a, b});
      EXPECT_NEAR(log_add_exp(a, b), expected, 1e-12 * std::max(1.0, std::abs(expected)));
      EXPECT_EQ(log_add_exp(a, b), log_add_exp(b, a));
    }
  }
  EXPECT_EQ(log_add_exp(-kInf, -kInf), -kInf);
  EXPECT_THROW(log_add_exp(kNan, 0.0), InvalidArgument);
  EXPECT_THROW(log_add_exp(0.0, kInf), InvalidArgument);
}

TEST(AverageLogLikelihood, ClosedForms) {
  EXPECT_NEAR(average_log_likelihood(std::vector<double>{std::log(0.2), std::log(0.4)}),
              std::log(0.3), 1e-15);
  // A zero likelihood still counts in N.
  EXPECT_NEAR(average_log_likelihood(std::vector<double>{std::log(0.6), -kInf, -kInf}),
              std::log(0.2), 1e-15);
  EXPECT_EQ(average_log_likelihood(std::vector<double>{-kInf, -kInf}), -kInf);
  EXPECT_DOUBLE_EQ(average_log_likelihood(std::vector<double>{-1e4, -1e4}), -1e4);
  EXPECT_DOUBLE_EQ(average_log_likelihood(std::vector<double>{1e4}), 1e4);
  EXPECT_THROW(average_log_likelihood(std::vector<double>{}), InvalidArgument);
  EXPECT_THROW(average_log_likelihood(std::vector<double>{0.0, kNan}), InvalidArgument);
}

TEST(AverageLogLikelihood, AgreesWithNaiveAndIsShiftInvariant) {
  const auto l = random_values(40, -20.0, 5.0, 9);
  double naive = 0;
  for (double v : l) naive += std::exp(v);
  naive = std::log(naive / l.size());
  EXPECT_NEAR(average_log_likelihood(l), naive, 1e-12);
  std::vector<double> far = l;
  for (double& v : far) v -= 1e4;
  const double a = average_log_likelihood(far);
  EXPECT_TRUE(std::isfinite(a));
  EXPECT_NEAR(a, naive - 1e4, 1e-9);
}

TEST(AverageLogLikelihood, WeightedByLogWeightsAndByLinearWeights) {
  const auto lw = random_values(30, -4.0, 2.0, 1);
  const auto ll = random_values(30, -10.0, 3.0, 2);
  double num = 0, den = 0;
  std::vector<double> w(30);
  for (std::size_t i = 0; i < 30; ++i) {
    w[i] = std::exp(lw[i]);
    num += w[i] * std::exp(ll[i]);
    den += w[i];
  }
  const double naive = std::log(num / den);
  EXPECT_NEAR(average_log_likelihood_log_weights(lw, ll), naive, 1e-12);
  EXPECT_NEAR(average_log_likelihood_weights(w, ll), naive, 1e-12);

  // Log-weights and log-likelihoods of ±1e4: unnormalized weights are fine.
  std::vector<double> lw_far = lw, ll_far = ll;
  for (double& v : lw_far) v += 1e4;
  for (double& v : ll_far) v -= 1e4;
  EXPECT_NEAR(average_log_likelihood_log_weights(lw_far, ll_far), naive - 1e4, 1e-9);
  std::vector<double> w_scaled = w;
  for (double& v : w_scaled) v *= 1e-200;
  EXPECT_NEAR(average_log_likelihood_weights(w_scaled, ll_far), naive - 1e4, 1e-9);

  // Equal weights reduce to the unweighted average.
  const std::vector<double> zeros(30, 0.0), ones(30, 1.0);
  EXPECT_NEAR(average_log_likelihood_log_weights(zeros, ll), average_log_likelihood(ll), 1e-13);
  EXPECT_NEAR(average_log_likelihood_weights(ones, ll), average_log_likelihood(ll), 1e-13);
}

TEST(AverageLogLikelihood, WeightedEdgeCases) {
  // Zero weight hides a zero likelihood; closed form log((1·0.5 + 3·0.1)/4).
  const std::vector<double> ll = {std::log(0.5), std::log(0.1), -kInf};
  EXPECT_NEAR(average_log_likelihood_weights(std::vector<double>{1, 3, 0}, ll), std::log(0.2),
              1e-15);
  EXPECT_NEAR(
      average_log_likelihood_log_weights(std::vector<double>{0.0, std::log(3.0), -kInf}, ll),
      std::log(0.2), 1e-15);
  // All weighted likelihoods zero → −inf.
  EXPECT_EQ(average_log_likelihood_weights(std::vector<double>{0, 0, 1}, ll), -kInf);
  EXPECT_EQ(average_log_likelihood_log_weights(std::vector<double>{-kInf, -kInf, 0.0}, ll), -kInf);
  // Invalid weights.
  EXPECT_THROW(average_log_likelihood_weights(std::vector<double>{0, 0, 0}, ll), InvalidArgument);
  EXPECT_THROW(average_log_likelihood_weights(std::vector<double>{1, -1, 1}, ll), InvalidArgument);
  EXPECT_THROW(average_log_likelihood_weights(std::vector<double>{1, kNan, 1}, ll),
               InvalidArgument);
  EXPECT_THROW(average_log_likelihood_log_weights(std::vector<double>{-kInf, -kInf, -kInf}, ll),
               InvalidArgument);
  EXPECT_THROW(average_log_likelihood_log_weights(std::vector<double>{0, kNan, 0}, ll),
               InvalidArgument);
  EXPECT_THROW(average_log_likelihood_log_weights(std::vector<double>{0, 0}, ll), InvalidArgument);
  EXPECT_THROW(average_log_likelihood_weights(std::vector<double>{}, std::vector<double>{}),
               InvalidArgument);
}

TEST(NormalizeLogWeights, SumsToOneAndReturnsTheShift) {
  std::vector<double> lw = {1e4, 1e4 + std::log(3.0), -kInf};
  const double shift = normalize_log_weights(lw);
  EXPECT_NEAR(shift, 1e4 + std::log(4.0), 1e-9);
  EXPECT_NEAR(std::exp(lw[0]), 0.25, 1e-12);
  EXPECT_NEAR(std::exp(lw[1]), 0.75, 1e-12);
  EXPECT_EQ(lw[2], -kInf);
  EXPECT_NEAR(log_sum_exp(lw), 0.0, 1e-11);  // ulp(1e4) ≈ 1.8e-12

  const auto w = weights_from_log_weights(std::vector<double>{-1e4, -1e4 + std::log(3.0), -kInf});
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NEAR(w[0], 0.25, 1e-12);
  EXPECT_NEAR(w[1], 0.75, 1e-12);
  EXPECT_EQ(w[2], 0.0);

  const auto r = random_values(100, -50.0, 50.0, 4);
  const auto wr = weights_from_log_weights(r);
  EXPECT_NEAR(std::accumulate(wr.begin(), wr.end(), 0.0), 1.0, 1e-14);

  std::vector<double> dead = {-kInf, -kInf};
  EXPECT_THROW(normalize_log_weights(dead), InvalidArgument);
  std::vector<double> empty;
  EXPECT_THROW(normalize_log_weights(empty), InvalidArgument);
  std::vector<double> bad = {0.0, kNan};
  EXPECT_THROW(normalize_log_weights(bad), InvalidArgument);
}

TEST(WeightedMeanCovariance, ClosedForm) {
  // Samples (0,0), (2,0), (0,4) with weights 1, 1, 2: μ = (0.5, 2);
  // ML covariance Σ w (x−μ)(x−μ)ᵀ / 4.
  Eigen::MatrixXd x(2, 3);
  x << 0, 2, 0, 0, 0, 4;
  const std::vector<double> w = {1, 1, 2};
  const MeanCovariance mc = weighted_mean_covariance(x, w);
  EXPECT_NEAR((mc.mean - Eigen::Vector2d(0.5, 2.0)).norm(), 0.0, 1e-15);
  Eigen::Matrix2d expected;
  // Deviations: (−0.5,−2), (1.5,−2), (−0.5, 2) weighted 1,1,2.
  expected << (0.25 + 2.25 + 2 * 0.25) / 4, (1.0 - 3.0 - 2.0) / 4, (1.0 - 3.0 - 2.0) / 4,
      (4.0 + 4.0 + 8.0) / 4;
  EXPECT_NEAR((mc.covariance - expected).norm(), 0.0, 1e-14);

  // Unbiased with reliability weights: V1 = 4, V2 = 6 → divisor 4 − 1.5.
  const MeanCovariance ub = weighted_mean_covariance(x, w, CovarianceNormalization::Unbiased);
  EXPECT_NEAR((ub.covariance - expected * 4.0 / 2.5).norm(), 0.0, 1e-14);
}

TEST(WeightedMeanCovariance, IntegerWeightsEqualReplicationAndScaleInvariance) {
  std::mt19937_64 rng(6);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd x(3, 10);
  for (int j = 0; j < 10; ++j) x.col(j) = Eigen::Vector3d(g(rng), 2 * g(rng), g(rng) + 1);
  std::vector<double> w(10);
  std::vector<Eigen::Vector3d> replicated;
  for (int j = 0; j < 10; ++j) {
    w[j] = 1 + j % 3;
    for (int k = 0; k < w[j]; ++k) replicated.push_back(x.col(j));
  }
  Eigen::MatrixXd xr(3, replicated.size());
  for (std::size_t j = 0; j < replicated.size(); ++j) xr.col(j) = replicated[j];
  const auto a = weighted_mean_covariance(x, w);
  const auto b = mean_covariance(xr);
  EXPECT_LT((a.mean - b.mean).norm(), 1e-14);
  EXPECT_LT((a.covariance - b.covariance).norm(), 1e-14);
  std::vector<double> w_scaled = w;
  for (double& v : w_scaled) v *= 1e-3;
  const auto c = weighted_mean_covariance(x, w_scaled);
  EXPECT_LT((a.covariance - c.covariance).norm(), 1e-13);
  // Unit-weight unbiased covariance is the usual N − 1 sample covariance.
  const auto u = mean_covariance(x, CovarianceNormalization::Unbiased);
  const Eigen::MatrixXd centered = x.colwise() - x.rowwise().mean();
  EXPECT_LT((u.covariance - centered * centered.transpose() / 9.0).norm(), 1e-14);
  EXPECT_EQ(u.covariance, u.covariance.transpose());
}

TEST(WeightedMeanCovariance, AccurateFarFromTheOrigin) {
  // Variance 1 around 1e8: a one-pass Σx² − Nμ² formula would lose it all.
  Eigen::MatrixXd x(1, 4);
  x << 1e8 - 1.5, 1e8 - 0.5, 1e8 + 0.5, 1e8 + 1.5;
  const auto mc = mean_covariance(x);
  EXPECT_DOUBLE_EQ(mc.mean[0], 1e8);
  EXPECT_NEAR(mc.covariance(0, 0), 1.25, 1e-9);
}

TEST(WeightedMeanCovariance, RejectsInvalidInput) {
  Eigen::MatrixXd x(2, 3);
  x << 0, 1, 2, 3, 4, 5;
  EXPECT_THROW(weighted_mean_covariance(x, std::vector<double>{1, 1}), InvalidArgument);
  EXPECT_THROW(weighted_mean_covariance(x, std::vector<double>{0, 0, 0}), InvalidArgument);
  EXPECT_THROW(weighted_mean_covariance(x, std::vector<double>{1, -1, 1}), InvalidArgument);
  EXPECT_THROW(weighted_mean_covariance(Eigen::MatrixXd(2, 0), std::vector<double>{}),
               InvalidArgument);
  EXPECT_THROW(
      weighted_mean_covariance(x, std::vector<double>{0, 5, 0}, CovarianceNormalization::Unbiased),
      InvalidArgument);
  x(1, 2) = kNan;
  try {
    mean_covariance(x);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("sample 2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rove
