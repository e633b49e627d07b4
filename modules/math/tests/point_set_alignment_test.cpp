#include "rove/math/point_set_alignment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "rove/core/error.h"

namespace rove {
namespace {

std::vector<Eigen::Vector3d> random_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::vector<Eigen::Vector3d> p(n);
  for (auto& x : p) x = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

TEST(PointSetAlignment, RecoversAKnownSimilarity) {
  const auto from = random_points(40, 1);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(3, -1, 2);
  const double s = 2.5;
  std::vector<Eigen::Vector3d> to;
  for (const auto& p : from) to.push_back(s * R * p + t);
  const auto fit = align_point_sets<3>(from, to, true);
  EXPECT_NEAR((fit.R - R).norm(), 0.0, 1e-12);
  EXPECT_NEAR((fit.t - t).norm(), 0.0, 1e-11);
  EXPECT_NEAR(fit.scale, s, 1e-12);
  EXPECT_NEAR(fit.rmse, 0.0, 1e-11);
  EXPECT_FALSE(fit.degenerate);
  // Without scale the best rigid fit leaves a residual and keeps scale 1.
  const auto rigid = align_point_sets<3>(from, to, false);
  EXPECT_EQ(rigid.scale, 1.0);
  EXPECT_GT(rigid.rmse, 1.0);
  EXPECT_NEAR(rigid.R.determinant(), 1.0, 1e-12);
}

TEST(PointSetAlignment, NoiseGivesTheLeastSquaresResidual) {
  // Pure translation plus zero-mean noise: the fit's rmse is at most the
  // noise's rmse (the identity-plus-shift is one candidate of the minimum).
  const auto from = random_points(200, 2);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.05);
  std::vector<Eigen::Vector3d> to;
  double sq = 0.0;
  for (const auto& p : from) {
    const Eigen::Vector3d e(n(rng), n(rng), n(rng));
    sq += e.squaredNorm();
    to.push_back(p + Eigen::Vector3d(1, 2, 3) + e);
  }
  const auto fit = align_point_sets<3>(from, to);
  EXPECT_LE(fit.rmse, std::sqrt(sq / 200.0));
  EXPECT_NEAR((fit.t - Eigen::Vector3d(1, 2, 3)).norm(), 0.0, 0.02);
}

TEST(PointSetAlignment, PlanarAndDegenerateSets) {
  const std::vector<Eigen::Vector2d> from = {{0, 0}, {1, 0}, {0, 2}};
  const double a = 1.0;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(a).toRotationMatrix();
  std::vector<Eigen::Vector2d> to;
  for (const auto& p : from) to.push_back(R * p + Eigen::Vector2d(4, 5));
  const auto fit = align_point_sets<2>(from, to);
  EXPECT_NEAR((fit.R - R).norm(), 0.0, 1e-12);
  EXPECT_FALSE(fit.degenerate);

  // Points on a line: the rotation about the line is not determined.
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const auto d = align_point_sets<3>(line, line);
  EXPECT_TRUE(d.degenerate);
  EXPECT_NEAR(d.rmse, 0.0, 1e-12);
  // One point in 2D: any rotation fits.
  const std::vector<Eigen::Vector2d> one = {{1, 1}};
  EXPECT_TRUE(align_point_sets<2>(one, one).degenerate);
}

TEST(PointSetAlignment, RejectsWhatItCannotAlign) {
  const std::vector<Eigen::Vector3d> a = {{0, 0, 0}, {1, 0, 0}};
  const std::vector<Eigen::Vector3d> b = {{0, 0, 0}};
  EXPECT_THROW(align_point_sets<3>(a, b), InvalidArgument);
  EXPECT_THROW(align_point_sets<3>(std::vector<Eigen::Vector3d>{}, std::vector<Eigen::Vector3d>{}),
               InvalidArgument);
  const std::vector<Eigen::Vector3d> same = {{1, 1, 1}, {1, 1, 1}};
  EXPECT_THROW(align_point_sets<3>(same, a, true), InvalidArgument);
  const std::vector<Eigen::Vector3d> nan = {{0, 0, 0}, {std::nan(""), 0, 0}};
  EXPECT_THROW(align_point_sets<3>(nan, a), InvalidArgument);
}

}  // namespace
}  // namespace rove
