#include "rove/bayes/resampling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "rove/bayes/distributions.h"
#include "rove/bayes/log_weights.h"
#include "rove/core/error.h"

namespace rove {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr ResamplingMethod kAll[] = {ResamplingMethod::Multinomial, ResamplingMethod::Residual,
                                     ResamplingMethod::Stratified, ResamplingMethod::Systematic};

// Ten uneven weights, one of them zero.
std::vector<double> test_weights() {
  const std::vector<double> w = {0.30, 0.005, 0.12, 0.0, 0.07, 0.2133, 0.0417, 0.15, 0.05, 0.05};
  std::vector<double> lw;
  for (double v : w) lw.push_back(v > 0 ? std::log(v) - 7.0 : -kInf);  // unnormalized
  return lw;
}

struct CountStats {
  std::vector<double> total;     // copies summed over the runs
  std::vector<double> variance;  // sample variance of the copies per run
};

CountStats run(ResamplingMethod m, const std::vector<double>& lw, std::size_t n_out, int runs,
               std::uint64_t seed) {
  const std::size_t n = lw.size();
  CountStats s{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
  std::vector<double> sq(n, 0.0);
  Rng rng(seed);
  for (int r = 0; r < runs; ++r) {
    const auto c = resampling_counts(m, lw, n_out, rng);
    std::size_t sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      s.total[i] += c[i];
      sq[i] += static_cast<double>(c[i]) * c[i];
      sum += c[i];
    }
    EXPECT_EQ(sum, n_out);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double mean = s.total[i] / runs;
    s.variance[i] = (sq[i] - runs * mean * mean) / (runs - 1);
  }
  return s;
}

// Pearson's statistic of the summed copy counts against runs·n_out·w̄ᵢ, over
// the particles of positive weight. For multinomial resampling the totals
// are multinomial (runs·n_out draws), so the statistic is χ² with
// (positive weights − 1) degrees of freedom; the other schemes have lower
// variance, which only makes the statistic smaller: the test's false
// rejection rate is at most its significance for all four.
double pearson(const CountStats& s, const std::vector<double>& lw, double draws) {
  const auto w = weights_from_log_weights(lw);
  double x2 = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0) continue;
    const double e = draws * w[i];
    x2 += (s.total[i] - e) * (s.total[i] - e) / e;
  }
  return x2;
}

TEST(Resampling, ExpectedCopiesAreNTimesTheWeight) {
  // Significance 0.001 with a fixed seed: 9 positive weights, 8 degrees of freedom.
  const auto lw = test_weights();
  const double limit = chi_square_quantile(0.999, 8);
  for (const auto m : kAll) {
    for (const std::size_t n_out : {std::size_t{10}, std::size_t{37}}) {
      const int runs = 4000;
      const auto s = run(m, lw, n_out, runs, 11);
      EXPECT_EQ(s.total[3], 0.0) << mrpt_name(m) << ": a zero weight was chosen";
      EXPECT_LT(pearson(s, lw, static_cast<double>(runs) * n_out), limit)
          << mrpt_name(m) << " n_out " << n_out;
    }
  }
}

TEST(Resampling, TheCopyCountTestDetectsABiasedScheme) {
  // The same statistic against weights off by ±10 % on two particles is far
  // beyond the limit: the test above can fail.
  auto lw = test_weights();
  const auto s = run(ResamplingMethod::Systematic, lw, 10, 4000, 11);
  lw[0] += std::log(1.1);
  lw[2] += std::log(0.9);
  EXPECT_GT(pearson(s, lw, 40000.0), 4 * chi_square_quantile(0.999, 8));
}

TEST(Resampling, SystematicAndStratifiedVaryLessThanMultinomial) {
  const auto lw = test_weights();
  const int runs = 4000;
  auto total_variance = [&](ResamplingMethod m) {
    const auto s = run(m, lw, 10, runs, 5);
    double v = 0;
    for (double x : s.variance) v += x;
    return v;
  };
  const double multinomial = total_variance(ResamplingMethod::Multinomial);
  // Multinomial: Σ n w̄ᵢ (1 − w̄ᵢ) = 10 (1 − Σ w̄ᵢ²) ≈ 8.09.
  const auto w = weights_from_log_weights(lw);
  double expected = 0;
  for (double x : w) expected += 10 * x * (1 - x);
  EXPECT_NEAR(multinomial, expected, 0.05 * expected);
  EXPECT_LT(total_variance(ResamplingMethod::Stratified), 0.5 * multinomial);
  EXPECT_LT(total_variance(ResamplingMethod::Systematic), 0.5 * multinomial);
  EXPECT_LT(total_variance(ResamplingMethod::Residual), multinomial);
}

TEST(Resampling, SystematicGivesFloorOrCeilOfNW) {
  const auto lw = test_weights();
  const auto w = weights_from_log_weights(lw);
  Rng rng(8);
  for (const std::size_t n_out : {std::size_t{10}, std::size_t{1000}, std::size_t{7}}) {
    for (int r = 0; r < 500; ++r) {
      const auto c = resampling_counts(ResamplingMethod::Systematic, lw, n_out, rng);
      for (std::size_t i = 0; i < w.size(); ++i) {
        const double nw = n_out * w[i];
        EXPECT_GE(c[i], std::floor(nw - 1e-9));
        EXPECT_LE(c[i], std::ceil(nw + 1e-9));
      }
    }
  }
}

TEST(Resampling, ResidualKeepsItsDeterministicPartExactly) {
  const auto lw = test_weights();
  const auto w = weights_from_log_weights(lw);
  Rng rng(2);
  for (const std::size_t n_out : {std::size_t{10}, std::size_t{100}, std::size_t{33}}) {
    std::size_t fixed = 0;
    for (double x : w) fixed += static_cast<std::size_t>(std::floor(n_out * x));
    for (int r = 0; r < 500; ++r) {
      const auto c = resampling_counts(ResamplingMethod::Residual, lw, n_out, rng);
      std::size_t extra = 0;
      for (std::size_t i = 0; i < w.size(); ++i) {
        const auto floor_i = static_cast<std::uint32_t>(std::floor(n_out * w[i]));
        ASSERT_GE(c[i], floor_i);
        extra += c[i] - floor_i;
      }
      EXPECT_EQ(extra, n_out - fixed);
    }
  }
}

TEST(Resampling, IndicesAreAscendingAndMatchTheCounts) {
  const auto lw = test_weights();
  for (const auto m : kAll) {
    Rng a(4), b(4);
    const auto counts = resampling_counts(m, lw, 25, a);
    const auto idx = resample_indices(m, lw, 25, b);
    ASSERT_EQ(idx.size(), 25u);
    EXPECT_TRUE(std::is_sorted(idx.begin(), idx.end()));
    EXPECT_EQ(idx, indices_from_counts(counts));
  }
}

TEST(Resampling, EdgeCases) {
  Rng rng(1);
  // One particle: every output is it.
  for (const auto m : kAll) EXPECT_EQ(resample_indices(m, std::vector<double>{-5.0}, 4, rng),
                                      (std::vector<std::size_t>{0, 0, 0, 0}));
  // All the weight on the last particle, extreme magnitudes.
  const std::vector<double> last = {-kInf, -1e300, -kInf, 1e300};
  for (const auto m : kAll)
    EXPECT_EQ(resample_indices(m, last, 3, rng), (std::vector<std::size_t>{3, 3, 3}));
  EXPECT_THROW(resample_indices(ResamplingMethod::Systematic, std::vector<double>{}, 3, rng),
               InvalidArgument);
  EXPECT_THROW(resample_indices(ResamplingMethod::Systematic, std::vector<double>{0.0}, 0, rng),
               InvalidArgument);
  EXPECT_THROW(resample_indices(ResamplingMethod::Multinomial, std::vector<double>{-kInf}, 2, rng),
               InvalidArgument);
  EXPECT_THROW(resample_indices(ResamplingMethod::Multinomial, std::vector<double>{std::nan("")},
                                2, rng),
               InvalidArgument);
  EXPECT_EQ(mrpt_name(ResamplingMethod::Stratified), "prStratified");
}

TEST(Resampling, DrawFromCumulativeSkipsZeroWeights) {
  const std::vector<double> lw = {-kInf, 0.0, -kInf, 0.0, -kInf};
  const auto c = cumulative_weights(lw);
  EXPECT_EQ(c.back(), 1.0);
  EXPECT_EQ(draw_from_cumulative(c, 0.0), 1u);
  EXPECT_EQ(draw_from_cumulative(c, 0.49), 1u);
  EXPECT_EQ(draw_from_cumulative(c, 0.5), 3u);
  EXPECT_EQ(draw_from_cumulative(c, std::nextafter(1.0, 0.0)), 3u);
}

// The guide table gives the binary search's index for every u: random u,
// the slice starts j/N, the cumulative sums themselves and their
// neighbours, over weights with zeros, a dominant particle and near-ties.
TEST(Resampling, CumulativeSamplerEqualsTheBinarySearch) {
  Rng rng(11);
  std::vector<std::vector<double>> cases = {
      {0.0},
      {-kInf, 0.0, -kInf, 0.0, -kInf},
      {0.0, -800.0, -800.0, -800.0, 0.0},
      {-kInf, -kInf, -kInf, 5.0},
  };
  std::vector<double> uneven(997);
  for (double& w : uneven) w = 8.0 * rng.uniform() - (rng.uniform() < 0.3 ? kInf : 0.0);
  uneven[500] = 0.0;
  cases.push_back(uneven);
  std::vector<double> peaked(1000, -30.0);
  peaked[999] = 0.0;
  cases.push_back(peaked);
  for (const auto& lw : cases) {
    const CumulativeSampler sampler(lw);
    const std::vector<double>& c = sampler.cumulative();
    EXPECT_EQ(c, cumulative_weights(lw));
    std::vector<double> us = {0.0, std::nextafter(1.0, 0.0)};
    for (std::size_t j = 0; j < c.size(); ++j) {
      const double start = static_cast<double>(j) / static_cast<double>(c.size());
      us.insert(us.end(), {start, std::nextafter(start, 0.0), std::nextafter(start, 1.0)});
      if (c[j] < 1.0) us.insert(us.end(), {c[j], std::nextafter(c[j], 0.0), std::nextafter(c[j], 1.0)});
    }
    for (int k = 0; k < 20000; ++k) us.push_back(rng.uniform());
    for (const double u : us) {
      if (!(u >= 0.0 && u < 1.0)) continue;
      ASSERT_EQ(sampler.draw(u), draw_from_cumulative(c, u)) << "u " << u << ", " << lw.size();
    }
  }
  const CumulativeSampler one(std::vector<double>{0.0});
  EXPECT_THROW(one.draw(1.0), InvalidArgument);
  EXPECT_THROW(one.draw(-0.1), InvalidArgument);
  EXPECT_THROW(CumulativeSampler(std::vector<double>{}), InvalidArgument);
}

}  // namespace
}  // namespace rove
