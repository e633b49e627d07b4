#include "rove/math/ransac.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <set>
#include <vector>

#include <Eigen/Core>

#include "rove/core/error.h"
#include "rove/math/line_detection.h"
#include "rove/math/plane_detection.h"

namespace rove {
namespace {

// 1D "model": a value; data are numbers, inliers lie close to the value.
// fit() can be told to also emit a wrong model, to check that RANSAC keeps
// the best of several models from one sample; it records every sample.
struct ValueProblem {
  using Model = double;
  using Datum = double;
  std::size_t k = 1;
  bool emit_decoy = false;
  std::vector<std::vector<double>>* samples = nullptr;

  std::size_t sample_size() const { return k; }
  void fit(std::span<const double> sample, std::vector<double>& models) const {
    if (samples) samples->emplace_back(sample.begin(), sample.end());
    if (emit_decoy) models.push_back(1e6);
    double mean = 0.0;
    for (double v : sample) mean += v;
    models.push_back(mean / static_cast<double>(sample.size()));
  }
  double distance(double model, double datum) const { return std::abs(model - datum); }
};

// A problem whose fit never produces a model.
struct NeverFits {
  using Model = double;
  using Datum = double;
  std::size_t sample_size() const { return 2; }
  void fit(std::span<const double>, std::vector<double>&) const {}
  double distance(double m, double d) const { return std::abs(m - d); }
};

TEST(RansacIterations, MatchesHartleyZissermanTable43) {
  // Table 4.3 of Hartley & Zisserman (p = 0.99): rows s = 2..8, columns
  // outlier proportion 5%, 10%, 20%, 25%, 30%, 40%, 50%.
  const double eps[] = {0.05, 0.10, 0.20, 0.25, 0.30, 0.40, 0.50};
  const std::size_t table[7][7] = {
      {2, 3, 5, 6, 7, 11, 17},      {3, 4, 7, 9, 11, 19, 35},
      {3, 5, 9, 13, 17, 34, 72},    {4, 6, 12, 17, 26, 57, 146},
      {4, 7, 16, 24, 37, 97, 293},  {4, 8, 20, 33, 54, 163, 588},
      {5, 9, 26, 44, 78, 272, 1177}};
  for (std::size_t s = 2; s <= 8; ++s) {
    for (int j = 0; j < 7; ++j) {
      EXPECT_EQ(ransac_required_iterations(1.0 - eps[j], s, 0.99), table[s - 2][j])
          << "s = " << s << ", outliers " << eps[j];
    }
  }
}

TEST(RansacIterations, ClosedFormAndLimits) {
  // w = 0.5, s = 3, p = 0.95: log(0.05)/log(0.875) = 22.43 → 23.
  EXPECT_EQ(ransac_required_iterations(0.5, 3, 0.95), 23u);
  EXPECT_EQ(ransac_required_iterations(1.0, 4, 0.99), 0u);
  EXPECT_EQ(ransac_required_iterations(0.0, 4, 0.99), SIZE_MAX);
  EXPECT_EQ(ransac_required_iterations(1e-6, 4, 0.99), SIZE_MAX);  // w^s below precision
  // Tiny w^s still representable: N ≈ −log(1−p)/w^s.
  const double w = 0.01;
  const std::size_t n = ransac_required_iterations(w, 3, 0.99);
  EXPECT_NEAR(static_cast<double>(n), -std::log(0.01) / 1e-6, 5.0);
  EXPECT_THROW(ransac_required_iterations(1.5, 3, 0.99), InvalidArgument);
  EXPECT_THROW(ransac_required_iterations(0.5, 0, 0.99), InvalidArgument);
  EXPECT_THROW(ransac_required_iterations(0.5, 3, 1.0), InvalidArgument);
  EXPECT_THROW(ransac_required_iterations(0.5, 3, 0.0), InvalidArgument);
}

std::vector<double> values_with_outliers(std::size_t inliers, std::size_t outliers,
                                         std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::uniform_real_distribution<double> far(10.0, 100.0);
  std::vector<double> v;
  for (std::size_t i = 0; i < inliers; ++i) v.push_back(3.0 + noise(rng));
  for (std::size_t i = 0; i < outliers; ++i) v.push_back(far(rng));
  std::shuffle(v.begin(), v.end(), rng);
  return v;
}

TEST(Ransac, FindsTheInlierValueAndStopsAdaptively) {
  const auto data = values_with_outliers(60, 40, 7);
  RansacOptions o;
  o.distance_threshold = 0.05;
  o.max_iterations = 10000;
  const auto r = ransac(ValueProblem{}, data, o);
  ASSERT_TRUE(r.model.has_value());
  EXPECT_NEAR(*r.model, 3.0, 0.05);
  EXPECT_EQ(r.termination, RansacTermination::Converged) << r.message;
  EXPECT_EQ(r.inliers.size(), 60u);
  for (std::size_t i : r.inliers) EXPECT_NEAR(data[i], 3.0, 0.06);
  EXPECT_TRUE(std::is_sorted(r.inliers.begin(), r.inliers.end()));
  // s = 1, w = 0.6: N = ⌈log 0.01 / log 0.4⌉ = 6 once the best is found.
  EXPECT_LE(r.iterations, 100u);
}

TEST(Ransac, KeepsTheBestOfSeveralModelsPerSample) {
  const auto data = values_with_outliers(50, 50, 3);
  ValueProblem p;
  p.emit_decoy = true;
  RansacOptions o;
  o.distance_threshold = 0.05;
  const auto r = ransac(p, data, o);
  ASSERT_TRUE(r.model.has_value());
  EXPECT_NEAR(*r.model, 3.0, 0.05);
}

TEST(Ransac, AllInliersConvergeAfterOneSampleUnlessMinIterations) {
  const std::vector<double> data(20, 1.0);
  RansacOptions o;
  o.distance_threshold = 0.1;
  auto r = ransac(ValueProblem{}, data, o);
  EXPECT_EQ(r.iterations, 1u);
  EXPECT_EQ(r.termination, RansacTermination::Converged);
  o.min_iterations = 10;
  r = ransac(ValueProblem{}, data, o);
  EXPECT_EQ(r.iterations, 10u);
  EXPECT_EQ(r.termination, RansacTermination::Converged);
}

TEST(Ransac, CapReportsMaxIterationsWithTheBestModel) {
  const auto data = values_with_outliers(10, 90, 11);  // w = 0.1, s = 3
  ValueProblem p;
  p.k = 3;
  RansacOptions o;
  o.distance_threshold = 0.05;
  o.max_iterations = 5;
  const auto r = ransac(p, data, o);
  EXPECT_EQ(r.iterations, 5u);
  EXPECT_EQ(r.termination, RansacTermination::MaxIterations) << r.message;
  EXPECT_TRUE(r.model.has_value());
  EXPECT_NE(r.message.find("cap"), std::string::npos) << r.message;
}

TEST(Ransac, SamplesWithoutReplacementAndUniformly) {
  std::vector<double> data(10);
  for (int i = 0; i < 10; ++i) data[i] = 100.0 * i;  // no model explains two data
  std::vector<std::vector<double>> samples;
  ValueProblem p;
  p.k = 4;
  p.samples = &samples;
  RansacOptions o;
  o.distance_threshold = 1.0;
  o.max_iterations = 20000;
  o.min_iterations = 20000;
  const auto r = ransac(p, data, o);
  ASSERT_EQ(samples.size(), 20000u);
  std::vector<int> count(10, 0);
  for (const auto& s : samples) {
    const std::set<double> distinct(s.begin(), s.end());
    ASSERT_EQ(distinct.size(), 4u) << "a sample repeated a datum";
    for (double v : s) ++count[static_cast<int>(v / 100.0)];
  }
  // Each datum appears in 4/10 of the samples: 8000 expected, sd ≈ 69.
  for (int c : count) EXPECT_NEAR(c, 8000, 400);
  EXPECT_EQ(r.iterations, 20000u);
}

TEST(Ransac, NotEnoughDataGivesNoModel) {
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {1, 0, 0}};
  const auto r = ransac(PlaneRansacProblem{}, two, RansacOptions{});
  EXPECT_EQ(r.termination, RansacTermination::NotEnoughData);
  EXPECT_FALSE(r.model.has_value());
  EXPECT_TRUE(r.inliers.empty());
  EXPECT_EQ(r.iterations, 0u);
  EXPECT_NE(r.message.find("minimal sample of 3"), std::string::npos) << r.message;

  const std::vector<Eigen::Vector3d> none;
  EXPECT_EQ(ransac(PlaneRansacProblem{}, none, RansacOptions{}).termination,
            RansacTermination::NotEnoughData);
}

TEST(Ransac, CollinearPointsAreDegenerateForAPlane) {
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 50; ++i) line.emplace_back(0.5 + 0.1 * i, 1.0 - 0.2 * i, 2.0 + 0.3 * i);
  RansacOptions o;
  o.max_iterations = 200;
  const auto r = ransac(PlaneRansacProblem{}, line, o);
  EXPECT_EQ(r.termination, RansacTermination::Degenerate) << r.message;
  EXPECT_FALSE(r.model.has_value());
  EXPECT_TRUE(r.inliers.empty());
  EXPECT_EQ(r.iterations, 200u);

  // Coincident points are degenerate for a line.
  const std::vector<Eigen::Vector2d> same(10, Eigen::Vector2d(1.0, 2.0));
  const auto rl = ransac(LineRansacProblem{}, same, o);
  EXPECT_EQ(rl.termination, RansacTermination::Degenerate);
  EXPECT_FALSE(rl.model.has_value());
}

TEST(Ransac, FitWithoutModelsIsDegenerate) {
  const std::vector<double> data = {1, 2, 3, 4};
  RansacOptions o;
  o.max_iterations = 7;
  const auto r = ransac(NeverFits{}, data, o);
  EXPECT_EQ(r.termination, RansacTermination::Degenerate);
  EXPECT_EQ(r.iterations, 7u);
  EXPECT_FALSE(r.model.has_value());
}

TEST(Ransac, SameSeedSameResultAcrossRuns) {
  const auto data = values_with_outliers(30, 70, 5);
  ValueProblem p;
  p.k = 2;
  RansacOptions o;
  o.distance_threshold = 0.03;
  o.seed = 1234;
  const auto a = ransac(p, data, o);
  const auto b = ransac(p, data, o);
  ASSERT_TRUE(a.model && b.model);
  EXPECT_EQ(*a.model, *b.model);
  EXPECT_EQ(a.inliers, b.inliers);
  EXPECT_EQ(a.iterations, b.iterations);
  // The same seed draws the same samples; another seed draws others.
  std::vector<std::vector<double>> s1, s2, s3;
  p.samples = &s1;
  ransac(p, data, o);
  p.samples = &s2;
  ransac(p, data, o);
  o.seed = 4321;
  p.samples = &s3;
  ransac(p, data, o);
  EXPECT_EQ(s1, s2);
  EXPECT_NE(s1, s3);
}

TEST(Ransac, RejectsInvalidOptions) {
  const std::vector<double> data = {1, 2, 3};
  RansacOptions o;
  o.distance_threshold = 0.0;
  EXPECT_THROW(ransac(ValueProblem{}, data, o), InvalidArgument);
  o = {};
  o.distance_threshold = std::nan("");
  EXPECT_THROW(ransac(ValueProblem{}, data, o), InvalidArgument);
  o = {};
  o.success_probability = 1.0;
  EXPECT_THROW(ransac(ValueProblem{}, data, o), InvalidArgument);
  o = {};
  o.max_iterations = 0;
  EXPECT_THROW(ransac(ValueProblem{}, data, o), InvalidArgument);
  o = {};
  o.min_iterations = o.max_iterations + 1;
  EXPECT_THROW(ransac(ValueProblem{}, data, o), InvalidArgument);
  ValueProblem zero;
  zero.k = 0;
  EXPECT_THROW(ransac(zero, data, RansacOptions{}), InvalidArgument);
}

TEST(Ransac, TerminationNames) {
  EXPECT_EQ(to_string(RansacTermination::Converged), "Converged");
  EXPECT_EQ(to_string(RansacTermination::MaxIterations), "MaxIterations");
  EXPECT_EQ(to_string(RansacTermination::NotEnoughData), "NotEnoughData");
  EXPECT_EQ(to_string(RansacTermination::Degenerate), "Degenerate");
}

}  // namespace
}  // namespace rove
