#include "rove/bayes/log_weights.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "rove/bayes/random.h"
#include "rove/core/error.h"

namespace rove {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(LogWeights, EssIsNForEqualWeightsAndOneForASingleWeight) {
  const std::vector<double> equal(37, -3.7);
  EXPECT_NEAR(effective_sample_size(equal), 37.0, 1e-12);
  std::vector<double> one(10, -kInf);
  one[4] = -1000.0;
  const auto s = summarize_log_weights(one);
  EXPECT_DOUBLE_EQ(s.effective_sample_size, 1.0);
  EXPECT_DOUBLE_EQ(s.normalized_ess, 0.1);
  EXPECT_EQ(s.max_index, 4u);
  EXPECT_DOUBLE_EQ(s.log_sum, -1000.0);
}

TEST(LogWeights, EssMatchesTheLinearFormulaAndIgnoresShifts) {
  Rng rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const std::size_t n = 1 + rng.uniform_index(200);
    std::vector<double> lw(n);
    for (auto& v : lw) v = rng.normal(0.0, 2.0);
    double s1 = 0, s2 = 0;
    for (double v : lw) s1 += std::exp(v), s2 += std::exp(2 * v);
    const double ess = effective_sample_size(lw);
    EXPECT_NEAR(ess, s1 * s1 / s2, 1e-9 * ess);
    EXPECT_GE(ess, 1.0 - 1e-12);
    EXPECT_LE(ess, n + 1e-9);
    // Shifting every log-weight (even far out of exp's range) changes nothing.
    std::vector<double> shifted = lw;
    for (auto& v : shifted) v -= 1e5;
    EXPECT_NEAR(effective_sample_size(shifted), ess, 1e-9 * ess);
    const auto s = summarize_log_weights(shifted);
    EXPECT_NEAR(s.log_sum, std::log(s1) - 1e5, 1e-9 * 1e5);
  }
}

TEST(LogWeights, MovingWeightTowardOneParticleLowersEss) {
  std::vector<double> lw(20, 0.0);
  double last = effective_sample_size(lw);
  for (int k = 1; k <= 10; ++k) {
    lw[0] = 0.5 * k;
    const double ess = effective_sample_size(lw);
    EXPECT_LT(ess, last);
    last = ess;
  }
}

TEST(LogWeights, RejectsInvalidInput) {
  EXPECT_THROW(effective_sample_size(std::vector<double>{}), InvalidArgument);
  EXPECT_THROW(effective_sample_size(std::vector<double>{0.0, std::nan("")}), InvalidArgument);
  EXPECT_THROW(effective_sample_size(std::vector<double>{0.0, kInf}), InvalidArgument);
  EXPECT_THROW(effective_sample_size(std::vector<double>{-kInf, -kInf}), InvalidArgument);
}

}  // namespace
}  // namespace rove
