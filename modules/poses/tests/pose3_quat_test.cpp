#include <cmath>
#include <limits>
#include <random>
#include <sstream>

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

TEST(Pose3Quat, NormalizesAndMakesRealPartNonNegative) {
  const Pose3Quat p(1, 2, 3, 2, 0, 0, 0);
  EXPECT_EQ(p.quaternion().coeffs(), Eigen::Quaterniond::Identity().coeffs());
  const Pose3Quat q(0, 0, 0, -1, 1, -1, 1);  // norm 2, w < 0 -> negated
  EXPECT_DOUBLE_EQ(q.qw(), 0.5);
  EXPECT_DOUBLE_EQ(q.qx(), -0.5);
  EXPECT_DOUBLE_EQ(q.qy(), 0.5);
  EXPECT_DOUBLE_EQ(q.qz(), -0.5);
  const Pose3Quat tiny(0, 0, 0, 1e-200, 0, 1e-200, 0);  // rescaled without underflow
  EXPECT_NEAR(tiny.qw(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(tiny.qy(), std::sqrt(0.5), 1e-15);
  const Pose3Quat e(Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond(0, 0, 0, 3));
  EXPECT_EQ(e.quaternion().coeffs(), Eigen::Vector4d(0, 0, 1, 0));  // (x, y, z, w) order
  EXPECT_EQ(e.translation(), Eigen::Vector3d(1, 2, 3));
  Eigen::Matrix<double, 7, 1> v;
  v << 1, 2, 3, 0, 0, 0, 1;
  EXPECT_EQ(e.to_vector(), v);
  EXPECT_EQ(Pose3Quat(), Pose3Quat(0, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(Pose3Quat::identity(), Pose3Quat());
}

TEST(Pose3Quat, RejectsZeroAndNonFiniteQuaternions) {
  EXPECT_THROW(Pose3Quat(0, 0, 0, 0, 0, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3Quat(0, 0, 0, kNan, 0, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3Quat(0, 0, 0, 1, kInf, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3Quat(kNan, 0, 0, 1, 0, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3Quat(0, 0, kInf, 1, 0, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3Quat(Eigen::Vector3d::Zero(), Eigen::Quaterniond(0, 0, 0, 0)),
               InvalidArgument);
  EXPECT_THROW(Pose3Quat(Eigen::Vector3d(0, kNan, 0), Eigen::Quaterniond::Identity()),
               InvalidArgument);
  // Huge components overflow the squared norm but not the norm.
  EXPECT_NO_THROW(Pose3Quat(0, 0, 0, 1e300, 1e300, 0, 0));
}

TEST(Pose3Quat, QuaternionFromYawPitchRollIsMrptFormula) {
  std::mt19937_64 rng(31);
  for (int i = 0; i < 200; ++i) {
    const Pose3 p = test::random_pose3(rng);
    const Pose3Quat q(p);
    const YawPitchRoll a = p.yaw_pitch_roll();
    // Same rotation as the matrix (up to the sign of q).
    const Eigen::Quaterniond ref(p.rotation());
    EXPECT_NEAR(std::abs(q.quaternion().dot(ref)), 1.0, 1e-12);
    // Exactly the half-angle products of MRPT's getAsQuaternion.
    const double cy = std::cos(a.yaw / 2), sy = std::sin(a.yaw / 2);
    const double cp = std::cos(a.pitch / 2), sp = std::sin(a.pitch / 2);
    const double cr = std::cos(a.roll / 2), sr = std::sin(a.roll / 2);
    EXPECT_NEAR(q.qw(), cr * cp * cy + sr * sp * sy, 1e-15);
    EXPECT_NEAR(q.qx(), sr * cp * cy - cr * sp * sy, 1e-15);
    EXPECT_NEAR(q.qy(), cr * sp * cy + sr * cp * sy, 1e-15);
    EXPECT_NEAR(q.qz(), cr * cp * sy - sr * sp * cy, 1e-15);
  }
  // As in MRPT, the converted quaternion keeps the formula's sign: here w < 0.
  const Pose3Quat neg(Pose3(0, 0, 0, 170 * kDeg, -80 * kDeg, 170 * kDeg));
  EXPECT_LT(neg.qw(), 0.0);
  // Composition renormalizes to w >= 0 (MRPT's crossProduct).
  EXPECT_GE((neg + Pose3Quat()).qw(), 0.0);
}

TEST(Pose3Quat, RoundTripsWithPose3) {
  std::mt19937_64 rng(32);
  for (int i = 0; i < 200; ++i) {
    const Pose3 p = test::random_pose3(rng);
    EXPECT_TRUE(near(Pose3(Pose3Quat(p)), p, 1e-14));
    const Pose3Quat q = test::random_pose3_quat(rng);
    EXPECT_TRUE(near(Pose3Quat(Pose3(q)), q, 1e-14));
    EXPECT_TRUE(q.rotation().isApprox(q.quaternion().toRotationMatrix(), 1e-14));
    EXPECT_TRUE(Pose3(q).matrix().isApprox(q.matrix(), 1e-15));
    EXPECT_TRUE(near(Pose3Quat(q.matrix()), q, 1e-14));
    const YawPitchRoll a = q.yaw_pitch_roll();
    EXPECT_TRUE(near(Pose3(q.x(), q.y(), q.z(), a.yaw, a.pitch, a.roll), Pose3(q), 1e-13));
  }
  // Near gimbal lock.
  for (const double pitch : {kPi / 2 - 1e-7, -kPi / 2 + 1e-7, kPi / 2, -kPi / 2}) {
    const Pose3 p(1, 2, 3, 0.5, pitch, -0.25);
    EXPECT_TRUE(near(Pose3(Pose3Quat(p)), p, 1e-9)) << pitch;
  }
}

TEST(Pose3Quat, OperatorsAgreeWithPose3) {
  std::mt19937_64 rng(33);
  for (int i = 0; i < 200; ++i) {
    const Pose3Quat a = test::random_pose3_quat(rng), b = test::random_pose3_quat(rng);
    const Pose3 A(a), B(b);
    EXPECT_TRUE(near(Pose3(a + b), A + B, 1e-12));
    EXPECT_TRUE(near(Pose3(a - b), A - B, 1e-12));
    EXPECT_TRUE(near(Pose3(-a), -A, 1e-12));
    EXPECT_TRUE(near(Pose3(a.inverse()), A.inverse(), 1e-12));
    EXPECT_GE((a + b).qw(), 0.0);
    EXPECT_GE((a - b).qw(), 0.0);
    EXPECT_NEAR((a + b).quaternion().norm(), 1.0, 1e-15);
    const Point3 p = test::random_point3(rng);
    EXPECT_TRUE(near(a + p, A + p, 1e-12));
    EXPECT_TRUE(near(p - a, p - A, 1e-12));
    const Point2 p2 = test::random_point2(rng);
    EXPECT_TRUE(near(a + p2, A + Point3(p2), 1e-12));
    EXPECT_TRUE(near(p2 - a, Point3(p2) - A, 1e-12));
  }
}

TEST(Pose3Quat, GroupProperties) {
  std::mt19937_64 rng(34);
  for (int i = 0; i < 200; ++i) {
    const Pose3Quat a = test::random_pose3_quat(rng), b = test::random_pose3_quat(rng),
                    c = test::random_pose3_quat(rng);
    EXPECT_TRUE(near((a + b) + c, a + (b + c), 1e-12));
    EXPECT_TRUE(near(a + (b - a), b, 1e-12));
    EXPECT_TRUE(near((a + b) - a, b, 1e-12));  // a^-1 (a b) = b
    EXPECT_TRUE(near(a + (-a), Pose3Quat(), 1e-12));
    EXPECT_TRUE(near(a.inverse() + a, Pose3Quat(), 1e-12));
    const Point3 p = test::random_point3(rng);
    EXPECT_TRUE(near(a + (p - a), p, 1e-12));
    EXPECT_TRUE(near((a + p) - a, p, 1e-12));
    Pose3Quat d = a;
    d += b;
    EXPECT_EQ(d, a + b);
    d -= b;
    EXPECT_EQ(d, (a + b) - b);
  }
}

TEST(Pose3Quat, InverseConjugatesWithoutChangingSign) {
  const Pose3Quat p(1, 0, 0, std::cos(0.25), 0, 0, std::sin(0.25));  // yaw 0.5 rad
  const Pose3Quat inv = p.inverse();
  EXPECT_DOUBLE_EQ(inv.qw(), p.qw());
  EXPECT_DOUBLE_EQ(inv.qz(), -p.qz());
  EXPECT_NEAR(inv.x(), -std::cos(0.5), 1e-15);
  EXPECT_NEAR(inv.y(), std::sin(0.5), 1e-15);
}

TEST(Pose3Quat, PrintsAsMrpt) {
  const Pose3Quat p(1, 2, 3, 1, 0, 0, 0);
  EXPECT_EQ(to_string(p), "(x,y,z,qr,qx,qy,qz)=(1.0000,2.0000,3.0000,1.0000,0.0000,0.0000,0.0000)");
  std::ostringstream os;
  os << Pose3Quat(0.5, -0.25, 0, 0, 0, 0, 1);
  EXPECT_EQ(os.str(), "(x,y,z,qr,qx,qy,qz)=(0.5000,-0.2500,0.0000,0.0000,0.0000,0.0000,1.0000)");
  EXPECT_EQ(fmt::format("{}", p), to_string(p));
}

TEST(Pose3Quat, StringFormsAsMrpt) {
  const Pose3Quat p(1, 2, 3, 0.5, 0.5, 0.5, 0.5);
  EXPECT_EQ(p.as_string(), "[1.000000 2.000000 3.000000 0.500000 0.500000 0.500000 0.500000]");
  EXPECT_EQ(Pose3Quat::from_string("[1 2 3 0.5 0.5 0.5 0.5]"), p);
  EXPECT_EQ(Pose3Quat::from_string("[1 2 3 1 1 1 1]"), p);  // normalized
  EXPECT_TRUE(near(Pose3Quat::from_string(p.as_string()), p, 1e-9));
  try {
    (void)Pose3Quat::from_string("[1 2 3 0 0 0 0]");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "qw qx qy qz");
  }
  try {
    (void)Pose3Quat::from_string("[1 2 3 1 0 0]");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "qz");
  }
}

}  // namespace
}  // namespace rove
