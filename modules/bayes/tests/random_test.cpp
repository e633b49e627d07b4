#include "rove/bayes/random.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "rove/bayes/distributions.h"

namespace rove {
namespace {

TEST(Rng, SameSeedSameSequenceDifferentSeedsDiffer) {
  Rng a(42), b(42), c(43);
  for (int i = 0; i < 100; ++i) {
    const auto x = a();
    EXPECT_EQ(x, b());
    EXPECT_NE(x, c());
  }
}

TEST(Rng, StreamsAreReproducibleAndDistinct) {
  EXPECT_EQ(Rng::stream(7, 3), Rng::stream(7, 3));
  EXPECT_NE(Rng::stream(7, 3), Rng::stream(7, 4));
  EXPECT_NE(Rng::stream(7, 3), Rng::stream(8, 3));
  // Neighbouring streams are uncorrelated: the correlation of their first
  // uniforms over 20000 stream pairs is within 5 standard errors of 0.
  const int n = 20000;
  double sxy = 0, sx = 0, sy = 0, sxx = 0, syy = 0;
  for (int i = 0; i < n; ++i) {
    const double x = Rng::stream(1, i).uniform(), y = Rng::stream(1, i + 1).uniform();
    sx += x, sy += y, sxy += x * y, sxx += x * x, syy += y * y;
  }
  const double cov = sxy / n - sx / n * sy / n;
  const double corr = cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
  EXPECT_LT(std::abs(corr), 5.0 / std::sqrt(n));
}

TEST(Rng, WorksWithStandardAlgorithms) {
  std::vector<int> v(10);
  std::iota(v.begin(), v.end(), 0);
  Rng rng(1);
  std::shuffle(v.begin(), v.end(), rng);
  std::vector<int> sorted = v;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < 10; ++i) EXPECT_EQ(sorted[i], i);
}

// Pearson's statistic of `counts` against equal expected counts.
double chi_square_uniform(const std::vector<int>& counts, int total) {
  const double e = static_cast<double>(total) / counts.size();
  double x2 = 0;
  for (int c : counts) x2 += (c - e) * (c - e) / e;
  return x2;
}

TEST(Rng, UniformAndIndexFitTheirDistributions) {
  // Chi-square goodness of fit at significance 0.001 (fixed seed).
  Rng rng(5);
  const int n = 200000;
  std::vector<int> bins(50, 0), idx(7, 0);
  for (int i = 0; i < n; ++i) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ++bins[static_cast<int>(u * 50)];
    ++idx[rng.uniform_index(7)];
  }
  EXPECT_LT(chi_square_uniform(bins, n), chi_square_quantile(0.999, 49));
  EXPECT_LT(chi_square_uniform(idx, n), chi_square_quantile(0.999, 6));
}

TEST(Rng, NormalFitsTheStandardNormal) {
  // 40 equiprobable bins by normal_quantile; chi-square at significance 0.001.
  Rng rng(9);
  const int n = 200000, k = 40;
  std::vector<double> edges;
  for (int i = 1; i < k; ++i) edges.push_back(normal_quantile(static_cast<double>(i) / k));
  std::vector<int> bins(k, 0);
  double sum = 0, sum_sq = 0;
  for (int i = 0; i < n; ++i) {
    const double z = rng.normal();
    sum += z, sum_sq += z * z;
    ++bins[std::upper_bound(edges.begin(), edges.end(), z) - edges.begin()];
  }
  EXPECT_LT(chi_square_uniform(bins, n), chi_square_quantile(0.999, k - 1));
  EXPECT_NEAR(sum / n, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sum_sq / n, 1.0, 5.0 * std::sqrt(2.0 / n));
  Rng r2(9);
  EXPECT_NEAR(r2.normal(3.0, 0.0), 3.0, 0.0);
}

// Both outputs of a pair are standard normal (chi-square over the same 40
// bins), uncorrelated, and the first is what normal() gives from the same
// state.
TEST(Rng, NormalPairsAreIndependentStandardNormals) {
  Rng a(21), b(21);
  EXPECT_EQ(a.normal_pair()[0], b.normal());
  Rng rng(10);
  const int n = 200000, k = 40;
  std::vector<double> edges;
  for (int i = 1; i < k; ++i) edges.push_back(normal_quantile(static_cast<double>(i) / k));
  std::vector<int> first(k, 0), second(k, 0);
  double sum_xy = 0, sum_y = 0, sum_y2 = 0;
  for (int i = 0; i < n; ++i) {
    const auto [x, y] = rng.normal_pair();
    sum_xy += x * y, sum_y += y, sum_y2 += y * y;
    ++first[std::upper_bound(edges.begin(), edges.end(), x) - edges.begin()];
    ++second[std::upper_bound(edges.begin(), edges.end(), y) - edges.begin()];
  }
  EXPECT_LT(chi_square_uniform(first, n), chi_square_quantile(0.999, k - 1));
  EXPECT_LT(chi_square_uniform(second, n), chi_square_quantile(0.999, k - 1));
  EXPECT_NEAR(sum_y / n, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sum_y2 / n, 1.0, 5.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(sum_xy / n, 0.0, 5.0 / std::sqrt(n));  // correlation, both of unit variance
}

}  // namespace
}  // namespace rove
