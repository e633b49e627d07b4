// Tests of rove::SO3: generic Lie-group properties (lie_test_utils.h), closed
// forms (Rodrigues' formula, elementary rotations), the near-π logarithm and
// the checked constructors.

#include "rove/math/so3.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "lie_test_utils.h"

namespace rove::test {
namespace {

template <typename T>
class SO3Test : public ::testing::Test {};
TYPED_TEST_SUITE(SO3Test, ScalarTypes);

TYPED_TEST(SO3Test, ExpLogRoundTrips) { check_exp_log_round_trips<SO3<TypeParam>>(); }
TYPED_TEST(SO3Test, HatVeeAndMatrixExponential) {
  check_hat_vee_and_matrix_exponential<SO3<TypeParam>>();
}
TYPED_TEST(SO3Test, GroupAxioms) { check_group_axioms<SO3<TypeParam>>(); }
TYPED_TEST(SO3Test, ActionMatchesMatrix) { check_action_matches_matrix<SO3<TypeParam>>(); }
TYPED_TEST(SO3Test, Adjoint) { check_adjoint<SO3<TypeParam>>(); }
TYPED_TEST(SO3Test, JacobiansMatchNumericDifferentiation) { check_jacobians<SO3<TypeParam>>(); }

// Rodrigues: R = I + sin θ [a]× + (1 − cos θ) [a]×², evaluated in double.
Eigen::Matrix3d rodrigues(const Eigen::Vector3d& axis, double theta) {
  Eigen::Matrix3d K;
  K << 0, -axis.z(), axis.y(), axis.z(), 0, -axis.x(), -axis.y(), axis.x(), 0;
  return Eigen::Matrix3d::Identity() + std::sin(theta) * K + (1 - std::cos(theta)) * K * K;
}

TYPED_TEST(SO3Test, ExpMatchesRodriguesAndElementaryRotations) {
  using T = TypeParam;
  const double tol = round_trip_tol<T>();
  const double a = 0.7;
  Eigen::Matrix3d Rz;
  Rz << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  EXPECT_TRUE(matrices_near(SO3<T>::rot_z(T(a)).matrix(), Rz, tol));
  Eigen::Matrix3d Rx;
  Rx << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  EXPECT_TRUE(matrices_near(SO3<T>::rot_x(T(a)).matrix(), Rx, tol));
  Eigen::Matrix3d Ry;
  Ry << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  EXPECT_TRUE(matrices_near(SO3<T>::rot_y(T(a)).matrix(), Ry, tol));

  std::mt19937 rng(3);
  for (double theta : test_angles(1e-3)) {
    const Vector3<T> w = tangent_with_angle<SO3<T>>(rng, theta);
    const Eigen::Vector3d wd = w.template cast<double>();
    const double th = wd.norm();
    const Eigen::Matrix3d expected =
        th > 0 ? rodrigues(wd / th, th) : Eigen::Matrix3d::Identity().eval();
    EXPECT_TRUE(matrices_near(SO3<T>::exp(w).matrix(), expected, tol)) << theta;
  }
}

TYPED_TEST(SO3Test, LogAngleInZeroPi) {
  using T = TypeParam;
  for (const auto& R : group_samples<SO3<T>>(1e-3)) {
    EXPECT_LE(R.log().norm(), std::numbers::pi_v<T> * (1 + 1e-6));
  }
  // A rotation vector longer than π comes back as its shorter equivalent.
  const Vector3<T> w(T(0), T(0), T(4.0));
  const Vector3<T> back = SO3<T>::exp(w).log();
  EXPECT_NEAR(back.z(), 4.0 - 2 * std::numbers::pi, round_trip_tol<T>());
}

TYPED_TEST(SO3Test, LogNearPiFromMatrix) {
  using T = TypeParam;
  // Exactly π: R = diag(1, −1, −1) is a half turn about x.
  Matrix3<T> R = Vector3<T>(1, -1, -1).asDiagonal();
  const Vector3<T> w = SO3<T>(R).log();
  EXPECT_NEAR(std::abs(w.x()), std::numbers::pi, round_trip_tol<T>());
  EXPECT_NEAR(w.y(), 0.0, round_trip_tol<T>());
  EXPECT_NEAR(w.z(), 0.0, round_trip_tol<T>());

  // Angles just below π about random axes, from an independently computed
  // matrix: the axis must come out right although sin θ ≈ 0.
  std::mt19937 rng(21);
  std::normal_distribution<double> normal;
  const double margins[] = {1e-3, 1e-5, 1e-7, 1e-9, 0.0};
  for (int i = 0; i < 50; ++i) {
    Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
    axis.normalize();
    const double theta = std::numbers::pi - margins[i % 5];
    const Eigen::Matrix3d Rd = rodrigues(axis, theta);
    const SO3<T> X(Matrix3<T>(Rd.cast<T>()));
    const Eigen::Vector3d w_log = X.log().template cast<double>();
    // Up to the sign ambiguity at exactly π, log returns θ·axis.
    const double sign = w_log.dot(axis) >= 0 ? 1.0 : -1.0;
    const double tol = std::is_same_v<T, float> ? 2e-3 : 1e-7;
    EXPECT_TRUE(matrices_near(w_log, sign * theta * axis, tol)) << "margin " << margins[i % 5];
    if (margins[i % 5] >= 1e-5 && std::is_same_v<T, double>) {
      EXPECT_GT(sign, 0.0);  // unique logarithm below π
    }
    EXPECT_TRUE(matrices_near(SO3<T>::exp(X.log()).matrix(), Rd, tol));
  }
}

TYPED_TEST(SO3Test, TinyAnglesKeepFullRelativePrecision) {
  using T = TypeParam;
  const Vector3<T> w(T(1e-9), T(-2e-9), T(3e-9));
  const Vector3<T> back = SO3<T>::exp(w).log();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(back(i) / w(i), 1.0, 1e-6);
  // Jacobians at exactly zero are the identity.
  EXPECT_TRUE(matrices_near(SO3<T>::right_jacobian(Vector3<T>::Zero()), Matrix3<T>::Identity(), 0));
  EXPECT_TRUE(matrices_near(SO3<T>::right_jacobian_inverse(Vector3<T>::Zero()),
                            Matrix3<T>::Identity(), 0));
}

TYPED_TEST(SO3Test, ConstructorsCheckInput) {
  using T = TypeParam;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T inf = std::numeric_limits<T>::infinity();
  EXPECT_THROW(SO3<T>::exp(Vector3<T>(nan, 0, 0)), InvalidArgument);
  EXPECT_THROW(SO3<T>::exp(Vector3<T>(0, inf, 0)), InvalidArgument);
  EXPECT_THROW(SO3<T>(Quaternion<T>(nan, 0, 0, 0)), InvalidArgument);
  // Norm 1.001: rejected by the checked constructor, accepted when asked to normalize.
  const Quaternion<T> q(T(1.001), T(0), T(0), T(0));
  EXPECT_THROW(SO3<T>{q}, InvalidArgument);
  EXPECT_TRUE(SO3<T>::from_unnormalized(q).is_approx(SO3<T>()));
  EXPECT_THROW(SO3<T>::from_unnormalized(Quaternion<T>(0, 0, 0, 0)), InvalidArgument);
  // Within tolerance: accepted and normalized exactly.
  const T small = kUnitTolerance<T> / 4;
  const SO3<T> R(Quaternion<T>(T(1) + small, T(0), T(0), T(0)));
  EXPECT_NEAR(R.quaternion().norm(), 1.0, 4 * std::numeric_limits<T>::epsilon());

  // Matrices: non-orthonormal and reflections rejected.
  Matrix3<T> M = SO3<T>::exp(Vector3<T>(T(0.3), T(-0.2), T(1.1))).matrix();
  EXPECT_NO_THROW(SO3<T>{M});
  Matrix3<T> bad = M;
  bad(0, 1) += T(0.01);
  EXPECT_THROW(SO3<T>{bad}, InvalidArgument);
  EXPECT_THROW(SO3<T>{Matrix3<T>(-M)}, InvalidArgument);
  bad(2, 2) = nan;
  EXPECT_THROW(SO3<T>::from_matrix_orthonormalized(bad), InvalidArgument);
  EXPECT_THROW(SO3<T>::from_matrix_orthonormalized(Matrix3<T>(-M)), InvalidArgument);
}

TYPED_TEST(SO3Test, OrthonormalizationFindsNearestRotation) {
  using T = TypeParam;
  const SO3<T> R = SO3<T>::exp(Vector3<T>(T(0.3), T(-0.2), T(1.1)));
  // Scaling by 1.1 and adding a symmetric perturbation: the polar factor is R.
  Matrix3<T> S;
  S << T(1.1), T(0.02), T(0), T(0.02), T(0.9), T(0.01), T(0), T(0.01), T(1.0);
  const SO3<T> fixed = SO3<T>::from_matrix_orthonormalized(Matrix3<T>(R.matrix() * S));
  EXPECT_TRUE(fixed.is_approx(R, T(10) * std::numeric_limits<T>::epsilon() * 100));
}

TYPED_TEST(SO3Test, ProductsStayNormalized) {
  using T = TypeParam;
  SO3<T> R;
  const SO3<T> step = SO3<T>::exp(Vector3<T>(T(0.01), T(0.02), T(-0.013)));
  for (int i = 0; i < 100000; ++i) R = R * step;
  EXPECT_NEAR(R.quaternion().norm(), 1.0, 10 * std::numeric_limits<T>::epsilon());
}

TYPED_TEST(SO3Test, CastRoundTrip) {
  using T = TypeParam;
  const SO3<T> R = SO3<T>::exp(Vector3<T>(T(0.3), T(-0.2), T(1.1)));
  const SO3<double> Rd = R.template cast<double>();
  EXPECT_TRUE(matrices_near(Rd.matrix(), R.matrix(), round_trip_tol<T>()));
  EXPECT_TRUE(Rd.template cast<T>().is_approx(R, T(round_trip_tol<T>())));
}

}  // namespace
}  // namespace rove::test
