#include "rove/bayes/kalman.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "rove/bayes/distributions.h"
#include "rove/bayes/random.h"
#include "rove/core/error.h"

namespace rove {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

MatrixXd random_matrix(Rng& rng, int r, int c) {
  MatrixXd m(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) m(i, j) = rng.normal();
  return m;
}
MatrixXd random_spd(Rng& rng, int n, double scale) {
  const MatrixXd a = random_matrix(rng, n, n);
  return scale * (a * a.transpose() + 0.5 * MatrixXd::Identity(n, n));
}
// A sample of N(mean, cov).
VectorXd draw(Rng& rng, const VectorXd& mean, const MatrixXd& cov) {
  const MatrixXd L = cov.llt().matrixL();
  VectorXd e(mean.size());
  for (Eigen::Index i = 0; i < e.size(); ++i) e[i] = rng.normal();
  return mean + L * e;
}

struct Linear {
  MatrixXd F, Q, H, R;
  VectorXd b;
  VectorXd transition(const VectorXd& x) const { return F * x + b; }
  MatrixXd transition_jacobian(const VectorXd&) const { return F; }
  MatrixXd process_noise(const VectorXd&) const { return Q; }
  VectorXd observe(const VectorXd& x) const { return H * x; }
  MatrixXd observation_jacobian(const VectorXd&) const { return H; }
  MatrixXd observation_noise(const VectorXd&) const { return R; }
};

// The textbook linear Kalman filter, written independently of rove's code:
// explicit inverse, short-form covariance update.
struct ReferenceKalman {
  VectorXd x;
  MatrixXd P;
  void predict(const Linear& m) {
    x = m.F * x + m.b;
    P = m.F * P * m.F.transpose() + m.Q;
  }
  void update(const Linear& m, const VectorXd& z) {
    const MatrixXd S = m.H * P * m.H.transpose() + m.R;
    const MatrixXd K = P * m.H.transpose() * S.inverse();
    x = x + K * (z - m.H * x);
    P = (MatrixXd::Identity(x.size(), x.size()) - K * m.H) * P;
  }
};

Linear random_linear(Rng& rng, int n, int m) {
  Linear l;
  l.F = MatrixXd::Identity(n, n) + 0.2 * random_matrix(rng, n, n);
  l.Q = random_spd(rng, n, 0.05);
  l.H = random_matrix(rng, m, n);
  l.R = random_spd(rng, m, 0.1);
  l.b = random_matrix(rng, n, 1);
  return l;
}

TEST(Kalman, EkfEqualsTheLinearKalmanFilterOnALinearModel) {
  Rng rng(1);
  for (const auto jacobians : {KalmanJacobians::Analytic, KalmanJacobians::Numeric}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Linear model = random_linear(rng, 4, 2);
      GaussianState g{random_matrix(rng, 4, 1), random_spd(rng, 4, 1.0)};
      ReferenceKalman ref{g.mean, g.covariance};
      KalmanOptions options;
      options.jacobians = jacobians;
      const double tol = jacobians == KalmanJacobians::Analytic ? 1e-9 : 1e-6;
      for (int step = 0; step < 20; ++step) {
        g = ekf_predict(g, model, options);
        ref.predict(model);
        const VectorXd z = random_matrix(rng, 2, 1);
        const auto r = ekf_update(g, z, model, options);
        ASSERT_TRUE(r.ok()) << r.message;
        ref.update(model, z);
        g = r.posterior;
        const double scale = 1.0 + ref.P.norm();
        EXPECT_LT((g.mean - ref.x).norm(), tol * (1.0 + ref.x.norm())) << step;
        EXPECT_LT((g.covariance - ref.P).norm(), tol * scale) << step;
        // Innovation and its covariance are exposed and consistent with NIS.
        EXPECT_NEAR(r.nis, r.innovation.dot(r.innovation_covariance.inverse() * r.innovation),
                    1e-8 * (1 + r.nis));
      }
      // The IEKF on a linear model converges at its second linearization to
      // the same answer.
      const VectorXd z = random_matrix(rng, 2, 1);
      const auto e = ekf_update(g, z, model, options);
      const auto i = iekf_update(g, z, model, options);
      EXPECT_EQ(i.termination, KalmanTermination::Converged) << i.message;
      EXPECT_LE(i.iterations, jacobians == KalmanJacobians::Analytic ? 2 : 3);
      EXPECT_LT((i.posterior.mean - e.posterior.mean).norm(), tol);
      EXPECT_LT((i.posterior.covariance - e.posterior.covariance).norm(), tol);
    }
  }
}

// A robot (x, y, θ) moving on a circle, with range-bearing measurements to
// known landmarks; additive Gaussian process noise.
struct Unicycle {
  double v = 0.5, w = 0.1, dt = 1.0;
  MatrixXd Q = (VectorXd(3) << 0.03 * 0.03, 0.03 * 0.03, 0.01 * 0.01).finished().asDiagonal();
  VectorXd transition(const VectorXd& x) const {
    return (VectorXd(3) << x[0] + v * dt * std::cos(x[2]), x[1] + v * dt * std::sin(x[2]),
            x[2] + w * dt)
        .finished();
  }
  MatrixXd transition_jacobian(const VectorXd& x) const {
    MatrixXd F = MatrixXd::Identity(3, 3);
    F(0, 2) = -v * dt * std::sin(x[2]);
    F(1, 2) = v * dt * std::cos(x[2]);
    return F;
  }
  MatrixXd process_noise(const VectorXd&) const { return Q; }
};

struct RangeBearing {
  Eigen::Vector2d landmark;
  double sigma_range = 0.1, sigma_bearing = 2.0 * std::numbers::pi / 180.0;
  VectorXd observe(const VectorXd& x) const {
    const double dx = landmark.x() - x[0], dy = landmark.y() - x[1];
    return (VectorXd(2) << std::hypot(dx, dy), std::atan2(dy, dx) - x[2]).finished();
  }
  MatrixXd observation_jacobian(const VectorXd& x) const {
    const double dx = landmark.x() - x[0], dy = landmark.y() - x[1];
    const double q = dx * dx + dy * dy, r = std::sqrt(q);
    return (MatrixXd(2, 3) << -dx / r, -dy / r, 0, dy / q, -dx / q, -1).finished();
  }
  MatrixXd observation_noise(const VectorXd&) const {
    return (VectorXd(2) << sigma_range * sigma_range, sigma_bearing * sigma_bearing)
        .finished()
        .asDiagonal();
  }
  VectorXd innovation(const VectorXd& z, const VectorXd& z_pred) const {
    VectorXd d = z - z_pred;
    wrap_angles(d, {1});
    return d;
  }
};

const std::vector<Eigen::Vector2d> kLandmarks = {{5, 0}, {0, 6}, {-4, 3}, {2, -5}, {-3, -4}};

TEST(Kalman, EkfPassesNeesAndNisTestsOnRangeBearingLocalization) {
  // 50 Monte-Carlo runs of 100 steps. At each step the average NEES over the
  // runs must fall in its two-sided 95 % χ² interval (χ²(150)/50); a
  // consistent filter does so at 95 % of the steps, we require 85 %. The
  // average NIS over all 2-D updates must be within 5 % of 2.
  const int runs = 50, steps = 100;
  KalmanOptions options;
  options.angle_states = {2};
  Unicycle motion;
  std::vector<double> anees(steps, 0.0);
  double nis_sum = 0;
  int nis_count = 0;
  Rng rng(2026);
  for (int run = 0; run < runs; ++run) {
    GaussianState g{VectorXd::Zero(3), (VectorXd(3) << 0.1, 0.1, 0.01).finished().asDiagonal()};
    VectorXd truth = draw(rng, g.mean, g.covariance);
    for (int t = 0; t < steps; ++t) {
      truth = draw(rng, motion.transition(truth), motion.Q);
      g = ekf_predict(g, motion, options);
      for (const auto& l : kLandmarks) {
        RangeBearing sensor{l};
        if ((l - truth.head<2>()).norm() > 8.0) continue;
        VectorXd z = draw(rng, sensor.observe(truth), sensor.observation_noise(truth));
        const auto r = ekf_update(g, z, sensor, options);
        ASSERT_TRUE(r.ok()) << r.message;
        nis_sum += r.nis;
        ++nis_count;
        g = r.posterior;
      }
      anees[t] += nees(truth - g.mean, g.covariance, {2}) / runs;
    }
  }
  const auto interval = average_chi_square_interval(3, runs, 0.95);
  int inside = 0;
  for (double a : anees) inside += interval.contains(a);
  EXPECT_GE(inside, 85) << "steps with ANEES in [" << interval.lower << ", " << interval.upper << "]";
  EXPECT_GT(nis_count, 10000);
  EXPECT_NEAR(nis_sum / nis_count, 2.0, 0.1);
}

TEST(Kalman, NeesTestCatchesAnOverconfidentFilter) {
  // The same test fails when the filter believes its process noise is 4×
  // smaller (in σ) than it is: the test above can fail.
  const int runs = 50, steps = 100;
  KalmanOptions options;
  options.angle_states = {2};
  Unicycle motion, believed;
  believed.Q = motion.Q / 16.0;
  std::vector<double> anees(steps, 0.0);
  Rng rng(7);
  for (int run = 0; run < runs; ++run) {
    GaussianState g{VectorXd::Zero(3), (VectorXd(3) << 0.1, 0.1, 0.01).finished().asDiagonal()};
    VectorXd truth = draw(rng, g.mean, g.covariance);
    for (int t = 0; t < steps; ++t) {
      truth = draw(rng, motion.transition(truth), motion.Q);
      g = ekf_predict(g, believed, options);
      for (const auto& l : kLandmarks) {
        RangeBearing sensor{l};
        if ((l - truth.head<2>()).norm() > 8.0) continue;
        g = ekf_update(g, draw(rng, sensor.observe(truth), sensor.observation_noise(truth)), sensor,
                       options)
                .posterior;
      }
      anees[t] += nees(truth - g.mean, g.covariance, {2}) / runs;
    }
  }
  const auto interval = average_chi_square_interval(3, runs, 0.95);
  int inside = 0;
  for (double a : anees) inside += interval.contains(a);
  EXPECT_LT(inside, 50);
}

TEST(Kalman, IteratedEkfBeatsTheEkfOnAStronglyNonlinearObservation) {
  // Position (x, y) with a wide prior (σ = 1 m) and a precise range-bearing
  // fix to a landmark 4 m away: one linearization at the prior mean is far
  // off, Gauss–Newton relinearization is not. Over 2000 trials the IEKF's
  // mean squared error is below a quarter of the EKF's, and its average
  // NEES is closer to 2.
  struct PointSensor {
    RangeBearing rb{{4.0, 0.0}, 0.01, 0.002};
    VectorXd observe(const VectorXd& p) const { return rb.observe((VectorXd(3) << p, 0.0).finished()); }
    MatrixXd observation_jacobian(const VectorXd& p) const {
      return rb.observation_jacobian((VectorXd(3) << p, 0.0).finished()).leftCols(2);
    }
    MatrixXd observation_noise(const VectorXd& p) const { return rb.observation_noise(p); }
    VectorXd innovation(const VectorXd& z, const VectorXd& zp) const { return rb.innovation(z, zp); }
  } sensor;
  const GaussianState prior{VectorXd::Zero(2), MatrixXd::Identity(2, 2)};
  Rng rng(5);
  double mse_ekf = 0, mse_iekf = 0, nees_ekf = 0, nees_iekf = 0;
  const int trials = 2000;
  int converged = 0;
  for (int k = 0; k < trials; ++k) {
    const VectorXd truth = draw(rng, prior.mean, prior.covariance);
    if ((truth - sensor.rb.landmark).norm() < 1.0) {  // keep the landmark outside the cloud's core
      --k;
      continue;
    }
    const VectorXd z = draw(rng, sensor.observe(truth), sensor.observation_noise(truth));
    const auto e = ekf_update(prior, z, sensor);
    const auto i = iekf_update(prior, z, sensor);
    converged += i.termination == KalmanTermination::Converged;
    mse_ekf += (e.posterior.mean - truth).squaredNorm() / trials;
    mse_iekf += (i.posterior.mean - truth).squaredNorm() / trials;
    nees_ekf += nees(truth - e.posterior.mean, e.posterior.covariance) / trials;
    nees_iekf += nees(truth - i.posterior.mean, i.posterior.covariance) / trials;
  }
  EXPECT_LT(mse_iekf, 0.25 * mse_ekf) << mse_iekf << " vs " << mse_ekf;
  EXPECT_LT(std::abs(nees_iekf - 2.0), std::abs(nees_ekf - 2.0)) << nees_iekf << " vs " << nees_ekf;
  EXPECT_GT(converged, 0.99 * trials);
}

TEST(Kalman, GateRejectsAtTheStatedProbability) {
  // Linear model: a measurement from the model has NIS ~ χ²(2) exactly, so a
  // 95 % gate rejects 5 % of them: 1000 of 20000 ± 4 binomial σ (123).
  Rng rng(3);
  Linear model = random_linear(rng, 3, 2);
  const GaussianState prior{VectorXd::Zero(3), random_spd(rng, 3, 1.0)};
  KalmanOptions options;
  options.gate_probability = 0.95;
  const int trials = 20000;
  int rejected = 0;
  for (int k = 0; k < trials; ++k) {
    const VectorXd truth = draw(rng, prior.mean, prior.covariance);
    const VectorXd z = draw(rng, model.observe(truth), model.R);
    const auto r = ekf_update(prior, z, model, options);
    if (r.termination == KalmanTermination::Gated) {
      ++rejected;
      EXPECT_FALSE(r.applied());
      EXPECT_EQ(r.posterior.mean, prior.mean);
      EXPECT_EQ(r.posterior.covariance, prior.covariance);
      EXPECT_GT(r.nis, gate_threshold(2, 0.95));
    } else {
      EXPECT_LE(r.nis, gate_threshold(2, 0.95));
    }
  }
  EXPECT_NEAR(rejected, 0.05 * trials, 4 * std::sqrt(trials * 0.05 * 0.95));
  // An outlier 20 σ off is always rejected.
  const MatrixXd S = model.H * prior.covariance * model.H.transpose() + model.R;
  const MatrixXd L = S.llt().matrixL();
  const VectorXd off = 20.0 * L.col(0);
  for (int k = 0; k < 100; ++k) {
    const VectorXd truth = draw(rng, prior.mean, prior.covariance);
    const VectorXd z = draw(rng, model.observe(truth), model.R) + off;
    EXPECT_EQ(ekf_update(prior, z, model, options).termination, KalmanTermination::Gated);
  }
  EXPECT_NEAR(gate_threshold(2, 0.95), -2.0 * std::log(0.05), 1e-9);
}

TEST(Kalman, NumericJacobiansMatchAnalyticOnes) {
  Unicycle motion;
  RangeBearing sensor{{3.0, -2.0}};
  KalmanOptions numeric;
  numeric.jacobians = KalmanJacobians::Numeric;
  numeric.angle_states = {2};
  Rng rng(4);
  for (int k = 0; k < 50; ++k) {
    VectorXd x = (VectorXd(3) << rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3.1, 3.1)).finished();
    EXPECT_LT((transition_jacobian(motion, x, numeric) - motion.transition_jacobian(x)).norm(), 1e-7);
    EXPECT_LT((observation_jacobian(sensor, x, numeric) - sensor.observation_jacobian(x)).norm(), 1e-6);
  }
  // Across the ±π seam the wrapped difference keeps the numeric Jacobian right.
  VectorXd x(3);
  x << 0.0, 0.0, std::numbers::pi;
  RangeBearing behind{{-3.0, 1e-9}};
  EXPECT_LT((observation_jacobian(behind, x, numeric) - behind.observation_jacobian(x)).norm(), 1e-6);
}

TEST(Kalman, RejectsBadInputAndReportsNumericFailure) {
  Rng rng(6);
  Linear model = random_linear(rng, 3, 2);
  const GaussianState prior{VectorXd::Zero(3), MatrixXd::Identity(3, 3)};
  EXPECT_THROW(ekf_update(prior, (VectorXd(2) << 1.0, std::nan("")).finished(), model),
               InvalidArgument);
  EXPECT_THROW(ekf_update(prior, VectorXd::Zero(3), model), InvalidArgument);  // wrong size
  EXPECT_THROW(ekf_update(GaussianState{VectorXd::Zero(3), MatrixXd::Identity(2, 2)},
                          VectorXd::Zero(2), model),
               InvalidArgument);
  struct NoJacobian {
    VectorXd observe(const VectorXd& x) const { return x.head(1); }
    MatrixXd observation_noise(const VectorXd&) const { return MatrixXd::Identity(1, 1); }
  };
  EXPECT_THROW(ekf_update(prior, VectorXd::Zero(1), NoJacobian{}), InvalidArgument);
  KalmanOptions numeric;
  numeric.jacobians = KalmanJacobians::Numeric;
  EXPECT_TRUE(ekf_update(prior, VectorXd::Zero(1), NoJacobian{}, numeric).ok());
  Linear broken = model;
  broken.R = -10.0 * MatrixXd::Identity(2, 2);
  const auto r = ekf_update(prior, VectorXd::Zero(2), broken);
  EXPECT_EQ(r.termination, KalmanTermination::NotPositiveDefinite);
  EXPECT_FALSE(r.applied());
  EXPECT_EQ(r.posterior.mean, prior.mean);
  EXPECT_THROW(nees(VectorXd::Ones(2), -MatrixXd::Identity(2, 2)), NumericError);
  KalmanOptions bad;
  bad.gate_probability = 1.0;
  EXPECT_THROW(ekf_update(prior, VectorXd::Zero(2), model, bad), InvalidArgument);
}

TEST(Kalman, ConsistencyHelpers) {
  // χ²(150) quantiles at 0.025 and 0.975 are 117.98 and 185.80.
  const auto i = average_chi_square_interval(3, 50, 0.95);
  EXPECT_NEAR(i.lower, 117.9845 / 50, 1e-3);
  EXPECT_NEAR(i.upper, 185.8004 / 50, 1e-3);
  EXPECT_NEAR(nees((VectorXd(2) << 1.0, 2.0).finished(), (VectorXd(2) << 1.0, 4.0).finished().asDiagonal()),
              2.0, 1e-12);
  VectorXd a(2);
  a << 1.0, 3.5 * std::numbers::pi;
  wrap_angles(a, {1});
  EXPECT_NEAR(a[1], -0.5 * std::numbers::pi, 1e-12);
  a[1] = -std::numbers::pi;
  wrap_angles(a, {1});
  EXPECT_EQ(a[1], std::numbers::pi);
}

}  // namespace
}  // namespace rove
