#include <random>
#include <type_traits>
#include <utility>

#include <gtest/gtest.h>

#include "pose_test_helpers.h"
#include "rove/poses/compose.h"

namespace rove {
namespace {

using test::kDeg;
using test::near;

template <typename A, typename B>
using Plus = decltype(std::declval<const A&>() + std::declval<const B&>());
template <typename A, typename B>
using Minus = decltype(std::declval<const A&>() - std::declval<const B&>());

// MRPT's result types: pose+pose -> pose, pose+point -> point,
// point-pose -> point, pose-pose -> pose; 3D if either operand is 3D.
static_assert(std::is_same_v<Plus<Pose2, Pose2>, Pose2>);
static_assert(std::is_same_v<Plus<Pose2, Pose3>, Pose3>);
static_assert(std::is_same_v<Plus<Pose3, Pose2>, Pose3>);
static_assert(std::is_same_v<Plus<Pose3, Pose3>, Pose3>);
static_assert(std::is_same_v<Plus<Pose3Quat, Pose3Quat>, Pose3Quat>);
static_assert(std::is_same_v<Plus<Pose3Quat, Pose3>, Pose3Quat>);
static_assert(std::is_same_v<Plus<Pose3, Pose3Quat>, Pose3>);
static_assert(std::is_same_v<Plus<Pose3Quat, Pose2>, Pose3Quat>);
static_assert(std::is_same_v<Plus<Pose2, Pose3Quat>, Pose3Quat>);

static_assert(std::is_same_v<Minus<Pose2, Pose2>, Pose2>);
static_assert(std::is_same_v<Minus<Pose2, Pose3>, Pose3>);
static_assert(std::is_same_v<Minus<Pose3, Pose2>, Pose3>);
static_assert(std::is_same_v<Minus<Pose3, Pose3>, Pose3>);
static_assert(std::is_same_v<Minus<Pose3Quat, Pose3Quat>, Pose3Quat>);
static_assert(std::is_same_v<Minus<Pose3Quat, Pose3>, Pose3Quat>);
static_assert(std::is_same_v<Minus<Pose3, Pose3Quat>, Pose3>);
static_assert(std::is_same_v<Minus<Pose3Quat, Pose2>, Pose3Quat>);
static_assert(std::is_same_v<Minus<Pose2, Pose3Quat>, Pose3Quat>);

static_assert(std::is_same_v<Plus<Pose2, Point2>, Point2>);
static_assert(std::is_same_v<Plus<Pose2, Point3>, Point3>);
static_assert(std::is_same_v<Plus<Pose3, Point2>, Point3>);
static_assert(std::is_same_v<Plus<Pose3, Point3>, Point3>);
static_assert(std::is_same_v<Plus<Pose3Quat, Point2>, Point3>);
static_assert(std::is_same_v<Plus<Pose3Quat, Point3>, Point3>);

static_assert(std::is_same_v<Minus<Point2, Pose2>, Point2>);
static_assert(std::is_same_v<Minus<Point3, Pose2>, Point3>);
static_assert(std::is_same_v<Minus<Point2, Pose3>, Point3>);
static_assert(std::is_same_v<Minus<Point3, Pose3>, Point3>);
static_assert(std::is_same_v<Minus<Point2, Pose3Quat>, Point3>);
static_assert(std::is_same_v<Minus<Point3, Pose3Quat>, Point3>);

static_assert(std::is_same_v<decltype(-std::declval<Pose2>()), Pose2>);
static_assert(std::is_same_v<decltype(-std::declval<Pose3>()), Pose3>);
static_assert(std::is_same_v<decltype(-std::declval<Pose3Quat>()), Pose3Quat>);

static_assert(std::is_same_v<ComposeResult<Pose2, Point3>, Point3>);
static_assert(std::is_same_v<InverseComposeResult<Point2, Pose3Quat>, Point3>);

// A pose minus a point or a 2D += 3D is not defined.
template <typename A, typename B>
concept CanMinus = requires(const A& a, const B& b) { a - b; };
template <typename A, typename B>
concept CanPlusAssign = requires(A& a, const B& b) { a += b; };
static_assert(!CanMinus<Pose2, Point2>);
static_assert(!CanMinus<Pose3, Point3>);
static_assert(CanPlusAssign<Pose3, Pose2>);
static_assert(CanPlusAssign<Pose3, Pose3Quat>);
static_assert(CanPlusAssign<Pose3Quat, Pose3>);
static_assert(CanPlusAssign<Pose3Quat, Pose2>);
static_assert(CanPlusAssign<Pose2, Pose2>);
static_assert(CanPlusAssign<Pose3, Pose3>);
static_assert(CanPlusAssign<Pose3Quat, Pose3Quat>);
static_assert(!CanPlusAssign<Pose2, Pose3>);
static_assert(!CanPlusAssign<Pose2, Pose3Quat>);

// Every mix must equal the computation on Pose3 / Point3 (the reference).
TEST(Compose, EveryMixAgreesWithPose3) {
  std::mt19937_64 rng(41);
  for (int i = 0; i < 100; ++i) {
    const Pose2 p2 = test::random_pose2(rng);
    const Pose3 p3 = test::random_pose3(rng);
    const Pose3Quat pq = test::random_pose3_quat(rng);
    const Point2 t2 = test::random_point2(rng);
    const Point3 t3 = test::random_point3(rng);
    const Pose3 P2(p2), Pq(pq);
    constexpr double tol = 1e-12;

    EXPECT_TRUE(near(Pose3(p2 + p2), P2 + P2, tol));
    EXPECT_TRUE(near(p2 + p3, P2 + p3, tol));
    EXPECT_TRUE(near(p3 + p2, p3 + P2, tol));
    EXPECT_TRUE(near(Pose3(pq + p3), Pq + p3, tol));
    EXPECT_TRUE(near(p3 + pq, p3 + Pq, tol));
    EXPECT_TRUE(near(Pose3(pq + p2), Pq + P2, tol));
    EXPECT_TRUE(near(Pose3(p2 + pq), P2 + Pq, tol));

    EXPECT_TRUE(near(Pose3(p2 - p2), P2 - P2, tol));
    EXPECT_TRUE(near(p2 - p3, P2 - p3, tol));
    EXPECT_TRUE(near(p3 - p2, p3 - P2, tol));
    EXPECT_TRUE(near(Pose3(pq - p3), Pq - p3, tol));
    EXPECT_TRUE(near(p3 - pq, p3 - Pq, tol));
    EXPECT_TRUE(near(Pose3(pq - p2), Pq - P2, tol));
    EXPECT_TRUE(near(Pose3(p2 - pq), P2 - Pq, tol));

    EXPECT_TRUE(near(Point3(p2 + t2), P2 + Point3(t2), tol));
    EXPECT_TRUE(near(p2 + t3, P2 + t3, tol));
    EXPECT_TRUE(near(p3 + t2, p3 + Point3(t2), tol));
    EXPECT_TRUE(near(pq + t2, Pq + Point3(t2), tol));
    EXPECT_TRUE(near(Point3(t2 - p2), Point3(t2) - P2, tol));
    EXPECT_TRUE(near(t3 - p2, t3 - P2, tol));
    EXPECT_TRUE(near(t2 - p3, Point3(t2) - p3, tol));
    EXPECT_TRUE(near(t2 - pq, Point3(t2) - Pq, tol));

    Pose3 a = p3;
    a += p2;
    EXPECT_TRUE(near(a, p3 + P2, tol));
    a = p3;
    a += pq;
    EXPECT_TRUE(near(a, p3 + Pq, tol));
    a = p3;
    a -= pq;
    EXPECT_TRUE(near(a, p3 - Pq, tol));
    Pose3Quat b = pq;
    b += p3;
    EXPECT_TRUE(near(Pose3(b), Pq + p3, tol));
    b = pq;
    b -= p3;
    EXPECT_TRUE(near(Pose3(b), Pq - p3, tol));
    b = pq;
    b += p2;
    EXPECT_TRUE(near(Pose3(b), Pq + P2, tol));
    b = pq;
    b -= p2;
    EXPECT_TRUE(near(Pose3(b), Pq - P2, tol));
    a = p3;
    a -= p2;
    EXPECT_TRUE(near(a, p3 - P2, tol));
  }
}

TEST(Compose, NamedFunctionsEqualOperators) {
  std::mt19937_64 rng(42);
  const Pose2 p2 = test::random_pose2(rng);
  const Pose3 p3 = test::random_pose3(rng);
  const Pose3Quat pq = test::random_pose3_quat(rng);
  const Point3 t3 = test::random_point3(rng);
  EXPECT_EQ(compose(p2, p3), p2 + p3);
  EXPECT_EQ(compose(pq, t3), pq + t3);
  EXPECT_EQ(compose(p3, pq), p3 + pq);
  EXPECT_EQ(inverse_compose(p3, p2), p3 - p2);
  EXPECT_EQ(inverse_compose(t3, pq), t3 - pq);
  EXPECT_EQ(inverse(pq), -pq);
  EXPECT_EQ(inverse(p3), p3.inverse());
}

TEST(Compose, MrptTutorialExampleWithEveryRepresentation) {
  const Point3 L(0, 4, 2);
  const Pose2 R(2, 1, 45 * kDeg);
  const Pose3 C(0.5, 0.5, 1.5, -90 * kDeg, 0, -90 * kDeg);
  const Point3 expected(-3.0355339059327378, -0.5, 0.20710678118654752);
  EXPECT_TRUE(near(L - (R + C), expected, 1e-5));
  EXPECT_TRUE(near(L - (Pose3(R) + C), expected, 1e-5));
  EXPECT_TRUE(near(L - (R + Pose3Quat(C)), expected, 1e-5));
  EXPECT_TRUE(near(L - Pose3Quat(R + C), expected, 1e-5));
  EXPECT_TRUE(near(R + C + (L - (R + C)), L, 1e-9));
  EXPECT_TRUE(near((L - R) - C, L - (R + C), 1e-12));
}

}  // namespace
}  // namespace rove

#include "rove/poses/lie_conversion.h"

namespace rove {
namespace {

TEST(LieConversion, RoundTripsAndAgreesOnProducts) {
  std::mt19937_64 rng(43);
  for (int i = 0; i < 100; ++i) {
    const Pose2 a2 = test::random_pose2(rng), b2 = test::random_pose2(rng);
    EXPECT_TRUE(near(to_pose2(to_se2(a2)), a2, 1e-12));
    EXPECT_TRUE(to_se2(a2).matrix().isApprox(a2.matrix(), 1e-12));
    EXPECT_TRUE(near(to_pose2(to_se2(a2) * to_se2(b2)), a2 + b2, 1e-12));
    EXPECT_TRUE(near(to_pose2(to_se2(b2).inverse() * to_se2(a2)), a2 - b2, 1e-12));

    const Pose3 a3 = test::random_pose3(rng), b3 = test::random_pose3(rng);
    EXPECT_TRUE(to_se3(a3).matrix().isApprox(a3.matrix(), 1e-12));
    EXPECT_TRUE(near(to_pose3(to_se3(a3)), a3, 1e-12));
    EXPECT_TRUE(near(to_pose3(to_se3(a3) * to_se3(b3)), a3 + b3, 1e-12));
    EXPECT_TRUE(near(to_pose3(to_se3(b3).inverse() * to_se3(a3)), a3 - b3, 1e-12));

    const Pose3Quat q = test::random_pose3_quat(rng);
    EXPECT_TRUE(near(to_pose3_quat(to_se3(q)), q, 1e-12));
    EXPECT_TRUE(to_se3(q).matrix().isApprox(q.matrix(), 1e-12));
  }
}

}  // namespace
}  // namespace rove
