#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <type_traits>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "pose_test_helpers.h"
#include "rove/core/error.h"
#include "rove/poses/compose.h"

namespace rove {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(Point2, ConstructsAndConvertsToEigen) {
  const Point2 p(1.5, -2.0);
  EXPECT_EQ(p.x, 1.5);
  EXPECT_EQ(p.y, -2.0);
  EXPECT_EQ(p.to_vector(), Eigen::Vector2d(1.5, -2.0));
  EXPECT_EQ(Point2(Eigen::Vector2d(3, 4)), Point2(3, 4));
  EXPECT_EQ(Point2(), Point2(0, 0));
}

TEST(Point2, RejectsNonFinite) {
  EXPECT_THROW(Point2(kNan, 0), InvalidArgument);
  EXPECT_THROW(Point2(0, kInf), InvalidArgument);
  EXPECT_THROW(Point2(Eigen::Vector2d(-kInf, 0)), InvalidArgument);
}

TEST(Point3, RejectsNonFinite) {
  EXPECT_THROW(Point3(kNan, 0, 0), InvalidArgument);
  EXPECT_THROW(Point3(0, kInf, 0), InvalidArgument);
  EXPECT_THROW(Point3(0, 0, -kInf), InvalidArgument);
  EXPECT_THROW(Point3(Eigen::Vector3d(0, kNan, 0)), InvalidArgument);
}

TEST(Point3, ConversionsBetween2DAnd3D) {
  const Point3 p3 = Point2(1, 2);  // implicit, lossless
  EXPECT_EQ(p3, Point3(1, 2, 0));
  EXPECT_EQ(Point2(Point3(1, 2, 7)), Point2(1, 2));  // explicit, drops z
  static_assert(std::is_convertible_v<Point2, Point3>);
  static_assert(!std::is_convertible_v<Point3, Point2>);
  EXPECT_EQ(Point3(1, 2, 3).to_vector(), Eigen::Vector3d(1, 2, 3));
}

TEST(Point, ComponentArithmetic) {
  const Point2 a(1, 2), b(3, -5);
  EXPECT_EQ(a + b, Point2(4, -3));
  EXPECT_EQ(a - b, Point2(-2, 7));
  EXPECT_EQ(-a, Point2(-1, -2));
  EXPECT_EQ(a * 2.0, Point2(2, 4));
  EXPECT_EQ(0.5 * a, Point2(0.5, 1));
  Point2 c = a;
  c += b;
  EXPECT_EQ(c, Point2(4, -3));
  c -= b;
  EXPECT_EQ(c, a);
  c *= -3;
  EXPECT_EQ(c, Point2(-3, -6));

  const Point3 u(1, 2, 3), v(-1, 0.5, 4);
  EXPECT_EQ(u + v, Point3(0, 2.5, 7));
  EXPECT_EQ(u - v, Point3(2, 1.5, -1));
  EXPECT_EQ(-u, Point3(-1, -2, -3));
  EXPECT_EQ(u * 2.0, Point3(2, 4, 6));
  EXPECT_EQ(2.0 * u, Point3(2, 4, 6));
  EXPECT_EQ(u + a, Point3(2, 4, 3));
  EXPECT_EQ(a + u, Point3(2, 4, 3));
  EXPECT_EQ(u - a, Point3(0, 0, 3));
  EXPECT_EQ(a - u, Point3(0, 0, -3));
  Point3 w = u;
  w += a;
  EXPECT_EQ(w, Point3(2, 4, 3));
  w -= v;
  EXPECT_EQ(w, Point3(3, 3.5, -1));
  w *= 2;
  EXPECT_EQ(w, Point3(6, 7, -2));

  static_assert(std::is_same_v<decltype(a + b), Point2>);
  static_assert(std::is_same_v<decltype(a - b), Point2>);
  static_assert(std::is_same_v<decltype(a * 2.0), Point2>);
  static_assert(std::is_same_v<decltype(u + a), Point3>);
  static_assert(std::is_same_v<decltype(a + u), Point3>);
  static_assert(std::is_same_v<decltype(a - u), Point3>);
  static_assert(std::is_same_v<decltype(u - a), Point3>);
  static_assert(std::is_same_v<decltype(-u), Point3>);
}

TEST(Point, NormsAndDistancesMatchClosedForms) {
  EXPECT_DOUBLE_EQ(Point2(3, 4).norm(), 5.0);
  EXPECT_DOUBLE_EQ(Point2(3, 4).squared_norm(), 25.0);
  EXPECT_DOUBLE_EQ(Point3(2, 3, 6).norm(), 7.0);
  EXPECT_DOUBLE_EQ(Point3(2, 3, 6).squared_norm(), 49.0);

  const Point2 a(1, 1);
  const Point3 b(4, 5, 12);
  // Mixed 2D/3D: the 2D operand is at z = 0 (MRPT's distanceTo).
  EXPECT_DOUBLE_EQ(a.distance_to(b), 13.0);
  EXPECT_DOUBLE_EQ(b.distance_to(a), 13.0);
  EXPECT_DOUBLE_EQ(a.squared_distance_to(b), 169.0);
  EXPECT_DOUBLE_EQ(distance_2d(a, b), 5.0);
  EXPECT_DOUBLE_EQ(distance_3d(a, b), 13.0);
  EXPECT_DOUBLE_EQ(squared_distance(b, a), 169.0);
  EXPECT_DOUBLE_EQ(Point2(0, 0).distance_to(Point2(3, 4)), 5.0);
}

TEST(Point, DistancesToPosesUsePositionsOnly) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 50; ++i) {
    const Point3 p = test::random_point3(rng);
    const Pose3 q = test::random_pose3(rng);
    const Pose2 r = test::random_pose2(rng);
    const Pose3Quat s = test::random_pose3_quat(rng);
    const double dq = std::sqrt(std::pow(p.x - q.x(), 2) + std::pow(p.y - q.y(), 2) +
                                std::pow(p.z - q.z(), 2));
    EXPECT_NEAR(p.distance_to(q), dq, 1e-12);
    EXPECT_NEAR(q.distance_to(p), dq, 1e-12);
    const double dr = std::sqrt(std::pow(p.x - r.x(), 2) + std::pow(p.y - r.y(), 2) + p.z * p.z);
    EXPECT_NEAR(p.distance_to(r), dr, 1e-12);
    EXPECT_NEAR(r.distance_to(p), dr, 1e-12);
    EXPECT_NEAR(distance_2d(p, r), std::hypot(p.x - r.x(), p.y - r.y()), 1e-12);
    EXPECT_NEAR(s.distance_to(q), (s.translation() - q.translation()).norm(), 1e-12);
    EXPECT_NEAR(r.squared_distance_to(s),
                (Eigen::Vector3d(r.x(), r.y(), 0) - s.translation()).squaredNorm(), 1e-9);
    EXPECT_NEAR(q.norm(), q.translation().norm(), 1e-12);
    EXPECT_NEAR(r.norm(), std::hypot(r.x(), r.y()), 1e-12);
    EXPECT_NEAR(s.norm(), s.translation().norm(), 1e-12);
  }
}

TEST(Point, PrintsAsMrpt) {
  // MRPT's CPoint2D/CPoint3D operator<<: "(x,y[,z])" with the stream's format.
  EXPECT_EQ(to_string(Point2(1, 2.5)), "(1,2.5)");
  EXPECT_EQ(to_string(Point3(0, 4, 2)), "(0,4,2)");
  EXPECT_EQ(to_string(Point3(-3.0355339059327378, -0.5, 0.20710678118654752)),
            "(-3.03553,-0.5,0.207107)");
  std::ostringstream os;
  os.precision(3);
  os << Point2(1.23456, -0.5);
  EXPECT_EQ(os.str(), "(1.23,-0.5)");
  EXPECT_EQ(fmt::format("{}", Point2(1, 2.5)), "(1,2.5)");
  EXPECT_EQ(fmt::format("[{:>10}]", Point3(0, 4, 2)), "[   (0,4,2)]");
}

TEST(Point, StringFormsRoundTrip) {
  EXPECT_EQ(Point2(1, -2.5).as_string(), "[1.000000 -2.500000]");
  EXPECT_EQ(Point3(0, 4, 2).as_string(), "[0.000000 4.000000 2.000000]");
  EXPECT_EQ(Point2::from_string("[1 -2.5]"), Point2(1, -2.5));
  EXPECT_EQ(Point3::from_string(" [0, 4 ,2e0] "), Point3(0, 4, 2));
  EXPECT_EQ(Point3::from_string(Point3(0.25, -4, 2).as_string()), Point3(0.25, -4, 2));
}

TEST(Point, MalformedStringsNameTheField) {
  try {
    (void)Point3::from_string("[1 2]");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "z");
  }
  try {
    (void)Point2::from_string("[1 abc]");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "y");
    EXPECT_EQ(e.location().offset, 3u);
  }
  EXPECT_THROW((void)Point2::from_string("1 2"), ParseError);
  EXPECT_THROW((void)Point2::from_string("[1 2 3]"), ParseError);
  EXPECT_THROW((void)Point2::from_string("[1 nan]"), ParseError);
}

}  // namespace
}  // namespace rove
