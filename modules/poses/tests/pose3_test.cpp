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

Pose3 from_matrix(const Eigen::Matrix4d& T) { return Pose3(T); }

TEST(Pose3, RotationIsRzRyRx) {
  std::mt19937_64 rng(21);
  for (int i = 0; i < 100; ++i) {
    const double yaw = test::uniform(rng, -4, 4), pitch = test::uniform(rng, -4, 4),
                 roll = test::uniform(rng, -4, 4);
    const Pose3 p(1, 2, 3, yaw, pitch, roll);
    const Eigen::Matrix4d T = test::reference_matrix(1, 2, 3, yaw, pitch, roll);
    EXPECT_TRUE(p.matrix().isApprox(T, 1e-14));
    EXPECT_TRUE(p.rotation().isApprox(rotation_from_ypr(yaw, pitch, roll), 1e-15));
  }
  EXPECT_EQ(Pose3(), Pose3(0, 0, 0, 0, 0, 0));
  EXPECT_EQ(Pose3::identity().matrix(), Eigen::Matrix4d::Identity());
}

TEST(Pose3, PositivePitchPointsXAxisBelowXYPlane) {
  const Pose3 p(0, 0, 0, 0, 30 * kDeg, 0);
  const Point3 tip = p + Point3(1, 0, 0);
  EXPECT_LT(tip.z, 0.0);
  EXPECT_NEAR(tip.z, -0.5, 1e-15);
  EXPECT_NEAR(tip.x, std::sqrt(3) / 2, 1e-15);
  // Positive yaw turns x towards +y; positive roll turns y towards +z.
  EXPECT_TRUE(near(Pose3(0, 0, 0, 90 * kDeg, 0, 0) + Point3(1, 0, 0), Point3(0, 1, 0), 1e-15));
  EXPECT_TRUE(near(Pose3(0, 0, 0, 0, 0, 90 * kDeg) + Point3(0, 1, 0), Point3(0, 0, 1), 1e-15));
}

TEST(Pose3, YawPitchRollRoundTrip) {
  std::mt19937_64 rng(22);
  for (int i = 0; i < 500; ++i) {
    const double yaw = test::uniform(rng, -kPi + 1e-9, kPi),
                 pitch = test::uniform(rng, -kPi / 2 + 1e-3, kPi / 2 - 1e-3),
                 roll = test::uniform(rng, -kPi + 1e-9, kPi);
    const Pose3 p(0, 0, 0, yaw, pitch, roll);
    EXPECT_NEAR(p.yaw(), yaw, 1e-12);
    EXPECT_NEAR(p.pitch(), pitch, 1e-12);
    EXPECT_NEAR(p.roll(), roll, 1e-12);
    const YawPitchRoll a = p.yaw_pitch_roll();
    EXPECT_EQ(a.yaw, p.yaw());
    EXPECT_EQ(a.pitch, p.pitch());
    EXPECT_EQ(a.roll, p.roll());
  }
  // Angles out of range come back as the equivalent in-range triple.
  const Pose3 q(0, 0, 0, 200 * kDeg, 100 * kDeg, 10 * kDeg);
  EXPECT_NEAR(q.pitch(), 80 * kDeg, 1e-12);
  EXPECT_NEAR(q.yaw(), 20 * kDeg, 1e-12);
  EXPECT_NEAR(q.roll(), -170 * kDeg, 1e-12);
  EXPECT_TRUE(near(Pose3(0, 0, 0, q.yaw(), q.pitch(), q.roll()), q, 1e-12));
}

TEST(Pose3, YawPitchRollNearAndAtGimbalLock) {
  for (const double sign : {1.0, -1.0}) {
    for (const double offset : {1e-3, 1e-6, 1e-8}) {
      const double pitch = sign * (kPi / 2 - offset);
      const Pose3 p(0, 0, 0, 0.7, pitch, -0.4);
      // Close to the lock the angles are ill-conditioned, but they must still
      // rebuild the same rotation.
      const YawPitchRoll a = p.yaw_pitch_roll();
      EXPECT_NEAR(a.pitch, pitch, 1e-7);
      EXPECT_TRUE(near(Pose3(0, 0, 0, a.yaw, a.pitch, a.roll), p, 1e-9)) << offset;
    }
    // Exactly at the lock: R(2,1) = R(2,2) = 0 -> MRPT's branch, roll = 0.
    Eigen::Matrix3d R;
    const double yaw_total = 0.3;  // only yaw -/+ roll is observable
    if (sign > 0) {
      R << 0, std::sin(-yaw_total), std::cos(-yaw_total), 0, std::cos(-yaw_total),
          -std::sin(-yaw_total), -1, 0, 0;
    } else {
      R << 0, -std::sin(yaw_total), -std::cos(yaw_total), 0, std::cos(yaw_total),
          -std::sin(yaw_total), 1, 0, 0;
    }
    const Pose3 p(R, Eigen::Vector3d::Zero());
    const YawPitchRoll a = p.yaw_pitch_roll();
    EXPECT_EQ(a.roll, 0.0);
    EXPECT_NEAR(a.pitch, sign * kPi / 2, 1e-15);
    EXPECT_NEAR(a.yaw, yaw_total, 1e-15);
    EXPECT_TRUE(near(Pose3(0, 0, 0, a.yaw, a.pitch, a.roll), p, 1e-15));
  }
}

TEST(Pose3, ConstructorsValidateInput) {
  EXPECT_THROW(Pose3(kNan, 0, 0, 0, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3(0, 0, kInf, 0, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3(0, 0, 0, kNan, 0, 0), InvalidArgument);
  EXPECT_THROW(Pose3(0, 0, 0, 0, kInf, 0), InvalidArgument);
  EXPECT_THROW(Pose3(0, 0, 0, 0, 0, kNan), InvalidArgument);

  const Eigen::Matrix4d T = test::reference_matrix(1, 2, 3, 0.1, 0.2, 0.3);
  EXPECT_TRUE(from_matrix(T).matrix().isApprox(T, 1e-15));
  EXPECT_EQ(Pose3(T.topLeftCorner<3, 3>(), T.topRightCorner<3, 1>()).matrix(), T);

  Eigen::Matrix4d scaled = T;
  scaled.topLeftCorner<3, 3>() *= 1.01;
  EXPECT_THROW(from_matrix(scaled), InvalidArgument);
  Eigen::Matrix4d reflected = T;
  reflected.col(0).head<3>() *= -1.0;  // orthonormal but det = -1
  EXPECT_THROW(from_matrix(reflected), InvalidArgument);
  Eigen::Matrix4d bad_row = T;
  bad_row(3, 0) = 0.5;
  EXPECT_THROW(from_matrix(bad_row), InvalidArgument);
  Eigen::Matrix4d with_nan = T;
  with_nan(0, 3) = kNan;
  EXPECT_THROW(from_matrix(with_nan), InvalidArgument);
  EXPECT_THROW(Pose3(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, kInf, 0)), InvalidArgument);
  // A rotation rounded to 7 decimals passes the default tolerance, fails a strict one.
  const Eigen::Matrix3d rounded = (T.topLeftCorner<3, 3>() * 1e7).array().round() / 1e7;
  EXPECT_NO_THROW(Pose3(rounded, Eigen::Vector3d::Zero()));
  EXPECT_THROW(Pose3(rounded, Eigen::Vector3d::Zero(), 1e-12), InvalidArgument);
  EXPECT_THROW(Pose3(rounded, Eigen::Vector3d::Zero(), -1.0), InvalidArgument);
}

TEST(Pose3, ComposeMatchesHomogeneousMatrices) {
  std::mt19937_64 rng(23);
  for (int i = 0; i < 200; ++i) {
    const Pose3 a = test::random_pose3(rng), b = test::random_pose3(rng);
    EXPECT_TRUE((a + b).matrix().isApprox(a.matrix() * b.matrix(), 1e-12));
    EXPECT_TRUE((a - b).matrix().isApprox(b.matrix().inverse() * a.matrix(), 1e-12));
    EXPECT_TRUE(a.inverse().matrix().isApprox(a.matrix().inverse(), 1e-12));
    const Point3 p = test::random_point3(rng);
    const Eigen::Vector4d g = a.matrix() * Eigen::Vector4d(p.x, p.y, p.z, 1);
    EXPECT_TRUE(near(a + p, Point3(g.x(), g.y(), g.z()), 1e-12));
    const Eigen::Vector4d l = a.matrix().inverse() * Eigen::Vector4d(p.x, p.y, p.z, 1);
    EXPECT_TRUE(near(p - a, Point3(l.x(), l.y(), l.z()), 1e-12));
  }
}

TEST(Pose3, GroupProperties) {
  std::mt19937_64 rng(24);
  for (int i = 0; i < 200; ++i) {
    const Pose3 a = test::random_pose3(rng), b = test::random_pose3(rng),
                c = test::random_pose3(rng);
    EXPECT_TRUE(near((a + b) + c, a + (b + c), 1e-12));
    EXPECT_TRUE(near(a + (b - a), b, 1e-12));
    EXPECT_TRUE(near((a + b) - a, b, 1e-12));  // a^-1 (a b) = b
    EXPECT_TRUE(near(a + (-a), Pose3(), 1e-12));
    EXPECT_TRUE(near(a.inverse() + a, Pose3(), 1e-12));
    EXPECT_TRUE(near(a.inverse().inverse(), a, 1e-12));
    const Point3 p = test::random_point3(rng);
    EXPECT_TRUE(near(a + (p - a), p, 1e-12));
    EXPECT_TRUE(near((a + p) - a, p, 1e-12));
    EXPECT_TRUE(near((a + b) + p, a + (b + p), 1e-12));
    Pose3 d = a;
    d += b;
    EXPECT_EQ(d, a + b);
    d -= b;
    EXPECT_EQ(d, (a + b) - b);
  }
}

// The worked example of MRPT's 2D/3D geometry tutorial: a landmark L, a
// robot pose R and a camera C on the robot; the landmark as seen from the
// camera is L - (R + C).
TEST(Pose3, MrptTutorialExample) {
  const Point3 L(0, 4, 2);
  const Pose2 R(2, 1, 45 * kDeg);
  const Pose3 C(0.5, 0.5, 1.5, -90 * kDeg, 0 * kDeg, -90 * kDeg);
  const Point3 L_camera = L - (R + C);
  EXPECT_NEAR(L_camera.x, -3.03553, 1e-5);
  EXPECT_NEAR(L_camera.y, -0.5, 1e-5);
  EXPECT_NEAR(L_camera.z, 0.207106, 1e-5);
  // Closed form: the camera sits at (2, 1 + 1/sqrt(2), 1.5) with rotation
  // Rz(-45 deg) Rx(-90 deg), so L is at (1/2 - 5/sqrt(2), -1/2, 1/sqrt(2) - 1/2).
  EXPECT_NEAR(L_camera.x, 0.5 - 5 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(L_camera.y, -0.5, 1e-12);
  EXPECT_NEAR(L_camera.z, 1 / std::sqrt(2.0) - 0.5, 1e-12);
  const Point3 back = R + C + L_camera;
  EXPECT_TRUE(near(back, L, 1e-9));
}

TEST(Pose3, QuaternionAndVectorViews) {
  const Pose3 p(1, 2, 3, 0.4, -0.3, 0.2);
  const Eigen::Quaterniond q = p.quaternion();
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  EXPECT_TRUE(q.toRotationMatrix().isApprox(p.rotation(), 1e-14));
  Eigen::Matrix<double, 6, 1> v;
  v << 1, 2, 3, 0.4, -0.3, 0.2;
  EXPECT_TRUE(p.to_vector().isApprox(v, 1e-14));
  EXPECT_EQ(p.position(), Point3(1, 2, 3));
}

TEST(Pose3, PrintsAsMrpt) {
  const Pose3 p(1, 2, 3, 10 * kDeg, 20 * kDeg, 30 * kDeg);
  EXPECT_EQ(to_string(p), "(x,y,z,yaw,pitch,roll)=(1.0000,2.0000,3.0000,10.00deg,20.00deg,30.00deg)");
  std::ostringstream os;
  os << Pose3(0.5, -0.25, 1.5, -90 * kDeg, 0, -90 * kDeg);
  EXPECT_EQ(os.str(), "(x,y,z,yaw,pitch,roll)=(0.5000,-0.2500,1.5000,-90.00deg,0.00deg,-90.00deg)");
  EXPECT_EQ(fmt::format("{}", p), to_string(p));
}

TEST(Pose3, StringFormsAsMrpt) {
  const Pose3 p(1, 2, 3, 10 * kDeg, 20 * kDeg, 30 * kDeg);
  EXPECT_EQ(p.as_string(), "[1.000000 2.000000 3.000000 10.000000 20.000000 30.000000]");
  EXPECT_TRUE(near(Pose3::from_string("[1 2 3 10 20 30]"), p, 1e-15));
  EXPECT_TRUE(near(Pose3::from_string(p.as_string()), p, 1e-9));
  EXPECT_TRUE(near(Pose3::from_string("[1,2,3,10deg,20deg,30deg]"), p, 1e-15));
  const auto field_of = [](std::string_view text) -> std::string {
    try {
      (void)Pose3::from_string(text);
    } catch (const ParseError& e) {
      return e.location().field;
    }
    return "<no error>";
  };
  EXPECT_EQ(field_of("[1 2 3 10 20]"), "roll_deg");
  EXPECT_EQ(field_of("[1 2 3 10 2O 30]"), "pitch_deg");
  EXPECT_EQ(field_of("[1 2 z 10 20 30]"), "z");
  EXPECT_EQ(field_of("[1 2 3 10 20 30 40]"), "roll_deg");
  EXPECT_EQ(field_of("[1 2 3 nan 20 30]"), "yaw_deg");
}

}  // namespace
}  // namespace rove
