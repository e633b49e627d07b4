// PoseParticles and PoseSOG: weights, means, covariances against
// hand-computed values, sampling frequencies.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "pdf_test_util.h"
#include "rove/core/error.h"
#include "rove/poses/pdf_particles.h"
#include "rove/poses/pdf_sog.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(PdfParticles, Pose2MeanAndCovarianceAcrossPi) {
  Pose2Particles p;
  p.push_back(Pose2(0.0, 0.0, 179 * kDeg));
  p.push_back(Pose2(2.0, 0.0, -179 * kDeg));
  const Pose2 m = p.mean();
  EXPECT_NEAR(m.x(), 1.0, 1e-15);
  EXPECT_NEAR(m.y(), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(m.phi()), std::numbers::pi, 1e-12);
  const Eigen::Matrix3d C = p.covariance();
  Eigen::Matrix3d expected;
  expected << 1.0, 0.0, kDeg, 0.0, 0.0, 0.0, kDeg, 0.0, kDeg * kDeg;
  EXPECT_LT((C - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(PdfParticles, WeightsEssAndMostLikely) {
  Pose2Particles p;
  p.push_back(Pose2(0.0, 0.0, 0.0), std::log(3.0));
  p.push_back(Pose2(2.0, 4.0, kDeg * 90), std::log(1.0));
  const std::vector<double> w = p.normalized_weights();
  EXPECT_NEAR(w[0], 0.75, 1e-15);
  EXPECT_NEAR(w[1], 0.25, 1e-15);
  EXPECT_NEAR(p.effective_sample_size(), 1.0 / (0.75 * 0.75 + 0.25 * 0.25), 1e-12);
  EXPECT_EQ(p.most_likely().pose, Pose2(0.0, 0.0, 0.0));
  const Pose2 m = p.mean();
  EXPECT_NEAR(m.x(), 0.5, 1e-15);
  EXPECT_NEAR(m.y(), 1.0, 1e-15);
  EXPECT_NEAR(m.phi(), std::atan2(0.25, 0.75), 1e-15);
  // Log-weights shifted by a constant change nothing but the normalization.
  Pose2Particles shifted;
  shifted.push_back(Pose2(0.0, 0.0, 0.0), std::log(3.0) - 800.0);
  shifted.push_back(Pose2(2.0, 4.0, kDeg * 90), -800.0);
  EXPECT_NEAR(shifted.normalized_weights()[0], 0.75, 1e-12);
  shifted.normalize_weights();
  EXPECT_NEAR(std::exp(shifted.particles()[0].log_weight) +
                  std::exp(shifted.particles()[1].log_weight),
              1.0, 1e-12);
  Pose2Particles equal(10, Pose2(1, 2, 3));
  EXPECT_NEAR(equal.effective_sample_size(), 10.0, 1e-12);
}

TEST(PdfParticles, SampleFrequenciesFollowWeights) {
  Pose2Particles p;
  p.push_back(Pose2(0.0, 0.0, 0.0), std::log(3.0));
  p.push_back(Pose2(1.0, 0.0, 0.0), 0.0);
  p.push_back(Pose2(2.0, 0.0, 0.0), -std::numeric_limits<double>::infinity());
  std::mt19937_64 rng(1);
  int counts[3] = {0, 0, 0};
  const int n = 100000;
  for (int i = 0; i < n; ++i) ++counts[static_cast<int>(p.sample(rng).x())];
  EXPECT_NEAR(counts[0] / double(n), 0.75, 0.01);
  EXPECT_NEAR(counts[1] / double(n), 0.25, 0.01);
  EXPECT_EQ(counts[2], 0);
}

TEST(PdfParticles, Pose3MeanRotationAboutCommonAxis) {
  // Rotations about z by θᵢ: the chordal mean is the rotation about z by
  // atan2(Σ wᵢ sin θᵢ, Σ wᵢ cos θᵢ); translations average linearly.
  Pose3Particles p;
  p.push_back(Pose3(1, 0, 0, 0.4, 0, 0), std::log(2.0));
  p.push_back(Pose3(0, 1, 3, -0.2, 0, 0), std::log(1.0));
  p.push_back(Pose3(0, 2, 0, 1.0, 0, 0), std::log(1.0));
  const Pose3 m = p.mean();
  const double s = 0.5 * std::sin(0.4) + 0.25 * std::sin(-0.2) + 0.25 * std::sin(1.0);
  const double c = 0.5 * std::cos(0.4) + 0.25 * std::cos(-0.2) + 0.25 * std::cos(1.0);
  EXPECT_NEAR(m.yaw(), std::atan2(s, c), 1e-12);
  EXPECT_NEAR(m.pitch(), 0.0, 1e-12);
  EXPECT_NEAR(m.roll(), 0.0, 1e-12);
  EXPECT_LT((m.translation() - Eigen::Vector3d(0.5, 0.75, 0.75)).norm(), 1e-12);
  const Pose3Particles::Matrix C = p.covariance();
  const double ym = m.yaw();
  const double var_yaw = 0.5 * std::pow(0.4 - ym, 2) + 0.25 * std::pow(-0.2 - ym, 2) +
                         0.25 * std::pow(1.0 - ym, 2);
  EXPECT_NEAR(C(3, 3), var_yaw, 1e-12);
  EXPECT_NEAR(C(2, 2), 0.25 * 9 - 0.75 * 0.75, 1e-12);
  EXPECT_NEAR(C(4, 4), 0.0, 1e-12);
}

TEST(PdfParticles, Pose3ChordalMeanIsAMinimizer) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n(0.0, 0.3);
  std::vector<Pose3> poses;
  std::vector<double> weights;
  Pose3Particles p;
  for (int i = 0; i < 20; ++i) {
    poses.emplace_back(n(rng), n(rng), n(rng), 1.0 + n(rng), n(rng), -0.5 + n(rng));
    weights.push_back(0.5 + std::abs(n(rng)));
    p.push_back(poses.back(), std::log(weights.back()));
  }
  const Pose3 m = p.mean();
  auto cost = [&](const Eigen::Matrix3d& R) {
    double c = 0.0;
    for (std::size_t i = 0; i < poses.size(); ++i)
      c += weights[i] * (R - poses[i].rotation()).squaredNorm();
    return c;
  };
  const double c0 = cost(m.rotation());
  for (int k = 0; k < 200; ++k) {
    const Pose3 d(0, 0, 0, 0.01 * n(rng), 0.01 * n(rng), 0.01 * n(rng));
    EXPECT_GE(cost((m + d).rotation()), c0 - 1e-12);
  }
}

TEST(PdfParticles, InvalidInputsRejected) {
  Pose2Particles p;
  EXPECT_THROW(p.mean(), InvalidArgument);
  EXPECT_THROW(p.most_likely(), InvalidArgument);
  EXPECT_THROW(p.push_back(Pose2(), std::numeric_limits<double>::quiet_NaN()), InvalidArgument);
  EXPECT_THROW(p.push_back(Pose2(), std::numeric_limits<double>::infinity()), InvalidArgument);
  p.push_back(Pose2(), -std::numeric_limits<double>::infinity());
  EXPECT_THROW(p.normalize_weights(), InvalidArgument);
  // Opposite headings with equal weights: the mean heading is undetermined.
  Pose2Particles opposite;
  opposite.push_back(Pose2(0, 0, 0));
  opposite.push_back(Pose2(0, 0, std::numbers::pi));
  EXPECT_THROW(opposite.mean(), NumericError);
}

// ---- Sum of Gaussians ---------------------------------------------------------

TEST(PdfSog, Pose2LawOfTotalCovariance) {
  Pose2SOG sog;
  sog.push_back(Pose2Gaussian(Pose2(0, 0, 179 * kDeg), Eigen::Vector3d(0.1, 0.2, 0.01).asDiagonal()));
  sog.push_back(
      Pose2Gaussian(Pose2(2, 0, -179 * kDeg), Eigen::Vector3d(0.3, 0.1, 0.02).asDiagonal()));
  const Pose2 m = sog.mean();
  EXPECT_NEAR(m.x(), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(m.phi()), std::numbers::pi, 1e-12);
  Eigen::Matrix3d expected;
  expected << 0.2 + 1.0, 0.0, kDeg, 0.0, 0.15, 0.0, kDeg, 0.0, 0.015 + kDeg * kDeg;
  EXPECT_LT((sog.covariance() - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(PdfSog, Pose3WeightedModes) {
  Pose3Gaussian::Matrix C1 = Pose3Gaussian::Matrix::Identity() * 0.01;
  Pose3Gaussian::Matrix C2 = Pose3Gaussian::Matrix::Identity() * 0.04;
  Pose3SOG sog;
  sog.push_back(Pose3Gaussian(Pose3(0, 0, 0, 0, 0, 0), C1), std::log(3.0));
  sog.push_back(Pose3Gaussian(Pose3(4, 0, 0, 0, 0, 0), C2), std::log(1.0));
  EXPECT_NEAR(sog.mean().x(), 1.0, 1e-15);
  const Pose3SOG::Matrix C = sog.covariance();
  // 0.75·0.01 + 0.25·0.04 + 0.75·1² + 0.25·3².
  EXPECT_NEAR(C(0, 0), 0.0175 + 0.75 + 2.25, 1e-12);
  EXPECT_NEAR(C(1, 1), 0.0175, 1e-12);
  EXPECT_NEAR(C(5, 5), 0.0175, 1e-12);
  EXPECT_NEAR(C(0, 1), 0.0, 1e-12);
  EXPECT_EQ(sog.most_likely().gaussian.mean().x(), 0.0);
  sog.normalize_weights();
  EXPECT_NEAR(std::exp(sog.modes()[0].log_weight), 0.75, 1e-12);
}

TEST(PdfSog, SamplesMatchMixtureMoments) {
  std::mt19937_64 rng(3);
  Pose2SOG sog;
  sog.push_back(Pose2Gaussian(Pose2(0, 0, 0.2), pdf_test::random_covariance(
                                                    rng, Eigen::Vector3d(0.2, 0.3, 0.05))),
                std::log(2.0));
  sog.push_back(Pose2Gaussian(Pose2(1, -1, -0.3), pdf_test::random_covariance(
                                                      rng, Eigen::Vector3d(0.1, 0.2, 0.1))),
                std::log(1.0));
  const Pose2 m = sog.mean();
  std::vector<Eigen::VectorXd> d;
  for (int i = 0; i < 100000; ++i) d.emplace_back(pose_difference(sog.sample(rng), m));
  // The sample covariance is taken around the sample mean, the SOG one around
  // the circular mean: compare the raw second moments instead.
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const auto& v : d) second += v * v.transpose() / static_cast<double>(d.size());
  EXPECT_LT(pdf_test::normalized_cov_error(second, sog.covariance()), 0.02);
}

TEST(PdfSog, InvalidInputsRejected) {
  Pose3SOG sog;
  EXPECT_THROW(sog.mean(), InvalidArgument);
  EXPECT_THROW(sog.most_likely(), InvalidArgument);
  EXPECT_THROW(sog.push_back(Pose3Gaussian(), std::numeric_limits<double>::quiet_NaN()),
               InvalidArgument);
}

}  // namespace
}  // namespace rove
