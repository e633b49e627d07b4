// Tests of rove::SO2: generic Lie-group properties (lie_test_utils.h), angle
// wrapping, closed forms and the checked constructors.

#include "rove/math/so2.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "lie_test_utils.h"

namespace rove::test {
namespace {

template <typename T>
class SO2Test : public ::testing::Test {};
TYPED_TEST_SUITE(SO2Test, ScalarTypes);

TYPED_TEST(SO2Test, ExpLogRoundTrips) { check_exp_log_round_trips<SO2<TypeParam>>(); }
TYPED_TEST(SO2Test, HatVeeAndMatrixExponential) {
  check_hat_vee_and_matrix_exponential<SO2<TypeParam>>();
}
TYPED_TEST(SO2Test, GroupAxioms) { check_group_axioms<SO2<TypeParam>>(); }
TYPED_TEST(SO2Test, ActionMatchesMatrix) { check_action_matches_matrix<SO2<TypeParam>>(); }
TYPED_TEST(SO2Test, Adjoint) { check_adjoint<SO2<TypeParam>>(); }
TYPED_TEST(SO2Test, JacobiansMatchNumericDifferentiation) { check_jacobians<SO2<TypeParam>>(); }

TYPED_TEST(SO2Test, AnglesAddAndWrap) {
  using T = TypeParam;
  const double tol = round_trip_tol<T>();
  const SO2<T> a = SO2<T>::from_angle(T(2.5));
  const SO2<T> b = SO2<T>::from_angle(T(1.5));
  EXPECT_NEAR((a * b).angle(), 4.0 - 2 * std::numbers::pi, tol);
  EXPECT_NEAR(a.inverse().angle(), -2.5, tol);
  EXPECT_NEAR(SO2<T>::from_angle(T(std::numbers::pi - 1e-3)).angle(), std::numbers::pi - 1e-3, tol);
  EXPECT_NEAR(SO2<T>::from_angle(T(4.5)).angle(), 4.5 - 2 * std::numbers::pi, tol);
  // A half turn reports +π, never −π.
  EXPECT_EQ(SO2<T>::from_complex(T(-1), T(-0.0)).angle(), std::numbers::pi_v<T>);
  EXPECT_NEAR(SO2<T>::from_angle(T(7.0)).angle(), 7.0 - 2 * std::numbers::pi, tol);
  const Matrix2<T> R = SO2<T>::from_angle(T(0.3)).matrix();
  EXPECT_NEAR(R(0, 0), std::cos(0.3), tol);
  EXPECT_NEAR(R(1, 0), std::sin(0.3), tol);
  EXPECT_TRUE(matrices_near(SO2<T>::from_angle(T(std::numbers::pi / 2)) * Vector2<T>(1, 0),
                            Vector2<T>(0, 1), tol));
}

TYPED_TEST(SO2Test, ProductsStayNormalized) {
  using T = TypeParam;
  SO2<T> R;
  const SO2<T> step = SO2<T>::from_angle(T(0.0123));
  for (int i = 0; i < 100000; ++i) R = R * step;
  EXPECT_NEAR(R.unit_complex().norm(), 1.0, 10 * std::numeric_limits<T>::epsilon());
}

TYPED_TEST(SO2Test, ConstructorsCheckInput) {
  using T = TypeParam;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  EXPECT_THROW(SO2<T>::from_angle(nan), InvalidArgument);
  EXPECT_THROW(SO2<T>::exp(VectorN<T, 1>(std::numeric_limits<T>::infinity())), InvalidArgument);
  EXPECT_THROW(SO2<T>::from_complex(T(1.01), T(0)), InvalidArgument);
  EXPECT_NO_THROW(SO2<T>::from_complex(T(0.6), T(0.8)));
  Matrix2<T> M = SO2<T>::from_angle(T(0.4)).matrix();
  EXPECT_TRUE(SO2<T>(M).is_approx(SO2<T>::from_angle(T(0.4)), T(round_trip_tol<T>())));
  Matrix2<T> bad = M;
  bad(0, 1) += T(0.01);
  EXPECT_THROW(SO2<T>{bad}, InvalidArgument);
  bad = M;
  bad.col(0) *= T(-1);  // reflection
  EXPECT_THROW(SO2<T>{bad}, InvalidArgument);
  bad(0, 0) = nan;
  EXPECT_THROW(SO2<T>{bad}, InvalidArgument);
}

TYPED_TEST(SO2Test, CastRoundTrip) {
  using T = TypeParam;
  const SO2<T> R = SO2<T>::from_angle(T(-1.1));
  EXPECT_NEAR(R.template cast<double>().angle(), -1.1, round_trip_tol<T>());
  EXPECT_TRUE(R.template cast<double>().template cast<T>().is_approx(R, T(round_trip_tol<T>())));
}

}  // namespace
}  // namespace rove::test
