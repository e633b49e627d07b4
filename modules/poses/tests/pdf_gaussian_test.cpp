// Gaussian pose PDFs: propagation against Monte-Carlo and closed forms,
// conversions, sampling, densities and input validation.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "pdf_test_util.h"
#include "rove/core/error.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/pdf_gaussian3_quat.h"
#include "rove/poses/pdf_information.h"
#include "rove/poses/pdf_pose_average.h"

namespace rove {
namespace {

using pdf_test::normalized_cov_error;
using pdf_test::random_covariance;
using pdf_test::sample_covariance;

constexpr std::size_t kSamples = 100000;
// Monte-Carlo tolerance in units of standard deviations: the sampling error
// of a normalized covariance entry is about sqrt(2/N) = 0.0045 at N = 1e5.
constexpr double kMcTol = 0.03;

Pose2Gaussian::Matrix cov2(std::mt19937_64& rng, double s_xy, double s_phi) {
  return random_covariance(rng, Eigen::Vector3d(s_xy, 0.7 * s_xy, s_phi));
}

Pose3Gaussian::Matrix cov3(std::mt19937_64& rng, double s_t, double s_r) {
  Eigen::Matrix<double, 6, 1> s;
  s << s_t, 0.8 * s_t, 1.2 * s_t, s_r, 0.7 * s_r, 1.3 * s_r;
  return random_covariance(rng, s);
}

Eigen::Matrix<double, 7, 1> quat_diff(const Pose3Quat& p, const Pose3Quat& mean) {
  return Pose3QuatGaussian(mean).difference(p);
}

// ---- Propagation against Monte-Carlo ------------------------------------------

TEST(PdfGaussian2, ComposeMatchesMonteCarlo) {
  std::mt19937_64 rng(42);
  const Pose2Gaussian a(Pose2(1.0, 2.0, 0.5), cov2(rng, 0.08, 0.04));
  const Pose2Gaussian b(Pose2(2.0, -1.0, -0.3), cov2(rng, 0.1, 0.05));
  const std::vector<Pose2> sa = a.sample(rng, kSamples), sb = b.sample(rng, kSamples);
  for (int op = 0; op < 3; ++op) {
    const Pose2Gaussian r = op == 0 ? a + b : op == 1 ? a - b : inverse(a);
    std::vector<Eigen::VectorXd> d;
    for (std::size_t i = 0; i < kSamples; ++i) {
      const Pose2 s = op == 0 ? sa[i] + sb[i] : op == 1 ? sa[i] - sb[i] : -sa[i];
      d.emplace_back(pose_difference(s, r.mean()));
    }
    EXPECT_LT(normalized_cov_error(sample_covariance(d), r.covariance()), kMcTol) << "op " << op;
  }
}

TEST(PdfGaussian2, DeterministicOperandsMatchMonteCarlo) {
  std::mt19937_64 rng(7);
  const Pose2Gaussian a(Pose2(-1.0, 0.5, 2.8), cov2(rng, 0.05, 0.06));
  const Pose2 p(3.0, 1.0, -2.0);
  const std::vector<Pose2> sa = a.sample(rng, kSamples);
  for (int op = 0; op < 4; ++op) {
    const Pose2Gaussian r = op == 0 ? a + p : op == 1 ? p + a : op == 2 ? a - p : p - a;
    std::vector<Eigen::VectorXd> d;
    for (const Pose2& s : sa) {
      const Pose2 x = op == 0 ? s + p : op == 1 ? p + s : op == 2 ? s - p : p - s;
      d.emplace_back(pose_difference(x, r.mean()));
    }
    EXPECT_LT(normalized_cov_error(sample_covariance(d), r.covariance()), kMcTol) << "op " << op;
  }
}

TEST(PdfGaussian3, ComposeInverseMatchMonteCarlo) {
  std::mt19937_64 rng(4242);
  const Pose3Gaussian a(Pose3(1.0, 2.0, -0.5, 0.4, 0.3, -0.2), cov3(rng, 0.05, 0.03));
  const Pose3Gaussian b(Pose3(2.0, -1.0, 0.7, -2.9, -0.6, 2.9), cov3(rng, 0.08, 0.04));
  const std::vector<Pose3> sa = a.sample(rng, kSamples), sb = b.sample(rng, kSamples);
  for (int op = 0; op < 3; ++op) {
    const Pose3Gaussian r = op == 0 ? a + b : op == 1 ? a - b : inverse(a);
    std::vector<Eigen::VectorXd> d;
    for (std::size_t i = 0; i < kSamples; ++i) {
      const Pose3 s = op == 0 ? sa[i] + sb[i] : op == 1 ? sa[i] - sb[i] : sa[i].inverse();
      d.emplace_back(pose_difference(s, r.mean()));
    }
    EXPECT_LT(normalized_cov_error(sample_covariance(d), r.covariance()), kMcTol) << "op " << op;
  }
  // Deterministic operand on either side.
  const Pose3 p(0.5, -1.0, 2.0, 1.0, -0.3, 0.6);
  for (int op = 0; op < 2; ++op) {
    const Pose3Gaussian r = op == 0 ? a + p : p + a;
    std::vector<Eigen::VectorXd> d;
    for (const Pose3& s : sa) d.emplace_back(pose_difference(op == 0 ? s + p : p + s, r.mean()));
    EXPECT_LT(normalized_cov_error(sample_covariance(d), r.covariance()), kMcTol) << "op " << op;
  }
}

TEST(PdfGaussian3Quat, ComposeInverseMatchMonteCarlo) {
  std::mt19937_64 rng(99);
  // Quaternion Gaussians converted from Euler ones: the 7×7 covariances are
  // singular along the quaternion, as in practice.
  const Pose3QuatGaussian a = to_quat_gaussian(
      Pose3Gaussian(Pose3(1.0, 2.0, -0.5, 2.6, 0.3, -0.2), cov3(rng, 0.05, 0.03)));
  const Pose3QuatGaussian b = to_quat_gaussian(
      Pose3Gaussian(Pose3(2.0, -1.0, 0.7, 2.7, -0.6, 0.4), cov3(rng, 0.08, 0.04)));
  const std::vector<Pose3Quat> sa = a.sample(rng, kSamples), sb = b.sample(rng, kSamples);
  for (int op = 0; op < 3; ++op) {
    const Pose3QuatGaussian r = op == 0 ? a + b : op == 1 ? a - b : inverse(a);
    std::vector<Eigen::VectorXd> d;
    for (std::size_t i = 0; i < kSamples; ++i) {
      const Pose3Quat s = op == 0 ? sa[i] + sb[i] : op == 1 ? sa[i] - sb[i] : sa[i].inverse();
      d.emplace_back(quat_diff(s, r.mean()));
    }
    // Compare on the well-excited entries (the singular direction has ~0 variance).
    const Eigen::MatrixXd S = sample_covariance(d);
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j) {
        const double scale = std::sqrt(S(i, i) * S(j, j)) + 1e-6;
        EXPECT_LT(std::abs(S(i, j) - r.covariance()(i, j)) / scale, kMcTol)
            << "op " << op << " entry " << i << "," << j;
      }
  }
}

TEST(PdfGaussian3Quat, QuatToEulerMatchesMonteCarlo) {
  std::mt19937_64 rng(5);
  Pose3QuatGaussian::Matrix C = Pose3QuatGaussian::Matrix::Zero();
  Eigen::Matrix<double, 7, 1> s;
  s << 0.05, 0.04, 0.06, 0.01, 0.02, 0.015, 0.012;
  C = random_covariance(rng, s);  // full rank, non-unit samples
  const Pose3QuatGaussian q(Pose3Quat(1, 2, 3, 0.8, 0.2, -0.3, 0.4), C);
  const Pose3Gaussian e = to_euler_gaussian(q);
  std::vector<Eigen::VectorXd> d;
  for (const Pose3Quat& x : q.sample(rng, kSamples))
    d.emplace_back(pose_difference(Pose3(x), e.mean()));
  EXPECT_LT(normalized_cov_error(sample_covariance(d), e.covariance()), kMcTol);
}

TEST(PdfGaussian3, ComposeWhereQuaternionProductHasNegativeW) {
  // Regression: for these means the raw product of the yaw-pitch-roll
  // quaternions has w < 0. MRPT 2.5.8 re-signs the mean quaternion but not the
  // Jacobian rows, which flips the sign of the translation-rotation
  // cross-covariance; the Monte-Carlo oracle pins the consistent result.
  std::mt19937_64 rng(77);
  const Pose3 ma(1.0, 2.0, -0.5, 0.3, 0.2, -0.1), mb(-0.5, 3.0, 1.0, 2.9, -1.1, 2.8);
  const Pose3Gaussian a(ma, cov3(rng, 0.03, 0.015)), b(mb, cov3(rng, 0.04, 0.02));
  const Pose3Gaussian r = a + b;
  const std::vector<Pose3> sa = a.sample(rng, kSamples), sb = b.sample(rng, kSamples);
  std::vector<Eigen::VectorXd> d;
  for (std::size_t i = 0; i < kSamples; ++i) d.emplace_back(pose_difference(sa[i] + sb[i], r.mean()));
  EXPECT_LT(normalized_cov_error(sample_covariance(d), r.covariance()), kMcTol);
}

// ---- Closed forms -------------------------------------------------------------

TEST(PdfGaussian2, ComposeClosedForm) {
  // Heading uncertainty σ² at the origin, then 1 m forward: y and phi
  // inherit σ² and are fully correlated.
  const double s2 = 0.01;
  const Pose2Gaussian a(Pose2(0, 0, 0), Eigen::Vector3d(0, 0, s2).asDiagonal());
  const Pose2Gaussian r = a + Pose2Gaussian(Pose2(1, 0, 0));
  Eigen::Matrix3d expected;
  expected << 0, 0, 0, 0, s2, s2, 0, s2, s2;
  EXPECT_LT((r.covariance() - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(r.mean(), Pose2(1, 0, 0));
}

TEST(PdfGaussian3, ComposeClosedForm) {
  const double s2 = 0.01;
  Pose3Gaussian::Matrix C = Pose3Gaussian::Matrix::Zero();
  C(3, 3) = s2;
  const Pose3Gaussian r = Pose3Gaussian(Pose3(), C) + Pose3(1, 0, 0, 0, 0, 0);
  Pose3Gaussian::Matrix expected = Pose3Gaussian::Matrix::Zero();
  expected(1, 1) = expected(1, 3) = expected(3, 1) = expected(3, 3) = s2;
  EXPECT_LT((r.covariance() - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PdfGaussian3, TwoDimensionalEmbeddingCommutesWithCompose) {
  std::mt19937_64 rng(3);
  const Pose2Gaussian a(Pose2(1.0, 2.0, 0.5), cov2(rng, 0.08, 0.04));
  const Pose2Gaussian b(Pose2(2.0, -1.0, 2.9), cov2(rng, 0.1, 0.05));
  const Pose3Gaussian r3 = to_3d(a) + to_3d(b);
  const Pose2Gaussian r2 = to_2d(r3);
  EXPECT_LT((r2.covariance() - (a + b).covariance()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(r2.mean().x(), (a + b).mean().x(), 1e-12);
  EXPECT_NEAR(wrap_to_pi(r2.mean().phi() - (a + b).mean().phi()), 0.0, 1e-12);
  // Round trip 2D → 3D → 2D is exact.
  EXPECT_EQ(to_2d(to_3d(a)).covariance(), a.covariance());
}

TEST(PdfGaussian3, InverseComposeEqualsInverseThenCompose) {
  std::mt19937_64 rng(11);
  const Pose3Gaussian a(Pose3(1.0, 2.0, -0.5, 0.4, 0.3, -0.2), cov3(rng, 0.05, 0.03));
  const Pose3Gaussian b(Pose3(2.0, -1.0, 0.7, -2.9, -0.6, 2.9), cov3(rng, 0.08, 0.04));
  const Pose3Gaussian r1 = a - b, r2 = inverse(b) + a;
  EXPECT_LT((r1.covariance() - r2.covariance()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(pose_difference(r1.mean(), r2.mean()).cwiseAbs().maxCoeff(), 1e-12);
  // Inverse is an involution on the covariance too.
  EXPECT_LT((inverse(inverse(a)).covariance() - a.covariance()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(PdfGaussian3Quat, EulerQuatEulerRoundTrip) {
  std::mt19937_64 rng(8);
  for (const Pose3& m : {Pose3(1, 2, 3, 0.4, 0.3, -0.2), Pose3(-1, 0, 2, 2.97, -1.2, 2.96),
                         Pose3(0, 0, 0, -3.0, 1.3, 0.1)}) {
    const Pose3Gaussian g(m, cov3(rng, 0.1, 0.05));
    const Pose3QuatGaussian q = to_quat_gaussian(g);
    const Pose3Gaussian back = to_euler_gaussian(q);
    EXPECT_LT((back.covariance() - g.covariance()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(pose_difference(back.mean(), m).cwiseAbs().maxCoeff(), 1e-12);
    // The quaternion covariance has no variance along the mean quaternion.
    const Eigen::Matrix<double, 7, 1> dir =
        (Eigen::Matrix<double, 7, 1>() << 0, 0, 0, q.mean().qw(), q.mean().qx(), q.mean().qy(),
         q.mean().qz())
            .finished();
    EXPECT_NEAR(dir.dot(q.covariance() * dir), 0.0, 1e-15);
  }
}

TEST(PdfGaussian3Quat, EulerAndQuaternionCompositionAgree) {
  std::mt19937_64 rng(12);
  const Pose3Gaussian a(Pose3(1.0, 2.0, -0.5, 0.4, 0.3, -0.2), cov3(rng, 0.05, 0.03));
  const Pose3Gaussian b(Pose3(2.0, -1.0, 0.7, 2.9, -0.6, 2.9), cov3(rng, 0.08, 0.04));
  const Pose3Gaussian via_quat = to_euler_gaussian(to_quat_gaussian(a) + to_quat_gaussian(b));
  const Pose3Gaussian direct = a + b;
  EXPECT_LT((via_quat.covariance() - direct.covariance()).cwiseAbs().maxCoeff(), 1e-12);
  const Pose3Gaussian inv_q = to_euler_gaussian(inverse(to_quat_gaussian(a)));
  EXPECT_LT((inv_q.covariance() - inverse(a).covariance()).cwiseAbs().maxCoeff(), 1e-12);
}

// ---- Information form ---------------------------------------------------------

TEST(PdfInformation, RoundTrips) {
  std::mt19937_64 rng(21);
  const Pose2Gaussian g2(Pose2(1, 2, 3), cov2(rng, 0.2, 0.1));
  const Pose2Gaussian back2 = to_covariance(to_information(g2));
  EXPECT_LT((back2.covariance() - g2.covariance()).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT(((to_information(g2).information() * g2.covariance()) - Eigen::Matrix3d::Identity())
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  const Pose3Gaussian g3(Pose3(1, 2, 3, 0.1, 0.2, 0.3), cov3(rng, 0.2, 0.1));
  const Pose3Gaussian back3 = to_covariance(to_information(g3));
  EXPECT_LT((back3.covariance() - g3.covariance()).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(PdfInformation, OperationsAgreeWithCovarianceForm) {
  std::mt19937_64 rng(22);
  const Pose2Gaussian a(Pose2(1.0, 2.0, 0.5), cov2(rng, 0.08, 0.04));
  const Pose2Gaussian b(Pose2(2.0, -1.0, -0.3), cov2(rng, 0.1, 0.05));
  const Pose2 p(0.3, -0.7, 1.9);
  const auto ia = to_information(a), ib = to_information(b);
  auto near = [](const Eigen::MatrixXd& x, const Eigen::MatrixXd& y) {
    return (x - y).cwiseAbs().maxCoeff() < 1e-9 * y.cwiseAbs().maxCoeff();
  };
  EXPECT_TRUE(near((ia + ib).information(), to_information(a + b).information()));
  EXPECT_TRUE(near((ia - ib).information(), to_information(a - b).information()));
  EXPECT_TRUE(near((p + ia).information(), to_information(p + a).information()));
  EXPECT_TRUE(near((ia + p).information(), to_information(a + p).information()));
  EXPECT_TRUE(near((-ia).information(), to_information(-a).information()));

  const Pose3Gaussian a3(Pose3(1.0, 2.0, -0.5, 0.4, 0.3, -0.2), cov3(rng, 0.05, 0.03));
  const Pose3Gaussian b3(Pose3(2.0, -1.0, 0.7, -2.9, -0.6, 2.9), cov3(rng, 0.08, 0.04));
  const Pose3 p3(0.5, -1.0, 2.0, 1.0, -0.3, 0.6);
  const auto ia3 = to_information(a3), ib3 = to_information(b3);
  EXPECT_TRUE(near((ia3 + ib3).information(), to_information(a3 + b3).information()));
  EXPECT_TRUE(near((ia3 - ib3).information(), to_information(a3 - b3).information()));
  EXPECT_TRUE(near((p3 + ia3).information(), to_information(p3 + a3).information()));
  EXPECT_TRUE(near((ia3 + p3).information(), to_information(a3 + p3).information()));
  EXPECT_TRUE(near((-ia3).information(), to_information(-a3).information()));
}

TEST(PdfInformation, SingularInformationTransformsExactly) {
  // Information only about x: still valid after inversion; inverting twice
  // gives it back, and Mahalanobis distances of corresponding displacements
  // are preserved to first order.
  const Pose2GaussianInf g(Pose2(1.0, 2.0, 0.7), Eigen::Vector3d(4.0, 0.0, 0.0).asDiagonal());
  const Pose2GaussianInf inv = inverse(g);
  EXPECT_LT((inverse(inv).information() - g.information()).cwiseAbs().maxCoeff(), 1e-12);
  const Pose2 p(1.001, 2.0005, 0.7002);
  EXPECT_NEAR(inv.mahalanobis_distance(-p), g.mahalanobis_distance(p), 1e-5);
  EXPECT_THROW(to_covariance(g), InvalidArgument);
}

// ---- Densities and distances --------------------------------------------------

TEST(PdfGaussian2, MahalanobisAndLikelihoodClosedForm) {
  const Pose2 m(1.0, 2.0, 3.1);
  const Pose2Gaussian g(m, Eigen::Vector3d(4.0, 1.0, 0.25).asDiagonal());
  // d = (2, 1, 0.5) wraps across ±π on the angle.
  const Pose2 p(3.0, 3.0, wrap_to_pi(3.1 + 0.5));
  EXPECT_NEAR(g.mahalanobis_distance(p), std::sqrt(3.0), 1e-12);
  const double expected_log =
      -0.5 * (3.0 + std::log(4.0 * 1.0 * 0.25) + 3.0 * std::log(2.0 * std::numbers::pi));
  EXPECT_NEAR(g.log_likelihood(p), expected_log, 1e-12);
  EXPECT_NEAR(g.likelihood(p), std::exp(expected_log), 1e-15);
  const Pose2GaussianInf gi = to_information(g);
  EXPECT_NEAR(gi.log_likelihood(p), expected_log, 1e-12);
  EXPECT_NEAR(gi.mahalanobis_distance(p), std::sqrt(3.0), 1e-12);
  // Between two Gaussians: covariances add.
  const Pose2Gaussian h(p, Eigen::Vector3d(4.0, 1.0, 0.25).asDiagonal());
  EXPECT_NEAR(g.mahalanobis_distance(h), std::sqrt(1.5), 1e-12);
}

TEST(PdfGaussian3, MahalanobisAndLikelihoodClosedForm) {
  Eigen::Matrix<double, 6, 1> var;
  var << 1, 4, 9, 0.01, 0.04, 0.09;
  const Pose3Gaussian g(Pose3(1, 2, 3, 0.1, 0.2, 0.3), var.asDiagonal());
  const Pose3 p(2, 4, 6, 0.2, 0.4, 0.6);  // one sigma on each axis
  EXPECT_NEAR(g.mahalanobis_distance(p), std::sqrt(6.0), 1e-9);
  const double expected_log =
      -0.5 * (6.0 + var.array().log().sum() + 6.0 * std::log(2.0 * std::numbers::pi));
  EXPECT_NEAR(g.log_likelihood(p), expected_log, 1e-9);
  EXPECT_NEAR(to_information(g).log_likelihood(p), expected_log, 1e-9);
}

TEST(PdfGaussian2, ZeroCovarianceDistances) {
  const Pose2Gaussian g(Pose2(1, 2, 0.3));
  EXPECT_EQ(g.mahalanobis_distance(Pose2(1, 2, 0.3)), 0.0);
  EXPECT_EQ(g.mahalanobis_distance(Pose2(1, 2.1, 0.3)),
            std::numeric_limits<double>::infinity());
  EXPECT_THROW(g.log_likelihood(Pose2(1, 2, 0.3)), InvalidArgument);
}

// ---- Sampling -----------------------------------------------------------------

TEST(PdfGaussian2, SamplesMatchMeanAndCovariance) {
  std::mt19937_64 rng(31);
  const Pose2Gaussian g(Pose2(1.0, -2.0, 3.0), cov2(rng, 0.3, 0.2));  // straddles ±π
  std::vector<Eigen::VectorXd> d;
  for (const Pose2& s : g.sample(rng, kSamples)) d.emplace_back(pose_difference(s, g.mean()));
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(3);
  for (const auto& v : d) mean += v / static_cast<double>(kSamples);
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(mean[i]) / std::sqrt(g.covariance()(i, i)), 0.02);
  EXPECT_LT(normalized_cov_error(sample_covariance(d), g.covariance()), 0.02);
}

TEST(PdfGaussian3, SamplesMatchMeanAndCovariance) {
  std::mt19937_64 rng(32);
  const Pose3Gaussian g(Pose3(1.0, -2.0, 0.5, 0.3, -0.4, 1.0), cov3(rng, 0.3, 0.1));
  std::vector<Eigen::VectorXd> d;
  for (const Pose3& s : g.sample(rng, kSamples)) d.emplace_back(pose_difference(s, g.mean()));
  EXPECT_LT(normalized_cov_error(sample_covariance(d), g.covariance()), 0.02);
  const Pose3GaussianInf gi = to_information(g);
  std::vector<Eigen::VectorXd> di;
  for (const Pose3& s : gi.sample(rng, kSamples)) di.emplace_back(pose_difference(s, g.mean()));
  EXPECT_LT(normalized_cov_error(sample_covariance(di), g.covariance()), 0.02);
}

TEST(PdfGaussian, SemiDefiniteAndZeroCovarianceSampling) {
  std::mt19937_64 rng(33);
  const Pose2Gaussian zero(Pose2(1.0, 2.0, 0.3));
  EXPECT_EQ(zero.sample(rng), zero.mean());
  const Pose3Gaussian zero3(Pose3(1.0, 2.0, 3.0, 0.3, 0.2, 0.1));
  EXPECT_LT(pose_difference(zero3.sample(rng), zero3.mean()).cwiseAbs().maxCoeff(), 1e-14);
  // Rank one: all variance along (1, 1, 0).
  Eigen::Matrix3d C = Eigen::Vector3d(1, 1, 0) * Eigen::RowVector3d(1, 1, 0) * 0.04;
  const Pose2Gaussian g(Pose2(0, 0, 0), C);
  for (const Pose2& s : g.sample(rng, 100)) {
    EXPECT_NEAR(s.x(), s.y(), 1e-12);
    EXPECT_NEAR(s.phi(), 0.0, 1e-12);
  }
}

// ---- Validation ---------------------------------------------------------------

TEST(PdfGaussian, InvalidCovarianceRejected) {
  Eigen::Matrix3d nan = Eigen::Matrix3d::Identity();
  nan(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Pose2Gaussian(Pose2(), nan), InvalidArgument);
  Eigen::Matrix3d asym = Eigen::Matrix3d::Identity();
  asym(0, 1) = 0.5;
  EXPECT_THROW(Pose2Gaussian(Pose2(), asym), InvalidArgument);
  const Eigen::Matrix3d negative = Eigen::Vector3d(1.0, -0.1, 1.0).asDiagonal();
  EXPECT_THROW(Pose2Gaussian(Pose2(), negative), InvalidArgument);
  Pose3Gaussian::Matrix indefinite = Pose3Gaussian::Matrix::Identity();
  indefinite(0, 1) = indefinite(1, 0) = 2.0;  // eigenvalue −1
  EXPECT_THROW(Pose3Gaussian(Pose3(), indefinite), InvalidArgument);
  EXPECT_THROW(Pose3GaussianInf(Pose3(), indefinite), InvalidArgument);
  EXPECT_THROW(Pose3QuatGaussian(Pose3Quat(), Pose3QuatGaussian::Matrix::Constant(
                                                  std::numeric_limits<double>::infinity())),
               InvalidArgument);
  // Round-off sized asymmetry and negativity are accepted.
  Eigen::Matrix3d rounding = Eigen::Matrix3d::Identity();
  rounding(0, 1) = 1e-17;
  rounding(2, 2) = -1e-14;
  EXPECT_NO_THROW(Pose2Gaussian(Pose2(), rounding));
  // Singular covariance has no information form.
  EXPECT_THROW(to_information(Pose2Gaussian(Pose2())), InvalidArgument);
}

}  // namespace
}  // namespace rove
