// Tests of rove/math/quaternion.h: SLERP against the SO(3) geodesic
// q0·exp(t·log(q0⁻¹q1)), its endpoints, constant angular velocity, shortest
// path, the near-0° and near-180° cases, and input checks.

#include "rove/math/quaternion.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "lie_test_utils.h"
#include "rove/math/so3.h"

namespace rove::test {
namespace {

template <typename T>
class QuaternionTest : public ::testing::Test {};
TYPED_TEST_SUITE(QuaternionTest, ScalarTypes);

// Same rotation up to the sign of the quaternion.
template <typename T>
::testing::AssertionResult same_rotation(const Quaternion<T>& a, const Quaternion<T>& b,
                                         double tol) {
  const double d = std::min((a.coeffs() - b.coeffs()).norm(), (a.coeffs() + b.coeffs()).norm());
  if (d <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "quaternion distance " << d << " > " << tol << ": "
                                       << a.coeffs().transpose() << " vs "
                                       << b.coeffs().transpose();
}

template <typename T>
std::vector<Quaternion<T>> random_quaternions(unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<Quaternion<T>> out;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector4d v(normal(rng), normal(rng), normal(rng), normal(rng));
    v.normalize();
    out.emplace_back(Quaternion<T>(v.cast<T>()).normalized());
  }
  return out;
}

TYPED_TEST(QuaternionTest, MatchesGeodesicAndEndpoints) {
  using T = TypeParam;
  const double tol = round_trip_tol<T>() * 5;
  const auto q0s = random_quaternions<T>(1, 50);
  const auto q1s = random_quaternions<T>(2, 50);
  for (std::size_t i = 0; i < q0s.size(); ++i) {
    const SO3<T> R0(q0s[i]);
    const SO3<T> R1(q1s[i]);
    const Vector3<T> w = (R0.inverse() * R1).log();  // shortest rotation, |w| ≤ π
    EXPECT_TRUE(same_rotation(slerp(q0s[i], q1s[i], T(0)), q0s[i], tol));
    EXPECT_TRUE(same_rotation(slerp(q0s[i], q1s[i], T(1)), q1s[i], tol));
    for (double t : {0.1, 0.25, 0.5, 0.8}) {
      const Quaternion<T> s = slerp(q0s[i], q1s[i], T(t));
      EXPECT_NEAR(s.norm(), 1.0, 4 * std::numeric_limits<T>::epsilon());
      const SO3<T> expected = R0 * SO3<T>::exp(Vector3<T>(T(t) * w));
      EXPECT_TRUE(same_rotation(s, expected.quaternion(), tol)) << "t = " << t;
    }
  }
}

TYPED_TEST(QuaternionTest, ConstantAngularVelocity) {
  using T = TypeParam;
  const double tol = std::is_same_v<T, float> ? 1e-4 : 1e-12;
  const auto q0s = random_quaternions<T>(3, 30);
  const auto q1s = random_quaternions<T>(4, 30);
  for (std::size_t i = 0; i < q0s.size(); ++i) {
    const double total = rotation_angle_between(q0s[i], q1s[i]);
    EXPECT_LE(total, std::numbers::pi + 1e-6);  // shortest path
    for (int k = 0; k <= 10; ++k) {
      const double t = k / 10.0;
      const Quaternion<T> s = slerp(q0s[i], q1s[i], T(t));
      EXPECT_NEAR(rotation_angle_between(q0s[i], s), t * total, tol * (1 + total));
      EXPECT_NEAR(rotation_angle_between(s, q1s[i]), (1 - t) * total, tol * (1 + total));
    }
  }
}

TYPED_TEST(QuaternionTest, ShortestPathIgnoresQuaternionSign) {
  using T = TypeParam;
  const Quaternion<T> q0 = SO3<T>::rot_z(T(0.2)).quaternion();
  const Quaternion<T> q1 = SO3<T>::rot_z(T(1.0)).quaternion();
  const Quaternion<T> q1_neg(-q1.coeffs());
  for (double t : {0.0, 0.3, 0.7, 1.0}) {
    const Quaternion<T> a = slerp(q0, q1, T(t));
    const Quaternion<T> b = slerp(q0, q1_neg, T(t));
    EXPECT_TRUE(same_rotation(a, b, round_trip_tol<T>()));
    // The path goes the short way round z: angle 0.2 + 0.8 t.
    EXPECT_NEAR(SO3<T>(a).log().z(), 0.2 + 0.8 * t, round_trip_tol<T>() * 10);
  }
}

TYPED_TEST(QuaternionTest, NearZeroAngle) {
  using T = TypeParam;
  const Quaternion<T> q0 = SO3<T>::exp(Vector3<T>(T(0.3), T(-0.4), T(0.5))).quaternion();
  // Identical inputs return the input.
  EXPECT_TRUE(same_rotation(slerp(q0, q0, T(0.37)), q0, 4 * std::numeric_limits<T>::epsilon()));
  // A tiny rotation apart: the result lies on the geodesic.
  const Vector3<T> w(T(1e-9), T(2e-9), T(-1e-9));
  const Quaternion<T> q1 = (SO3<T>(q0) * SO3<T>::exp(w)).quaternion();
  const Quaternion<T> s = slerp(q0, q1, T(0.5));
  const Quaternion<T> expected = (SO3<T>(q0) * SO3<T>::exp(Vector3<T>(T(0.5) * w))).quaternion();
  EXPECT_TRUE(same_rotation(s, expected, 4 * std::numeric_limits<T>::epsilon()));
  EXPECT_NEAR(s.norm(), 1.0, 4 * std::numeric_limits<T>::epsilon());
}

TYPED_TEST(QuaternionTest, NearHalfTurn) {
  using T = TypeParam;
  const Vector3<T> axis = Vector3<T>(T(1), T(2), T(-2)).normalized();
  const Quaternion<T> q0 = Quaternion<T>::Identity();
  const double margin = std::is_same_v<T, float> ? 1e-3 : 1e-7;
  const double theta = std::numbers::pi - margin;
  const Quaternion<T> q1 = SO3<T>::exp(Vector3<T>(T(theta) * axis)).quaternion();
  for (double t : {0.25, 0.5, 0.75}) {
    const Quaternion<T> s = slerp(q0, q1, T(t));
    const Quaternion<T> expected = SO3<T>::exp(Vector3<T>(T(t * theta) * axis)).quaternion();
    EXPECT_TRUE(same_rotation(s, expected, round_trip_tol<T>() * 10)) << t;
  }
  // Exactly 180° apart: any half-way point is a 90° rotation about ±axis.
  const Quaternion<T> half_turn(T(0), axis.x(), axis.y(), axis.z());
  const Quaternion<T> s = slerp(q0, half_turn, T(0.5));
  const Vector3<T> w = SO3<T>(s).log();
  EXPECT_NEAR(w.norm(), std::numbers::pi / 2, round_trip_tol<T>() * 10);
  EXPECT_NEAR(std::abs(w.normalized().dot(axis)), 1.0, round_trip_tol<T>() * 10);
}

TYPED_TEST(QuaternionTest, RejectsBadInput) {
  using T = TypeParam;
  const Quaternion<T> q0 = Quaternion<T>::Identity();
  const Quaternion<T> q1 = SO3<T>::rot_x(T(1)).quaternion();
  const T nan = std::numeric_limits<T>::quiet_NaN();
  EXPECT_THROW(slerp(q0, q1, T(-0.01)), InvalidArgument);
  EXPECT_THROW(slerp(q0, q1, T(1.01)), InvalidArgument);
  EXPECT_THROW(slerp(q0, q1, nan), InvalidArgument);
  EXPECT_THROW(slerp(Quaternion<T>(nan, 0, 0, 0), q1, T(0.5)), InvalidArgument);
  EXPECT_THROW(slerp(q0, Quaternion<T>(T(2), 0, 0, 0), T(0.5)), InvalidArgument);
  EXPECT_THROW(rotation_angle_between(q0, Quaternion<T>(T(0.5), 0, 0, 0)), InvalidArgument);
}

TYPED_TEST(QuaternionTest, NormalizedOrThrow) {
  using T = TypeParam;
  const Quaternion<T> q(T(2), T(0), T(-2), T(1));
  const Quaternion<T> n = normalized_or_throw(q);
  EXPECT_NEAR(n.norm(), 1.0, 4 * std::numeric_limits<T>::epsilon());
  EXPECT_TRUE(matrices_near(n.coeffs() * T(3), q.coeffs(), round_trip_tol<T>()));
  EXPECT_THROW(normalized_or_throw(Quaternion<T>(0, 0, 0, 0)), InvalidArgument);
  EXPECT_THROW(normalized_or_throw(Quaternion<T>(std::numeric_limits<T>::infinity(), 0, 0, 0)),
               InvalidArgument);
}

}  // namespace
}  // namespace rove::test
