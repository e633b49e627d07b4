#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "pose_test_helpers.h"
#include "rove/core/error.h"
#include "rove/poses/compose.h"

namespace rove {
namespace {

using test::kDeg;
using test::near;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(WrapToPi, RangeIsHalfOpenAtMinusPi) {
  EXPECT_EQ(wrap_to_pi(0.25), 0.25);  // unchanged bit for bit
  EXPECT_EQ(wrap_to_pi(-3.0), -3.0);
  EXPECT_EQ(wrap_to_pi(kPi), kPi);
  EXPECT_EQ(wrap_to_pi(-kPi), kPi);
  EXPECT_NEAR(wrap_to_pi(3 * kPi / 2), -kPi / 2, 1e-15);
  EXPECT_NEAR(wrap_to_pi(-3 * kPi / 2), kPi / 2, 1e-15);
  EXPECT_NEAR(wrap_to_pi(3 * kPi), kPi, 1e-15);
  EXPECT_NEAR(wrap_to_pi(1000.0), 1000.0 - 159 * 2 * kPi, 1e-12);
  EXPECT_NEAR(wrap_to_pi(-1000.0), -1000.0 + 159 * 2 * kPi, 1e-12);
  std::mt19937_64 rng(3);
  for (int i = 0; i < 1000; ++i) {
    const double a = test::uniform(rng, -100, 100);
    const double w = wrap_to_pi(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-12);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-12);
  }
  EXPECT_TRUE(std::isnan(wrap_to_pi(kInf)));
}

TEST(Pose2, ConstructionWrapsPhi) {
  const Pose2 p(1, 2, 3 * kPi / 2);
  EXPECT_EQ(p.x(), 1.0);
  EXPECT_EQ(p.y(), 2.0);
  EXPECT_NEAR(p.phi(), -kPi / 2, 1e-15);
  EXPECT_EQ(Pose2(0, 0, -kPi).phi(), kPi);
  EXPECT_EQ(Pose2(0, 0, 0.3).phi(), 0.3);
  EXPECT_EQ(Pose2(), Pose2(0, 0, 0));
  EXPECT_EQ(Pose2::identity(), Pose2());
  EXPECT_EQ(Pose2(Point2(3, 4)), Pose2(3, 4, 0));
  EXPECT_EQ(Pose2(1, 2, 0.5).to_vector(), Eigen::Vector3d(1, 2, 0.5));
  EXPECT_EQ(Pose2(1, 2, 0.5).translation(), Eigen::Vector2d(1, 2));
  EXPECT_EQ(Pose2(1, 2, 0.5).position(), Point2(1, 2));
}

TEST(Pose2, RejectsNonFinite) {
  EXPECT_THROW(Pose2(kNan, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose2(0, kInf, 0), InvalidArgument);
  EXPECT_THROW(Pose2(0, 0, kNan), InvalidArgument);
  EXPECT_THROW(Pose2(0, 0, -kInf), InvalidArgument);
}

TEST(Pose2, MatricesMatchClosedForm) {
  const Pose2 p(1, 2, 30 * kDeg);
  Eigen::Matrix3d T;
  T << std::sqrt(3) / 2, -0.5, 1, 0.5, std::sqrt(3) / 2, 2, 0, 0, 1;
  EXPECT_TRUE(p.matrix().isApprox(T, 1e-15));
  EXPECT_TRUE(p.rotation().isApprox(T.topLeftCorner<2, 2>(), 1e-15));
}

TEST(Pose2, ComposeMatchesClosedForms) {
  // Move 1 m forward while facing +y.
  EXPECT_TRUE(near(Pose2(1, 2, 90 * kDeg) + Pose2(1, 0, 0), Pose2(1, 3, 90 * kDeg), 1e-15));
  // Headings wrap through +-pi.
  EXPECT_TRUE(near(Pose2(0, 0, 170 * kDeg) + Pose2(0, 0, 20 * kDeg), Pose2(0, 0, -170 * kDeg),
                   1e-14));
  EXPECT_NEAR((Pose2(0, 0, 170 * kDeg) + Pose2(0, 0, 20 * kDeg)).phi(), -170 * kDeg, 1e-14);
  EXPECT_TRUE(near(Pose2(2, 1, 45 * kDeg) + Point2(1, 0),
                   Point2(2 + std::sqrt(0.5), 1 + std::sqrt(0.5)), 1e-15));
  // Point seen from a pose: inverse of the above.
  EXPECT_TRUE(near(Point2(2 + std::sqrt(0.5), 1 + std::sqrt(0.5)) - Pose2(2, 1, 45 * kDeg),
                   Point2(1, 0), 1e-15));
}

TEST(Pose2, ComposeMatchesHomogeneousMatrices) {
  std::mt19937_64 rng(11);
  for (int i = 0; i < 200; ++i) {
    const Pose2 a = test::random_pose2(rng), b = test::random_pose2(rng);
    const Eigen::Matrix3d ab = a.matrix() * b.matrix();
    const Pose2 c = a + b;
    EXPECT_TRUE(c.matrix().isApprox(ab, 1e-12)) << c.as_string();
    const Eigen::Matrix3d a_from_b = b.matrix().inverse() * a.matrix();
    EXPECT_TRUE((a - b).matrix().isApprox(a_from_b, 1e-12));
    const Point2 p = test::random_point2(rng);
    const Eigen::Vector3d g = a.matrix() * Eigen::Vector3d(p.x, p.y, 1);
    EXPECT_TRUE(near(a + p, Point2(g.x(), g.y()), 1e-12));
    const Eigen::Vector3d l = a.matrix().inverse() * Eigen::Vector3d(p.x, p.y, 1);
    EXPECT_TRUE(near(p - a, Point2(l.x(), l.y()), 1e-12));
  }
}

TEST(Pose2, GroupProperties) {
  std::mt19937_64 rng(12);
  for (int i = 0; i < 200; ++i) {
    const Pose2 a = test::random_pose2(rng), b = test::random_pose2(rng),
                c = test::random_pose2(rng);
    EXPECT_TRUE(near((a + b) + c, a + (b + c), 1e-12));
    EXPECT_TRUE(near(a + (b - a), b, 1e-12));
    EXPECT_TRUE(near((a + b) - a, b, 1e-12));  // a^-1 (a b) = b
    EXPECT_TRUE(near(a + a.inverse(), Pose2(), 1e-12));
    EXPECT_TRUE(near(-a + a, Pose2(), 1e-12));
    EXPECT_EQ(-a, a.inverse());
    EXPECT_EQ(inverse(a), a.inverse());
    EXPECT_TRUE(near(a - b, -b + a, 1e-12));
    const Point2 p = test::random_point2(rng);
    EXPECT_TRUE(near(a + (p - a), p, 1e-12));
    EXPECT_TRUE(near((a + p) - a, p, 1e-12));
    EXPECT_TRUE(near((a + b) + p, a + (b + p), 1e-12));
    Pose2 d = a;
    d += b;
    EXPECT_EQ(d, a + b);
    d -= b;
    EXPECT_EQ(d, (a + b) - b);
  }
}

TEST(Pose2, InverseAtPiStaysInRange) {
  const Pose2 p(1, 0, kPi);
  EXPECT_EQ(p.inverse().phi(), kPi);
  EXPECT_TRUE(near(p.inverse(), Pose2(1, 0, kPi), 1e-15));
}

TEST(Pose2, ConvertsToPose3LosslesslyAndBack) {
  const Pose2 p(2, 1, 45 * kDeg);
  const Pose3 q = p;  // implicit
  EXPECT_EQ(q.x(), 2.0);
  EXPECT_EQ(q.y(), 1.0);
  EXPECT_EQ(q.z(), 0.0);
  EXPECT_NEAR(q.yaw(), 45 * kDeg, 1e-15);
  EXPECT_EQ(q.pitch(), 0.0);
  EXPECT_EQ(q.roll(), 0.0);
  EXPECT_TRUE(near(Pose2(q), p, 1e-15));
  static_assert(std::is_convertible_v<Pose2, Pose3>);
  static_assert(!std::is_convertible_v<Pose3, Pose2>);
  // Explicit 3D -> 2D keeps x, y, yaw and drops the rest.
  const Pose3 r(1, 2, 3, 30 * kDeg, 10 * kDeg, -20 * kDeg);
  EXPECT_TRUE(near(Pose2(r), Pose2(1, 2, 30 * kDeg), 1e-14));
}

TEST(Pose2, PrintsAsMrpt) {
  EXPECT_EQ(to_string(Pose2(2, 1, 45 * kDeg)), "(2.000,1.000,45.00deg)");
  EXPECT_EQ(to_string(Pose2(-0.5, 1e-4, -kPi / 2)), "(-0.500,0.000,-90.00deg)");
  std::ostringstream os;
  os.precision(1);
  os << Pose2(2, 1, 45 * kDeg);
  EXPECT_EQ(os.str(), "(2.000,1.000,45.00deg)");  // independent of stream flags
  EXPECT_EQ(fmt::format("{}", Pose2(2, 1, 45 * kDeg)), "(2.000,1.000,45.00deg)");
  EXPECT_EQ(fmt::format("{:<24}|", Pose2(2, 1, 45 * kDeg)), "(2.000,1.000,45.00deg)  |");
}

TEST(Pose2, StringFormsAsMrpt) {
  EXPECT_EQ(Pose2(2, 1, 45 * kDeg).as_string(), "[2.000000 1.000000 45.000000deg]");
  EXPECT_TRUE(near(Pose2::from_string("[2 1 45]"), Pose2(2, 1, 45 * kDeg), 1e-15));
  EXPECT_TRUE(near(Pose2::from_string("[2 1 45deg]"), Pose2(2, 1, 45 * kDeg), 1e-15));
  EXPECT_TRUE(near(Pose2::from_string("  [ 2, 1, -270 ]\n"), Pose2(2, 1, 90 * kDeg), 1e-14));
  const Pose2 p(-3.25, 0.125, -30 * kDeg);
  EXPECT_TRUE(near(Pose2::from_string(p.as_string()), p, 1e-9));
}

TEST(Pose2, MalformedStringsNameTheField) {
  const auto field_of = [](std::string_view text) -> std::string {
    try {
      (void)Pose2::from_string(text);
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, "<string>");
      return e.location().field;
    }
    return "<no error>";
  };
  EXPECT_EQ(field_of("[1 2]"), "phi_deg");
  EXPECT_EQ(field_of("[1 x 3]"), "y");
  EXPECT_EQ(field_of("[1 2 3 4]"), "phi_deg");
  EXPECT_EQ(field_of("[1deg 2 3]"), "x");  // "deg" only on angles
  EXPECT_EQ(field_of("[1 2 inf]"), "phi_deg");
  EXPECT_EQ(field_of("1 2 3"), "x");
  EXPECT_EQ(field_of("[1 2 3"), "x");
  EXPECT_EQ(field_of(""), "x");
  EXPECT_EQ(field_of("[]"), "x");
}

}  // namespace
}  // namespace rove
