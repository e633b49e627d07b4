#include "rove/registration/rigid_transform.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/poses/lie_conversion.h"
#include "rove/registration/pose_covariance.h"

namespace rove {
namespace {

std::vector<Eigen::Vector2d> random_points_2d(std::mt19937_64& rng, std::size_t n) {
  std::uniform_real_distribution<double> u(-5, 5);
  std::vector<Eigen::Vector2d> p(n);
  for (auto& q : p) q = {u(rng), u(rng)};
  return p;
}

TEST(FitRigid2d, RecoversKnownTransformExactly) {
  std::mt19937_64 rng(1);
  const auto src = random_points_2d(rng, 30);
  const Pose2 T(1.5, -0.7, 2.9);
  std::vector<Eigen::Vector2d> tgt;
  for (const auto& s : src) tgt.push_back(T.rotation() * s + T.translation());
  const auto r = fit_rigid_2d(tgt, src);
  ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  EXPECT_NEAR(r.T_target_source.translation().x(), 1.5, 1e-12);
  EXPECT_NEAR(r.T_target_source.translation().y(), -0.7, 1e-12);
  EXPECT_NEAR(r.T_target_source.angle(), 2.9, 1e-12);
  EXPECT_LT(r.rmse, 1e-12);
  EXPECT_EQ(r.pairs, 30u);
}

TEST(FitRigid2d, ZeroWeightsIgnoreOutliers) {
  std::mt19937_64 rng(2);
  const auto src = random_points_2d(rng, 20);
  const Pose2 T(0.3, 0.2, -0.4);
  std::vector<Eigen::Vector2d> tgt;
  std::vector<double> w;
  for (std::size_t i = 0; i < src.size(); ++i) {
    tgt.push_back(T.rotation() * src[i] + T.translation());
    w.push_back(1.0);
    if (i % 4 == 0) {
      tgt.back() += Eigen::Vector2d(3, -2);
      w.back() = 0.0;
    }
  }
  const auto r = fit_rigid_2d(tgt, src, w);
  ASSERT_EQ(r.termination, RegistrationTermination::Converged);
  EXPECT_NEAR(r.T_target_source.angle(), -0.4, 1e-12);
  EXPECT_EQ(r.pairs, 15u);
}

// The covariance σ²(JᵀJ)⁻¹ must match the spread of estimates under noise of
// variance σ² (Monte Carlo oracle, 400 trials).
TEST(FitRigid2d, CovarianceMatchesMonteCarlo) {
  std::mt19937_64 rng(3);
  const auto src = random_points_2d(rng, 25);
  const Pose2 T(0.5, 1.0, 0.3);
  const double sigma = 0.05;
  std::normal_distribution<double> noise(0, sigma);
  RigidFitOptions opt;
  opt.point_variance = sigma * sigma;
  Eigen::Matrix3d sample_cov = Eigen::Matrix3d::Zero();
  const int trials = 400;
  Eigen::Matrix3d predicted = Eigen::Matrix3d::Zero();
  for (int k = 0; k < trials; ++k) {
    std::vector<Eigen::Vector2d> tgt;
    for (const auto& s : src)
      tgt.push_back(T.rotation() * s + T.translation() + Eigen::Vector2d(noise(rng), noise(rng)));
    const auto r = fit_rigid_2d(tgt, src, {}, opt);
    // The error in the right tangent, where the covariance is reported.
    const Eigen::Vector3d d = (to_se2(T).inverse() * r.T_target_source).log();
    sample_cov += d * d.transpose() / trials;
    predicted = r.covariance;
  }
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(sample_cov(i, i) / predicted(i, i), 1.0, 0.25) << "diagonal " << i;
}

TEST(FitRigid2d, DegenerateAndInvalidInputsAreReported) {
  std::vector<Eigen::Vector2d> one{{1, 2}};
  EXPECT_EQ(fit_rigid_2d(one, one).termination, RegistrationTermination::TooFewCorrespondences);
  std::vector<Eigen::Vector2d> same{{1, 2}, {1, 2}, {1, 2}};
  std::vector<Eigen::Vector2d> other{{0, 0}, {1, 0}, {2, 0}};
  EXPECT_EQ(fit_rigid_2d(other, same).termination, RegistrationTermination::Degenerate);
  std::vector<Eigen::Vector2d> nan{{0, 0}, {std::nan(""), 1}, {2, 0}};
  EXPECT_EQ(fit_rigid_2d(other, nan).termination, RegistrationTermination::InvalidInput);
  std::vector<Eigen::Vector2d> two{{0, 0}, {1, 0}};
  EXPECT_THROW(fit_rigid_2d(other, two), InvalidArgument);
  std::vector<double> neg{1, -1, 1};
  EXPECT_THROW(fit_rigid_2d(other, other, neg), InvalidArgument);
}

TEST(FitRigid3d, RecoversKnownTransformExactly) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-5, 5);
  std::vector<Eigen::Vector3d> src(40), tgt;
  for (auto& p : src) p = {u(rng), u(rng), u(rng)};
  const Pose3 T(0.4, -1.2, 2.0, 2.5, -0.6, 1.1);
  for (const auto& s : src) tgt.push_back(T.rotation() * s + T.translation());
  const auto r = fit_rigid_3d(tgt, src);
  ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  EXPECT_TRUE(r.T_target_source.matrix().isApprox(T.matrix(), 1e-10));
  EXPECT_LT(r.rmse, 1e-10);
}

TEST(FitRigid3d, NoReflectionOnPlanarPoints) {
  // Planar source points: SVD could return a reflection; the guard must not.
  std::vector<Eigen::Vector3d> src{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0.5, 0}};
  const Pose3 T(0, 0, 1, 0.3, 0.2, -0.1);
  std::vector<Eigen::Vector3d> tgt;
  for (const auto& s : src) tgt.push_back(T.rotation() * s + T.translation());
  const auto r = fit_rigid_3d(tgt, src);
  ASSERT_EQ(r.termination, RegistrationTermination::Converged);
  EXPECT_NEAR(r.T_target_source.rotation_matrix().determinant(), 1.0, 1e-12);
  EXPECT_TRUE(r.T_target_source.matrix().isApprox(T.matrix(), 1e-10));
}

// The covariance is over the right tangent: log(T⁻¹·T̂) of the estimates
// spreads as it predicts, off-diagonal terms included. The cloud is
// elongated and the rotation large, so the left tangent (or Euler angles)
// would predict a visibly different matrix (checked below).
TEST(FitRigid3d, CovarianceIsOverTheRightTangent) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(-4, 4), uy(-1, 1), uz(-0.3, 0.3);
  std::vector<Eigen::Vector3d> src(30);
  for (auto& p : src) p = {ux(rng), uy(rng), uz(rng)};
  const SE3d T = to_se3(Pose3(0.4, -1.2, 2.0, 1.2, 0.4, -0.7));
  const double sigma = 0.05;
  std::normal_distribution<double> noise(0, sigma);
  RigidFitOptions opt;
  opt.point_variance = sigma * sigma;
  const int trials = 600;
  Eigen::Matrix<double, 6, 6> sample = Eigen::Matrix<double, 6, 6>::Zero(), predicted;
  for (int k = 0; k < trials; ++k) {
    std::vector<Eigen::Vector3d> tgt;
    for (const auto& s : src)
      tgt.push_back(T * s + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    const auto r = fit_rigid_3d(tgt, src, {}, opt);
    ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
    const SE3d::Tangent d = (T.inverse() * r.T_target_source).log();
    sample += d * d.transpose() / trials;
    predicted = r.covariance;
  }
  // Compared as correlations: |Sᵢⱼ − Pᵢⱼ| / √(PᵢᵢPⱼⱼ), whose sampling error
  // over 600 trials is about 0.04.
  auto worst = [&](const Eigen::Matrix<double, 6, 6>& P) {
    double w = 0;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        w = std::max(w, std::abs(sample(i, j) - P(i, j)) / std::sqrt(P(i, i) * P(j, j)));
    return w;
  };
  EXPECT_LT(worst(predicted), 0.15);
  // The same matrix read in the left tangent, (R·ρ, R·ω), does not fit.
  const Eigen::Matrix3d R = T.rotation_matrix();
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  A.topLeftCorner<3, 3>() = R;
  A.bottomRightCorner<3, 3>() = R;
  EXPECT_GT(worst(A * predicted * A.transpose()), 0.3);
}

TEST(FitRigid3d, CollinearPointsAreDegenerate) {
  std::vector<Eigen::Vector3d> src{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  const auto r = fit_rigid_3d(src, src);
  EXPECT_EQ(r.termination, RegistrationTermination::Degenerate) << r.message;
  // The unconstrained rotation about x shows up as a huge variance.
  EXPECT_GT(r.covariance.diagonal().maxCoeff(), 1e3);
}

}  // namespace
}  // namespace rove
