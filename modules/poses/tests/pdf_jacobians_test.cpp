// Every analytic Jacobian of pdf_jacobians.h and pdf_euler_quat.h against
// central numeric differentiation.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "pdf_test_util.h"
#include "rove/core/error.h"
#include "rove/poses/pdf_euler_quat.h"
#include "rove/poses/pdf_jacobians.h"

namespace rove {
namespace {

using pdf_test::numeric_jacobian;
using Vec = Eigen::VectorXd;

constexpr double kTol = 1e-7;

Pose2 pose2_of(const Vec& v) { return Pose2(v[0], v[1], v[2]); }
Pose3 pose3_of(const Vec& v) { return Pose3(v[0], v[1], v[2], v[3], v[4], v[5]); }
Pose3Quat quat_of(const Vec& v) { return Pose3Quat(v[0], v[1], v[2], v[3], v[4], v[5], v[6]); }
Vec vec(const Pose2& p) { return p.to_vector(); }
Vec vec(const Pose3& p) { return p.to_vector(); }
Vec vec(const Pose3Quat& p) { return p.to_vector(); }

std::vector<Pose2> some_pose2() {
  return {Pose2(1.0, 2.0, 0.3), Pose2(-0.5, 3.0, 2.9), Pose2(4.0, -1.0, -2.5), Pose2(0, 0, 0)};
}

std::vector<Pose3> some_pose3() {
  return {Pose3(1.0, 2.0, -0.5, 0.3, 0.2, -0.1), Pose3(-0.5, 3.0, 1.0, 2.9, -1.1, 2.8),
          Pose3(4.0, -1.0, 0.2, -2.5, 0.9, -2.9), Pose3(0.1, 0.2, 0.3, 3.0, -0.4, -3.0)};
}

std::vector<Pose3Quat> some_pose3_quat() {
  std::vector<Pose3Quat> out;
  for (const Pose3& p : some_pose3()) out.emplace_back(p.translation(), p.quaternion());
  // 150° about z twice: the product has w < 0 and is re-signed by the pose type.
  out.emplace_back(1.0, -2.0, 0.5, std::cos(75.0 * kPi / 180), 0.0, 0.0,
                   std::sin(75.0 * kPi / 180));
  return out;
}

TEST(PdfJacobians, Pose2ComposeInverseAndInverseCompose) {
  for (const Pose2& a : some_pose2())
    for (const Pose2& b : some_pose2()) {
      const PairJacobians<3> J = jacobians_compose(a, b);
      const auto Na = numeric_jacobian([&](const Vec& v) { return vec(pose2_of(v) + b); },
                                       vec(a), {2});
      const auto Nb = numeric_jacobian([&](const Vec& v) { return vec(a + pose2_of(v)); },
                                       vec(b), {2});
      EXPECT_LT((J.d_a - Na).cwiseAbs().maxCoeff(), kTol);
      EXPECT_LT((J.d_b - Nb).cwiseAbs().maxCoeff(), kTol);

      const PairJacobians<3> I = jacobians_inverse_compose(a, b);
      const auto Ia = numeric_jacobian([&](const Vec& v) { return vec(pose2_of(v) - b); },
                                       vec(a), {2});
      const auto Ib = numeric_jacobian([&](const Vec& v) { return vec(a - pose2_of(v)); },
                                       vec(b), {2});
      EXPECT_LT((I.d_a - Ia).cwiseAbs().maxCoeff(), kTol);
      EXPECT_LT((I.d_b - Ib).cwiseAbs().maxCoeff(), kTol);
    }
  for (const Pose2& a : some_pose2()) {
    const auto N = numeric_jacobian([&](const Vec& v) { return vec(-pose2_of(v)); }, vec(a), {2});
    EXPECT_LT((jacobian_inverse(a) - N).cwiseAbs().maxCoeff(), kTol);
  }
}

TEST(PdfJacobians, Pose2InverseMatchesMrptClosedForm) {
  // MRPT's CPosePDFGaussian::inverse Jacobian written out by hand.
  const Pose2 a(1.5, -2.0, 0.7);
  const double c = std::cos(0.7), s = std::sin(0.7);
  Eigen::Matrix3d H;
  H << -c, -s, 1.5 * s - (-2.0) * c, s, -c, 1.5 * c + (-2.0) * s, 0, 0, -1;
  EXPECT_LT((jacobian_inverse(a) - H).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PdfJacobians, Pose3ComposeInverseAndInverseCompose) {
  const std::vector<int> angles = {3, 4, 5};
  for (const Pose3& a : some_pose3())
    for (const Pose3& b : some_pose3()) {
      const PairJacobians<6> J = jacobians_compose(a, b);
      const auto Na = numeric_jacobian([&](const Vec& v) { return vec(pose3_of(v) + b); },
                                       vec(a), angles);
      const auto Nb = numeric_jacobian([&](const Vec& v) { return vec(a + pose3_of(v)); },
                                       vec(b), angles);
      EXPECT_LT((J.d_a - Na).cwiseAbs().maxCoeff(), 1e-6);
      EXPECT_LT((J.d_b - Nb).cwiseAbs().maxCoeff(), 1e-6);

      const PairJacobians<6> I = jacobians_inverse_compose(a, b);
      const auto Ia = numeric_jacobian([&](const Vec& v) { return vec(pose3_of(v) - b); },
                                       vec(a), angles);
      const auto Ib = numeric_jacobian([&](const Vec& v) { return vec(a - pose3_of(v)); },
                                       vec(b), angles);
      EXPECT_LT((I.d_a - Ia).cwiseAbs().maxCoeff(), 1e-6);
      EXPECT_LT((I.d_b - Ib).cwiseAbs().maxCoeff(), 1e-6);
    }
  for (const Pose3& a : some_pose3()) {
    const auto N =
        numeric_jacobian([&](const Vec& v) { return vec(pose3_of(v).inverse()); }, vec(a), angles);
    EXPECT_LT((jacobian_inverse(a) - N).cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(PdfJacobians, Pose3QuatComposeInverseAndInverseCompose) {
  for (const Pose3Quat& a : some_pose3_quat())
    for (const Pose3Quat& b : some_pose3_quat()) {
      const PairJacobians<7> J = jacobians_compose(a, b);
      const auto Na = numeric_jacobian([&](const Vec& v) { return vec(quat_of(v) + b); }, vec(a));
      const auto Nb = numeric_jacobian([&](const Vec& v) { return vec(a + quat_of(v)); }, vec(b));
      EXPECT_LT((J.d_a - Na).cwiseAbs().maxCoeff(), kTol);
      EXPECT_LT((J.d_b - Nb).cwiseAbs().maxCoeff(), kTol);

      const PairJacobians<7> I = jacobians_inverse_compose(a, b);
      const auto Ia = numeric_jacobian([&](const Vec& v) { return vec(quat_of(v) - b); }, vec(a));
      const auto Ib = numeric_jacobian([&](const Vec& v) { return vec(a - quat_of(v)); }, vec(b));
      EXPECT_LT((I.d_a - Ia).cwiseAbs().maxCoeff(), kTol);
      EXPECT_LT((I.d_b - Ib).cwiseAbs().maxCoeff(), kTol);
    }
  for (const Pose3Quat& a : some_pose3_quat()) {
    const auto N =
        numeric_jacobian([&](const Vec& v) { return vec(quat_of(v).inverse()); }, vec(a));
    EXPECT_LT((jacobian_inverse(a) - N).cwiseAbs().maxCoeff(), kTol);
  }
}

TEST(PdfJacobians, SignFlippedCompositionKeepsRowsConsistent) {
  // 150° + 150° about z: the raw product has w < 0; the result is re-signed.
  const Pose3Quat a(0, 0, 0, std::cos(75.0 * kPi / 180), 0, 0, std::sin(75.0 * kPi / 180));
  const Pose3Quat r = a + a;
  EXPECT_GE(r.qw(), 0.0);
  const PairJacobians<7> J = jacobians_compose(a, a);
  const auto N = numeric_jacobian([&](const Vec& v) { return vec(quat_of(v) + a); }, vec(a));
  EXPECT_LT((J.d_a - N).cwiseAbs().maxCoeff(), kTol);
}

TEST(PdfJacobians, YprToQuat) {
  for (const Pose3& p : some_pose3()) {
    const YawPitchRoll a = p.yaw_pitch_roll();
    Eigen::Matrix<double, 4, 3> J;
    const Eigen::Vector4d q = ypr_to_quat(a.yaw, a.pitch, a.roll, &J);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    const auto N = numeric_jacobian(
        [](const Vec& v) { return Vec(ypr_to_quat(v[0], v[1], v[2])); },
        Eigen::Vector3d(a.yaw, a.pitch, a.roll));
    EXPECT_LT((J - N).cwiseAbs().maxCoeff(), kTol);
    // Same rotation as the pose.
    EXPECT_LT((quat_to_rotation(q) - p.rotation()).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(PdfJacobians, QuatToYprIncludesNormalization) {
  for (const Pose3& p : some_pose3()) {
    const Eigen::Quaterniond qe = p.quaternion();
    const Eigen::Vector4d q = 1.3 * Eigen::Vector4d(qe.w(), qe.x(), qe.y(), qe.z());
    Eigen::Matrix<double, 3, 4> J;
    const Eigen::Vector3d ypr = quat_to_ypr(q, &J);
    const YawPitchRoll a = p.yaw_pitch_roll();
    EXPECT_NEAR(wrap_to_pi(ypr[0] - a.yaw), 0.0, 1e-12);
    EXPECT_NEAR(ypr[1], a.pitch, 1e-12);
    EXPECT_NEAR(wrap_to_pi(ypr[2] - a.roll), 0.0, 1e-12);
    const auto N = numeric_jacobian([](const Vec& v) { return Vec(quat_to_ypr(v)); }, Vec(q),
                                    {0, 1, 2});
    EXPECT_LT((J - N).cwiseAbs().maxCoeff(), kTol);
  }
}

TEST(PdfJacobians, QuatToYprGimbalLockAsMrpt) {
  // pitch = +90°: q = (cos, 0, sin, 0)(π/4) rotated by yaw 0.4 about z.
  const Eigen::Vector4d q = ypr_to_quat(0.4, kPi / 2, 0.0);
  Eigen::Matrix<double, 3, 4> J;
  const Eigen::Vector3d ypr = quat_to_ypr(q, &J);
  EXPECT_NEAR(ypr[1], kPi / 2, 1e-15);
  EXPECT_EQ(ypr[2], 0.0);
  EXPECT_NEAR(ypr[0], -2.0 * std::atan2(q[1], q[0]), 1e-15);
  EXPECT_NEAR(wrap_to_pi(ypr[0] - 0.4), 0.0, 1e-9);
  EXPECT_TRUE(J.row(1).isZero(0.0));
  EXPECT_TRUE(J.row(2).isZero(0.0));
}

TEST(PdfJacobians, QuatHelpers) {
  const Eigen::Vector4d q(0.9, 0.1, -0.3, 0.2);
  const Eigen::Vector3d v(0.5, -1.0, 2.0);
  const auto N = numeric_jacobian([](const Vec& x) { return Vec(x / x.norm()); }, Vec(q));
  EXPECT_LT((quat_normalization_jacobian(q) - N).cwiseAbs().maxCoeff(), kTol);
  const auto R = numeric_jacobian([&](const Vec& x) { return Vec(quat_to_rotation(x) * v); },
                                  Vec(q));
  EXPECT_LT((quat_rotate_jacobian(q, v) - R).cwiseAbs().maxCoeff(), kTol);
  const Eigen::Vector4d b(0.2, 0.7, 0.1, -0.4);
  EXPECT_LT((quat_left_matrix(q) * b - quat_right_matrix(b) * q).cwiseAbs().maxCoeff(), 1e-15);
  // Hamilton product agrees with Eigen's.
  const Eigen::Quaterniond eq = Eigen::Quaterniond(q[0], q[1], q[2], q[3]) *
                                Eigen::Quaterniond(b[0], b[1], b[2], b[3]);
  EXPECT_LT((quat_product(q, b) - Eigen::Vector4d(eq.w(), eq.x(), eq.y(), eq.z())).norm(), 1e-15);
  EXPECT_THROW(quat_normalization_jacobian(Eigen::Vector4d::Zero()), InvalidArgument);
  EXPECT_THROW(quat_to_ypr(Eigen::Vector4d::Zero()), InvalidArgument);
}

TEST(PdfJacobians, ConversionJacobians) {
  for (const Pose3& p : some_pose3()) {
    const auto N6 = numeric_jacobian([](const Vec& v) { return vec(Pose3Quat(pose3_of(v))); },
                                     vec(p));
    EXPECT_LT((jacobian_pose3_to_quat(p) - N6).cwiseAbs().maxCoeff(), kTol);
    const Pose3Quat q(p);
    const auto N7 = numeric_jacobian([](const Vec& v) { return vec(Pose3(quat_of(v))); }, vec(q),
                                     {3, 4, 5});
    EXPECT_LT((jacobian_quat_to_pose3(q) - N7).cwiseAbs().maxCoeff(), kTol);
    // Euler → quaternion → Euler is the identity to first order.
    const Eigen::Matrix<double, 6, 6> I = jacobian_quat_to_pose3(q) * jacobian_pose3_to_quat(p);
    EXPECT_LT((I - Eigen::Matrix<double, 6, 6>::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  }
}

}  // namespace
}  // namespace rove
