// Tests of rove::SE3: generic Lie-group properties (lie_test_utils.h), closed
// forms (pure translations, screw motions), the tangent ordering
// (translation first) and the checked constructors.

#include "rove/math/se3.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "lie_test_utils.h"

namespace rove::test {
namespace {

template <typename T>
class SE3Test : public ::testing::Test {};
TYPED_TEST_SUITE(SE3Test, ScalarTypes);

TYPED_TEST(SE3Test, ExpLogRoundTrips) { check_exp_log_round_trips<SE3<TypeParam>>(); }
TYPED_TEST(SE3Test, HatVeeAndMatrixExponential) {
  check_hat_vee_and_matrix_exponential<SE3<TypeParam>>();
}
TYPED_TEST(SE3Test, GroupAxioms) { check_group_axioms<SE3<TypeParam>>(); }
TYPED_TEST(SE3Test, ActionMatchesMatrix) { check_action_matches_matrix<SE3<TypeParam>>(); }
TYPED_TEST(SE3Test, Adjoint) { check_adjoint<SE3<TypeParam>>(); }
TYPED_TEST(SE3Test, JacobiansMatchNumericDifferentiation) { check_jacobians<SE3<TypeParam>>(); }

TYPED_TEST(SE3Test, TangentIsTranslationFirst) {
  using T = TypeParam;
  // Pure translation.
  Vector6<T> xi;
  xi << T(1), T(-2), T(3), T(0), T(0), T(0);
  const SE3<T> X = SE3<T>::exp(xi);
  EXPECT_TRUE(matrices_near(X.translation(), Vector3<T>(1, -2, 3), 0));
  EXPECT_TRUE(X.rotation().is_approx(SO3<T>()));
  // Pure rotation about z.
  xi << T(0), T(0), T(0), T(0), T(0), T(0.5);
  EXPECT_TRUE(matrices_near(SE3<T>::exp(xi).rotation_matrix(), SO3<T>::rot_z(T(0.5)).matrix(),
                            round_trip_tol<T>()));
}

TYPED_TEST(SE3Test, ScrewMotionClosedForm) {
  using T = TypeParam;
  // ξ = [ρ; ω] with ω = θ·ẑ and ρ = (0, 0, h): rotation θ about z plus a
  // translation h along z (ρ parallel to ω is unchanged by V(ω)).
  // With ρ = (v, 0, 0) ⟂ ω: t = V·ρ = v·(sin θ/θ, (1 − cos θ)/θ, 0).
  for (double theta : test_angles(1e-3)) {
    Vector6<T> xi;
    xi << T(0), T(0), T(0.7), T(0), T(0), T(theta);
    EXPECT_TRUE(matrices_near(SE3<T>::exp(xi).translation(), Vector3<T>(0, 0, T(0.7)),
                              round_trip_tol<T>()));
    xi << T(1.5), T(0), T(0), T(0), T(0), T(theta);
    const double a = theta == 0 ? 1.0 : std::sin(theta) / theta;
    const double b = theta == 0 ? 0.0 : (1 - std::cos(theta)) / theta;
    EXPECT_TRUE(matrices_near(SE3<T>::exp(xi).translation(),
                              Eigen::Vector3d(1.5 * a, 1.5 * b, 0), round_trip_tol<T>()))
        << theta;
  }
}

TYPED_TEST(SE3Test, LogNearPi) {
  using T = TypeParam;
  std::mt19937 rng(8);
  for (double margin : {1e-2, 1e-4, 1e-6}) {
    if (std::is_same_v<T, float> && margin < 1e-3) continue;
    for (int i = 0; i < 20; ++i) {
      const Vector6<T> xi = tangent_with_angle<SE3<T>>(rng, std::numbers::pi - margin, 3.0);
      const SE3<T> X = SE3<T>::exp(xi);
      EXPECT_TRUE(matrices_near(X.log(), xi, std::is_same_v<T, float> ? 2e-3 : 1e-8));
    }
  }
  // Exactly π: exp(log(X)) = X even though the logarithm's sign is a choice.
  const SE3<T> X(Matrix3<T>(Vector3<T>(-1, -1, 1).asDiagonal()), Vector3<T>(1, 2, 3));
  EXPECT_TRUE(matrices_near(SE3<T>::exp(X.log()).matrix(), X.matrix(), round_trip_tol<T>()));
}

TYPED_TEST(SE3Test, InverseAndCompositionClosedForms) {
  using T = TypeParam;
  const SE3<T> A(SO3<T>::rot_z(T(std::numbers::pi / 2)), Vector3<T>(1, 0, 0));
  const SE3<T> B(SO3<T>(), Vector3<T>(1, 0, 0));
  // A·B: rotate (1,0,0) by 90° about z → (0,1,0), then add (1,0,0).
  EXPECT_TRUE(matrices_near((A * B).translation(), Vector3<T>(1, 1, 0), round_trip_tol<T>()));
  EXPECT_TRUE(matrices_near(A.inverse().translation(), Vector3<T>(0, 1, 0), round_trip_tol<T>()));
  EXPECT_TRUE(matrices_near(A * Vector3<T>(0, 0, 5), Vector3<T>(1, 0, 5), round_trip_tol<T>()));
}

TYPED_TEST(SE3Test, ConstructorsCheckInput) {
  using T = TypeParam;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T inf = std::numeric_limits<T>::infinity();
  Vector6<T> xi = Vector6<T>::Zero();
  xi(4) = nan;
  EXPECT_THROW(SE3<T>::exp(xi), InvalidArgument);
  xi(4) = 0;
  xi(0) = inf;
  EXPECT_THROW(SE3<T>::exp(xi), InvalidArgument);
  EXPECT_THROW(SE3<T>(SO3<T>(), Vector3<T>(0, nan, 0)), InvalidArgument);
  EXPECT_THROW(SE3<T>(Quaternion<T>(T(0.9), 0, 0, 0), Vector3<T>::Zero()), InvalidArgument);
  EXPECT_NO_THROW(SE3<T>(Quaternion<T>(1, 0, 0, 0), Vector3<T>::Zero()));
  std::mt19937 rng(1);
  Matrix4<T> M = SE3<T>::exp(tangent_with_angle<SE3<T>>(rng, 1.0)).matrix();
  EXPECT_TRUE(SE3<T>(M).is_approx(SE3<T>(M)));
  EXPECT_TRUE(matrices_near(SE3<T>(M).matrix(), M, round_trip_tol<T>()));
  Matrix4<T> bad = M;
  bad(3, 0) = T(0.5);
  EXPECT_THROW(SE3<T>{bad}, InvalidArgument);
  bad = M;
  bad(0, 0) += T(0.01);
  EXPECT_THROW(SE3<T>{bad}, InvalidArgument);
}

TYPED_TEST(SE3Test, CastAndIsApprox) {
  using T = TypeParam;
  std::mt19937 rng(4);
  const SE3<T> X = SE3<T>::exp(tangent_with_angle<SE3<T>>(rng, 1.2));
  const SE3<double> Xd = X.template cast<double>();
  EXPECT_TRUE(matrices_near(Xd.matrix(), X.matrix(), round_trip_tol<T>()));
  EXPECT_TRUE(Xd.template cast<T>().is_approx(X, T(round_trip_tol<T>())));
  Vector6<T> d = Vector6<T>::Zero();
  d(0) = T(1e-2);
  EXPECT_FALSE(X.oplus(d).is_approx(X, T(1e-3)));
  EXPECT_TRUE(X.oplus(d).is_approx(X, T(2e-2)));
}

}  // namespace
}  // namespace rove::test
