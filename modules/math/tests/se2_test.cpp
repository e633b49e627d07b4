// Tests of rove::SE2: generic Lie-group properties (lie_test_utils.h), the
// tangent ordering [rho_x, rho_y, theta], closed forms and checked input.

#include "rove/math/se2.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "lie_test_utils.h"

namespace rove::test {
namespace {

template <typename T>
class SE2Test : public ::testing::Test {};
TYPED_TEST_SUITE(SE2Test, ScalarTypes);

TYPED_TEST(SE2Test, ExpLogRoundTrips) { check_exp_log_round_trips<SE2<TypeParam>>(); }
TYPED_TEST(SE2Test, HatVeeAndMatrixExponential) {
  check_hat_vee_and_matrix_exponential<SE2<TypeParam>>();
}
TYPED_TEST(SE2Test, GroupAxioms) { check_group_axioms<SE2<TypeParam>>(); }
TYPED_TEST(SE2Test, ActionMatchesMatrix) { check_action_matches_matrix<SE2<TypeParam>>(); }
TYPED_TEST(SE2Test, Adjoint) { check_adjoint<SE2<TypeParam>>(); }
TYPED_TEST(SE2Test, JacobiansMatchNumericDifferentiation) { check_jacobians<SE2<TypeParam>>(); }

TYPED_TEST(SE2Test, TangentOrderAndClosedForm) {
  using T = TypeParam;
  const double tol = round_trip_tol<T>();
  // ξ = [ρx, ρy, θ]: t = V(θ)·ρ with V = [[s/θ, −(1−c)/θ]; [(1−c)/θ, s/θ]].
  for (double theta : test_angles(1e-3)) {
    const SE2<T> X = SE2<T>::exp(Vector3<T>(T(2), T(-1), T(theta)));
    const double a = theta == 0 ? 1.0 : std::sin(theta) / theta;
    const double b = theta == 0 ? 0.0 : (1 - std::cos(theta)) / theta;
    EXPECT_TRUE(matrices_near(X.translation(), Eigen::Vector2d(2 * a + b, 2 * b - a), tol))
        << theta;
    EXPECT_NEAR(X.angle(), theta, tol);
  }
  // x, y, theta constructor and composition (a robot at (1, 0) facing +y
  // moving 1 m forward ends at (1, 1)).
  const SE2<T> pose(T(1), T(0), T(std::numbers::pi / 2));
  const SE2<T> step(T(1), T(0), T(0));
  EXPECT_TRUE(matrices_near((pose * step).translation(), Vector2<T>(1, 1), tol));
  EXPECT_NEAR((pose * step).angle(), std::numbers::pi / 2, tol);
  EXPECT_TRUE(matrices_near(pose.inverse().translation(), Vector2<T>(0, 1), tol));
}

TYPED_TEST(SE2Test, LogAtHalfTurn) {
  using T = TypeParam;
  // θ = π exactly and just below: V⁻¹ stays finite (h = (θ/2)cot(θ/2) → 0).
  for (double theta : {std::numbers::pi, std::numbers::pi - 1e-6, -(std::numbers::pi - 1e-6)}) {
    const SE2<T> X(T(1.5), T(-0.5), T(theta));
    const Vector3<T> xi = X.log();
    EXPECT_TRUE(xi.allFinite());
    EXPECT_TRUE(matrices_near(SE2<T>::exp(xi).matrix(), X.matrix(), round_trip_tol<T>()));
  }
}

TYPED_TEST(SE2Test, ConstructorsCheckInput) {
  using T = TypeParam;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  EXPECT_THROW(SE2<T>(nan, T(0), T(0)), InvalidArgument);
  EXPECT_THROW(SE2<T>(T(0), T(0), nan), InvalidArgument);
  EXPECT_THROW(SE2<T>::exp(Vector3<T>(0, nan, 0)), InvalidArgument);
  const SE2<T> X(T(1), T(2), T(0.3));
  EXPECT_TRUE(SE2<T>(X.matrix()).is_approx(X, T(round_trip_tol<T>())));
  Matrix3<T> bad = X.matrix();
  bad(2, 1) = T(1);
  EXPECT_THROW(SE2<T>{bad}, InvalidArgument);
}

TYPED_TEST(SE2Test, CastRoundTrip) {
  using T = TypeParam;
  const SE2<T> X(T(1), T(2), T(0.3));
  EXPECT_TRUE(matrices_near(X.template cast<double>().matrix(), X.matrix(), round_trip_tol<T>()));
  EXPECT_TRUE(X.template cast<double>().template cast<T>().is_approx(X, T(round_trip_tol<T>())));
}

}  // namespace
}  // namespace rove::test
