#include "rove/obs/motion_models.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

// MRPT's computeFromOdometry_modelGaussian, expanded by hand: with
// A = −s·Δx − c·Δy, B = c·Δx − s·Δy (c, s of Δφ/2), C = J diag(σxy², σxy², σφ²) Jᵀ
// has the entries below (the xy block's rotation cancels out).
Eigen::Matrix3d mrpt_gaussian_cov(double dx, double dy, double dphi,
                                  const GaussianMotionOptions& o) {
  const double d = std::sqrt(dx * dx + dy * dy);
  const double sxy = o.min_std_xy_m + o.a1_m_per_m * d + o.a2_m_per_rad * std::abs(dphi);
  const double sphi = o.min_std_phi_rad + o.a3_rad_per_m * d + o.a4_rad_per_rad * std::abs(dphi);
  const double c = std::cos(dphi / 2), s = std::sin(dphi / 2);
  const double A = -s * dx - c * dy, B = c * dx - s * dy;
  const double vxy = sxy * sxy, vphi = sphi * sphi;
  Eigen::Matrix3d C;
  C << vxy + A * A * vphi, A * B * vphi, A * vphi,
       A * B * vphi, vxy + B * B * vphi, B * vphi,
       A * vphi, B * vphi, vphi;
  return C;
}

TEST(GaussianMotionModel, DefaultsAreMrpt258) {
  const GaussianMotionOptions o;
  EXPECT_DOUBLE_EQ(o.a1_m_per_m, 0.01);
  EXPECT_DOUBLE_EQ(o.a2_m_per_rad, rad_to_deg(0.001));
  EXPECT_DOUBLE_EQ(o.a3_rad_per_m, deg_to_rad(1.0));
  EXPECT_DOUBLE_EQ(o.a4_rad_per_rad, 0.05);
  EXPECT_DOUBLE_EQ(o.min_std_xy_m, 0.01);
  EXPECT_DOUBLE_EQ(o.min_std_phi_rad, deg_to_rad(0.2));
  // A zero increment keeps only the minimum noise.
  const Pose2Gaussian g = gaussian_motion_model(Pose2(), o);
  const Eigen::Vector3d diag(1e-4, 1e-4, std::pow(deg_to_rad(0.2), 2));
  EXPECT_TRUE(g.covariance().isApprox(Eigen::Matrix3d(diag.asDiagonal()), 1e-14));
}

TEST(GaussianMotionModel, CovarianceMatchesMrptFormulaForThreeIncrements) {
  GaussianMotionOptions o;  // the tutorial's values, to exercise every term
  o.a1_m_per_m = 0.05;
  o.a2_m_per_rad = rad_to_deg(0.001);
  o.a3_rad_per_m = deg_to_rad(5.0);
  o.a4_rad_per_rad = 0.05;
  const double incs[3][3] = {{1.0, 0.2, deg_to_rad(10.0)},
                             {0.0, 0.0, deg_to_rad(90.0)},
                             {-0.5, 0.3, deg_to_rad(-170.0)}};
  for (const auto& u : incs) {
    const Pose2 inc(u[0], u[1], u[2]);
    const Pose2Gaussian g = gaussian_motion_model(inc, o);
    EXPECT_EQ(g.mean(), inc);
    const Eigen::Matrix3d expected = mrpt_gaussian_cov(u[0], u[1], u[2], o);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(g.covariance()(i, j), expected(i, j), 1e-15 + 1e-12 * std::abs(expected(i, j)))
            << "(" << i << "," << j << ") for increment " << inc;
      }
    }
  }
  // A value computed by hand: Δ = (1, 0, 0) with the defaults:
  // σxy = 0.01 + 0.01·1 = 0.02, σφ = 0.2° + 1° = 1.2°; A = 0, B = 1.
  const Pose2Gaussian g = gaussian_motion_model(Pose2(1.0, 0.0, 0.0), GaussianMotionOptions{});
  const double vphi = std::pow(deg_to_rad(1.2), 2);
  EXPECT_NEAR(g.covariance()(0, 0), 4e-4, 1e-16);
  EXPECT_NEAR(g.covariance()(1, 1), 4e-4 + vphi, 1e-16);
  EXPECT_NEAR(g.covariance()(1, 2), vphi, 1e-16);
  EXPECT_NEAR(g.covariance()(2, 2), vphi, 1e-16);
  EXPECT_NEAR(g.covariance()(0, 2), 0.0, 1e-18);
}

// Empirical mean/covariance of poses, angles taken relative to `ref`.
void moments(const std::vector<Pose2>& s, const Pose2& ref, Eigen::Vector3d& mean,
             Eigen::Matrix3d& cov) {
  mean.setZero();
  cov.setZero();
  std::vector<Eigen::Vector3d> d;
  d.reserve(s.size());
  for (const Pose2& p : s) d.emplace_back(p.x(), p.y(), ref.phi() + wrap_to_pi(p.phi() - ref.phi()));
  for (const auto& v : d) mean += v;
  mean /= static_cast<double>(d.size());
  for (const auto& v : d) cov += (v - mean) * (v - mean).transpose();
  cov /= static_cast<double>(d.size() - 1);
}

void expect_moments(const Eigen::Vector3d& mean, const Eigen::Matrix3d& cov,
                    const Eigen::Vector3d& mean_ref, const Eigen::Matrix3d& cov_ref, double n) {
  for (int i = 0; i < 3; ++i) {
    const double se_mean = std::sqrt(cov_ref(i, i) / n);
    EXPECT_NEAR(mean(i), mean_ref(i), 5.0 * se_mean) << "mean " << i;
    for (int j = 0; j < 3; ++j) {
      // Standard error of a sample covariance (Gaussian approximation).
      const double se = std::sqrt((cov_ref(i, i) * cov_ref(j, j) + cov_ref(i, j) * cov_ref(i, j)) / n);
      EXPECT_NEAR(cov(i, j), cov_ref(i, j), 6.0 * se) << "cov (" << i << "," << j << ")";
    }
  }
}

TEST(GaussianMotionModel, MonteCarloSamplesHaveTheModelCovariance) {
  MotionModelOptions opts;
  opts.gaussian.a1_m_per_m = 0.05;
  opts.gaussian.a3_rad_per_m = deg_to_rad(5.0);
  const RobotMovement2D move(Pose2(0.8, -0.3, deg_to_rad(25.0)), opts);
  std::mt19937_64 rng(1234);
  const int n = 100000;
  std::vector<Pose2> samples;
  for (int i = 0; i < n; ++i) samples.push_back(move.sample(rng));
  Eigen::Vector3d mean;
  Eigen::Matrix3d cov;
  moments(samples, move.mean(), mean, cov);
  const Pose2Gaussian g = move.gaussian();
  expect_moments(mean, cov, g.mean().to_vector(), g.covariance(), n);
}

// Exact moments of MRPT's Thrun sampler (derived with E[cos(a + σε)] =
// cos(a)·e^(−σ²/2), E[cos²] = (1 + cos 2a·e^(−2σ²))/2 and Stein's lemma),
// valid while φ does not wrap.
void thrun_exact_moments(const Pose2& u, const ThrunMotionOptions& o, Eigen::Vector3d& mean,
                         Eigen::Matrix3d& cov) {
  const double rot1 = std::atan2(u.y(), u.x());
  const double trans = u.norm();
  const double rot2 = wrap_to_pi(u.phi() - rot1);
  const double s1 = o.alpha1_rot_rot * std::abs(rot1) + o.alpha2_rot_trans_rad_per_m * trans;
  const double st = o.alpha3_trans_trans * trans +
                    o.alpha4_trans_rot_m_per_rad * (std::abs(rot1) + std::abs(rot2));
  const double s3 = o.alpha1_rot_rot * std::abs(rot2) + o.alpha2_rot_trans_rad_per_m * trans;
  const double e1 = std::exp(-0.5 * s1 * s1), e2 = std::exp(-2.0 * s1 * s1);
  const double t2 = trans * trans + st * st;
  const double sxy2 = o.additional_std_xy_m * o.additional_std_xy_m;
  mean << trans * std::cos(rot1) * e1, trans * std::sin(rot1) * e1, rot1 + rot2;
  cov(0, 0) = t2 * 0.5 * (1.0 + std::cos(2 * rot1) * e2) - mean(0) * mean(0) + sxy2;
  cov(1, 1) = t2 * 0.5 * (1.0 - std::cos(2 * rot1) * e2) - mean(1) * mean(1) + sxy2;
  cov(0, 1) = cov(1, 0) = t2 * 0.5 * std::sin(2 * rot1) * e2 - mean(0) * mean(1);
  cov(0, 2) = cov(2, 0) = -trans * s1 * s1 * std::sin(rot1) * e1;
  cov(1, 2) = cov(2, 1) = trans * s1 * s1 * std::cos(rot1) * e1;
  cov(2, 2) = s1 * s1 + s3 * s3 + o.additional_std_phi_rad * o.additional_std_phi_rad;
}

TEST(ThrunMotionModel, SampleMomentsMatchTheClosedForm) {
  ThrunMotionOptions o;
  o.alpha1_rot_rot = 0.1;
  o.alpha2_rot_trans_rad_per_m = 0.05;
  o.alpha3_trans_trans = 0.05;
  o.alpha4_trans_rot_m_per_rad = 0.02;
  o.additional_std_xy_m = 0.01;
  o.additional_std_phi_rad = deg_to_rad(0.5);
  for (const Pose2& u : {Pose2(1.0, 0.3, deg_to_rad(20.0)), Pose2(-0.4, 0.6, deg_to_rad(-30.0))}) {
    std::mt19937_64 rng(42);
    const int n = 200000;
    std::vector<Pose2> samples;
    for (int i = 0; i < n; ++i) samples.push_back(sample_thrun_motion(u, o, rng));
    Eigen::Vector3d mean, mean_ref;
    Eigen::Matrix3d cov, cov_ref;
    moments(samples, u, mean, cov);
    thrun_exact_moments(u, o, mean_ref, cov_ref);
    expect_moments(mean, cov, mean_ref, cov_ref, n);
  }
}

TEST(ThrunMotionModel, DefaultsAndParticles) {
  const ThrunMotionOptions o;
  EXPECT_EQ(o.particle_count, 300u);
  EXPECT_DOUBLE_EQ(o.alpha2_rot_trans_rad_per_m, deg_to_rad(4.0));
  EXPECT_DOUBLE_EQ(o.alpha4_trans_rot_m_per_rad, rad_to_deg(0.0001));
  std::mt19937_64 rng(7);
  const Pose2 u(0.5, 0.0, deg_to_rad(5.0));
  const Pose2Particles p = thrun_motion_particles(u, o, rng);
  EXPECT_EQ(p.size(), 300u);
  EXPECT_NEAR(p.mean().x(), 0.5, 0.01);
  EXPECT_NEAR(p.mean().phi(), deg_to_rad(5.0), deg_to_rad(1.0));
  // The same seed draws the same particles.
  std::mt19937_64 rng2(7);
  EXPECT_EQ(thrun_motion_particles(u, o, rng2).particles()[17].pose, p.particles()[17].pose);
}

TEST(ThrunMotionModel, ZeroNoiseReproducesTheIncrement) {
  ThrunMotionOptions o;
  o.alpha1_rot_rot = o.alpha2_rot_trans_rad_per_m = o.alpha3_trans_trans = 0.0;
  o.alpha4_trans_rot_m_per_rad = o.additional_std_xy_m = o.additional_std_phi_rad = 0.0;
  std::mt19937_64 rng(1);
  const Pose2 u(0.3, -0.4, deg_to_rad(100.0));
  const Pose2 s = sample_thrun_motion(u, o, rng);
  EXPECT_NEAR(s.x(), 0.3, 1e-15);
  EXPECT_NEAR(s.y(), -0.4, 1e-15);
  EXPECT_NEAR(s.phi(), u.phi(), 1e-15);
  // A pure rotation: δrot1 = 0, δrot2 = Δφ.
  const Pose2 r = sample_thrun_motion(Pose2(0.0, 0.0, 1.0), o, rng);
  EXPECT_EQ(r.x(), 0.0);
  EXPECT_EQ(r.phi(), 1.0);
}

TEST(MotionModels, RejectBadOptions) {
  GaussianMotionOptions g;
  g.a1_m_per_m = -0.1;
  EXPECT_THROW((void)gaussian_motion_model(Pose2(), g), InvalidArgument);
  ThrunMotionOptions t;
  t.alpha3_trans_trans = std::nan("");
  std::mt19937_64 rng(1);
  EXPECT_THROW((void)sample_thrun_motion(Pose2(), t, rng), InvalidArgument);
  ThrunMotionOptions zero;
  zero.particle_count = 0;
  EXPECT_THROW((void)thrun_motion_particles(Pose2(), zero, rng), InvalidArgument);
  MotionModelOptions bad;
  bad.gaussian.min_std_xy_m = -1.0;
  EXPECT_THROW(RobotMovement2D(Pose2(), bad), InvalidArgument);
}

TEST(RobotMovement2D, ModelSelectionAndEstimatedChange) {
  MotionModelOptions opts;
  opts.model = MotionModel::Thrun;
  RobotMovement2D m(Pose2(1.0, 0.0, 0.0), opts);
  EXPECT_EQ(m.gaussian().mean(), Pose2(1.0, 0.0, 0.0));
  std::mt19937_64 rng(3);
  EXPECT_NEAR(m.sample(rng).x(), 1.0, 0.2);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  m.estimated_pose_change = Pose2Gaussian(Pose2(2.0, 0.5, 0.1), C);
  EXPECT_EQ(m.mean(), Pose2(2.0, 0.5, 0.1));
  EXPECT_EQ(m.sample(rng), Pose2(2.0, 0.5, 0.1));
  EXPECT_EQ(m.gaussian().mean(), Pose2(2.0, 0.5, 0.1));
}

}  // namespace
}  // namespace rove
