#include "rove/math/levenberg_marquardt.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rove/core/error.h"

namespace rove {
namespace {

void expect_monotone(const LmResult& r) {
  double prev = r.initial_cost;
  for (std::size_t i = 0; i < r.cost_history.size(); ++i) {
    EXPECT_LE(r.cost_history[i], prev) << "cost increased at iteration " << i + 1;
    prev = r.cost_history[i];
  }
  EXPECT_EQ(static_cast<int>(r.cost_history.size()), r.iterations);
  if (!r.cost_history.empty()) {
    EXPECT_EQ(r.cost_history.back(), r.final_cost);
  }
}

Eigen::VectorXd rosenbrock_r(const Eigen::VectorXd& x) {
  return Eigen::Vector2d(10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]);
}
Eigen::MatrixXd rosenbrock_j(const Eigen::VectorXd& x) {
  Eigen::MatrixXd J(2, 2);
  J << -20.0 * x[0], 10.0, -1.0, 0.0;
  return J;
}

TEST(LevenbergMarquardt, RosenbrockFromTheClassicStart) {
  for (LmDamping damping : {LmDamping::Marquardt, LmDamping::Levenberg}) {
    LmOptions o;
    o.damping = damping;
    o.max_iterations = 500;
    const LmResult r =
        levenberg_marquardt(rosenbrock_r, rosenbrock_j, Eigen::Vector2d(-1.2, 1.0), o);
    SCOPED_TRACE(r.message);
    EXPECT_NEAR(r.x[0], 1.0, 1e-8);
    EXPECT_NEAR(r.x[1], 1.0, 1e-8);
    EXPECT_LT(r.final_cost, 1e-18);
    EXPECT_DOUBLE_EQ(r.initial_cost, 0.5 * (4.4 * 4.4 + 2.2 * 2.2));  // r(x0) = (−4.4, 2.2)
    EXPECT_NE(r.termination, LmTermination::MaxIterations);
    EXPECT_NE(r.termination, LmTermination::NumericFailure);
    EXPECT_GT(r.accepted_steps, 5);
    expect_monotone(r);
  }
}

// y = A exp(−λ t) + noise. The optimum is found independently by variable
// projection: for fixed λ, A is linear with a closed form, leaving a 1D
// search in λ (golden section to 1e-13).
struct DecayData {
  std::vector<double> t, y;
};

DecayData make_decay_data() {
  DecayData d;
  std::mt19937_64 rng(8);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (int i = 0; i < 50; ++i) {
    const double t = 0.2 * i;
    d.t.push_back(t);
    d.y.push_back(5.0 * std::exp(-0.4 * t) + noise(rng));
  }
  return d;
}

Eigen::VectorXd decay_r(const DecayData& d, const Eigen::VectorXd& x) {
  Eigen::VectorXd r(d.t.size());
  for (std::size_t i = 0; i < d.t.size(); ++i) r[i] = x[0] * std::exp(-x[1] * d.t[i]) - d.y[i];
  return r;
}

Eigen::MatrixXd decay_j(const DecayData& d, const Eigen::VectorXd& x) {
  Eigen::MatrixXd J(d.t.size(), 2);
  for (std::size_t i = 0; i < d.t.size(); ++i) {
    const double e = std::exp(-x[1] * d.t[i]);
    J(i, 0) = e;
    J(i, 1) = -x[0] * d.t[i] * e;
  }
  return J;
}

Eigen::Vector2d decay_optimum(const DecayData& d) {
  auto best_a = [&](double lambda) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < d.t.size(); ++i) {
      const double e = std::exp(-lambda * d.t[i]);
      num += d.y[i] * e;
      den += e * e;
    }
    return num / den;
  };
  auto cost = [&](double lambda) {
    const double a = best_a(lambda);
    double c = 0;
    for (std::size_t i = 0; i < d.t.size(); ++i) {
      c += std::pow(a * std::exp(-lambda * d.t[i]) - d.y[i], 2);
    }
    return c;
  };
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double lo = 0.1, hi = 1.0;
  while (hi - lo > 1e-13) {
    const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    if (cost(m1) < cost(m2))
      hi = m2;
    else
      lo = m1;
  }
  const double lambda = 0.5 * (lo + hi);
  return {best_a(lambda), lambda};
}

TEST(LevenbergMarquardt, ExponentialDecayMatchesTheVariableProjectionOptimum) {
  const DecayData d = make_decay_data();
  const Eigen::Vector2d expected = decay_optimum(d);
  EXPECT_NEAR(expected[0], 5.0, 0.2);  // the noisy optimum is near the truth
  EXPECT_NEAR(expected[1], 0.4, 0.02);
  const auto r = levenberg_marquardt([&](const Eigen::VectorXd& x) { return decay_r(d, x); },
                                     [&](const Eigen::VectorXd& x) { return decay_j(d, x); },
                                     Eigen::Vector2d(1.0, 1.0));
  SCOPED_TRACE(r.message);
  EXPECT_NEAR(r.x[0], expected[0], 1e-6);
  EXPECT_NEAR(r.x[1], expected[1], 1e-7);
  expect_monotone(r);
  // At the optimum the gradient Jᵀr vanishes.
  const Eigen::Vector2d grad = decay_j(d, r.x).transpose() * decay_r(d, r.x);
  EXPECT_LT(grad.lpNorm<Eigen::Infinity>(), 1e-7);

  for (NumericDiffScheme scheme : {NumericDiffScheme::Forward, NumericDiffScheme::Central}) {
    LmOptions o;
    o.numeric_scheme = scheme;
    const auto rn = levenberg_marquardt([&](const Eigen::VectorXd& x) { return decay_r(d, x); },
                                        Eigen::Vector2d(1.0, 1.0), o);
    SCOPED_TRACE(rn.message);
    EXPECT_NEAR(rn.x[0], expected[0], 1e-5);
    EXPECT_NEAR(rn.x[1], expected[1], 1e-6);
    EXPECT_GT(rn.residual_evaluations, r.residual_evaluations);
    expect_monotone(rn);
  }
}

TEST(LevenbergMarquardt, NumericJacobianAgreesWithAnalytic) {
  const DecayData d = make_decay_data();
  const ResidualFunction f = [&](const Eigen::VectorXd& x) { return decay_r(d, x); };
  for (const Eigen::Vector2d& x :
       {Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(-3.0, 0.05), Eigen::Vector2d(0.0, 0.0)}) {
    const Eigen::MatrixXd exact = decay_j(d, x);
    const Eigen::VectorXd r = f(x);
    const double scale = exact.cwiseAbs().maxCoeff();
    const Eigen::MatrixXd fwd = numeric_jacobian(f, x, r, NumericDiffScheme::Forward, 1.5e-8);
    const Eigen::MatrixXd cen = numeric_jacobian(f, x, r, NumericDiffScheme::Central, 6e-6);
    EXPECT_LT((fwd - exact).cwiseAbs().maxCoeff(), 1e-6 * scale) << "x = " << x.transpose();
    EXPECT_LT((cen - exact).cwiseAbs().maxCoeff(), 1e-9 * scale) << "x = " << x.transpose();
  }
  EXPECT_THROW(numeric_jacobian(f, Eigen::Vector2d(1, 1), f(Eigen::Vector2d(1, 1)),
                                NumericDiffScheme::Central, 0.0),
               InvalidArgument);
}

TEST(LevenbergMarquardt, LinearProblemGivesTheLeastSquaresSolution) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(30, 4);
  Eigen::VectorXd b(30);
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 4; ++j) A(i, j) = g(rng) * (j + 1);
    b[i] = g(rng);
  }
  const Eigen::VectorXd expected = A.colPivHouseholderQr().solve(b);
  const auto r = levenberg_marquardt(
      [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return A * x - b; },
      [&](const Eigen::VectorXd&) -> Eigen::MatrixXd { return A; }, Eigen::VectorXd::Zero(4));
  EXPECT_LT((r.x - expected).norm(), 1e-9) << r.message;
  EXPECT_NEAR(r.final_cost, 0.5 * (A * expected - b).squaredNorm(), 1e-12);
}

TEST(LevenbergMarquardt, ParameterWithoutInfluenceStaysPut) {
  // r depends only on x₀: J has a zero column; Marquardt's floor keeps the
  // damped system solvable and x₁ unchanged.
  const auto r = levenberg_marquardt(
      [](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        return Eigen::Vector2d(x[0] - 3.0, 2.0 * (x[0] - 3.0));
      },
      Eigen::Vector2d(0.0, 7.0));
  EXPECT_NEAR(r.x[0], 3.0, 1e-9) << r.message;
  EXPECT_EQ(r.x[1], 7.0);
}

TEST(LevenbergMarquardt, NanResidualAtTheStartIsReportedByComponent) {
  const auto r = levenberg_marquardt(
      [](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        return Eigen::Vector3d(x[0], std::sqrt(x[0] - 5.0), 1.0);
      },
      Eigen::VectorXd::Constant(1, 1.0));
  EXPECT_EQ(r.termination, LmTermination::NumericFailure);
  EXPECT_NE(r.message.find("residual component 1"), std::string::npos) << r.message;
  EXPECT_TRUE(std::isnan(r.initial_cost));
  EXPECT_EQ(r.x[0], 1.0);
}

TEST(LevenbergMarquardt, NanJacobianIsReportedByEntry) {
  const auto r = levenberg_marquardt(
      rosenbrock_r,
      [](const Eigen::VectorXd& x) -> Eigen::MatrixXd {
        Eigen::MatrixXd J = rosenbrock_j(x);
        J(1, 0) = std::numeric_limits<double>::quiet_NaN();
        return J;
      },
      Eigen::Vector2d(-1.2, 1.0));
  EXPECT_EQ(r.termination, LmTermination::NumericFailure);
  EXPECT_NE(r.message.find("Jacobian entry (1, 0)"), std::string::npos) << r.message;
}

TEST(LevenbergMarquardt, NonFiniteTrialPointsAreRejectedNotAccepted) {
  // r = log x + 3: the first Gauss–Newton step from x = 1 lands at x = −2,
  // outside the domain; the solver must back off and still converge.
  int non_finite = 0;
  const auto r = levenberg_marquardt(
      [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        const double v = std::log(x[0]) + 3.0;
        if (!std::isfinite(v)) ++non_finite;
        return Eigen::VectorXd::Constant(1, v);
      },
      [](const Eigen::VectorXd& x) -> Eigen::MatrixXd {
        return Eigen::MatrixXd::Constant(1, 1, 1.0 / x[0]);
      },
      Eigen::VectorXd::Constant(1, 1.0));
  EXPECT_GT(non_finite, 0);
  EXPECT_NEAR(r.x[0], std::exp(-3.0), 1e-10) << r.message;
  EXPECT_NE(r.termination, LmTermination::NumericFailure);
  expect_monotone(r);
}

TEST(LevenbergMarquardt, StopsAtMaxIterations) {
  LmOptions o;
  o.max_iterations = 2;
  const auto r = levenberg_marquardt(rosenbrock_r, rosenbrock_j, Eigen::Vector2d(-1.2, 1.0), o);
  EXPECT_EQ(r.termination, LmTermination::MaxIterations);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_LE(r.final_cost, r.initial_cost);
  expect_monotone(r);
}

TEST(LevenbergMarquardt, StartingAtTheOptimumStopsOnTheGradient) {
  const auto r = levenberg_marquardt(rosenbrock_r, rosenbrock_j, Eigen::Vector2d(1.0, 1.0));
  EXPECT_EQ(r.termination, LmTermination::GradientTolerance);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.final_cost, 0.0);
}

TEST(LevenbergMarquardt, CostToleranceStopsOnSmallDecrease) {
  const DecayData d = make_decay_data();
  LmOptions o;
  o.gradient_tolerance = 0.0;
  o.step_tolerance = 0.0;
  o.cost_change_tolerance = 1e-3;
  const auto r = levenberg_marquardt([&](const Eigen::VectorXd& x) { return decay_r(d, x); },
                                     [&](const Eigen::VectorXd& x) { return decay_j(d, x); },
                                     Eigen::Vector2d(1.0, 1.0), o);
  EXPECT_EQ(r.termination, LmTermination::CostTolerance) << r.message;
}

TEST(LevenbergMarquardt, RejectsInvalidInput) {
  EXPECT_THROW(levenberg_marquardt(rosenbrock_r, rosenbrock_j, Eigen::VectorXd()), InvalidArgument);
  EXPECT_THROW(levenberg_marquardt(rosenbrock_r, rosenbrock_j, Eigen::Vector2d(std::nan(""), 0.0)),
               InvalidArgument);
  LmOptions o;
  o.initial_lambda = 0.0;
  EXPECT_THROW(levenberg_marquardt(rosenbrock_r, rosenbrock_j, Eigen::Vector2d(0, 0), o),
               InvalidArgument);
  o = {};
  o.numeric_relative_step = -1.0;
  EXPECT_THROW(levenberg_marquardt(rosenbrock_r, Eigen::Vector2d(0, 0), o), InvalidArgument);
  // Jacobian of the wrong shape.
  EXPECT_THROW(
      levenberg_marquardt(
          rosenbrock_r,
          [](const Eigen::VectorXd&) -> Eigen::MatrixXd { return Eigen::MatrixXd::Zero(3, 2); },
          Eigen::Vector2d(0, 0)),
      InvalidArgument);
  // Residual whose size changes between calls.
  int calls = 0;
  EXPECT_THROW(levenberg_marquardt(
                   [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
                     return Eigen::VectorXd::Constant(++calls == 1 ? 2 : 3, x[0] - 1.0);
                   },
                   Eigen::VectorXd::Constant(1, 0.0)),
               InvalidArgument);
}

TEST(LevenbergMarquardt, TerminationNames) {
  EXPECT_EQ(to_string(LmTermination::GradientTolerance), "GradientTolerance");
  EXPECT_EQ(to_string(LmTermination::StepTolerance), "StepTolerance");
  EXPECT_EQ(to_string(LmTermination::CostTolerance), "CostTolerance");
  EXPECT_EQ(to_string(LmTermination::MaxIterations), "MaxIterations");
  EXPECT_EQ(to_string(LmTermination::NumericFailure), "NumericFailure");
}

}  // namespace
}  // namespace rove
