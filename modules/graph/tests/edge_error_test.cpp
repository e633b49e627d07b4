// Analytic edge Jacobians against central differences on the manifold.
#include <random>

#include <gtest/gtest.h>

#include "graph_test_util.h"
#include "rove/graph/edge_error.h"

namespace rove {
namespace {

template <class PoseT, class RandomPose>
void check_jacobians(RandomPose random_pose) {
  constexpr int D = PoseT::kDof;
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 200; ++trial) {
    const PoseT Xi = random_pose(rng), Xj = random_pose(rng);
    // Measurements near the true relative pose (the usual regime) and far from it.
    const PoseT Z = trial % 2 ? random_pose(rng)
                              : (Xi.inverse() * Xj) * PoseT::exp(Vec::Constant(0.05));
    Mat Ji, Jj;
    edge_error(Xi, Xj, Z, &Ji, &Jj);
    Mat Ni, Nj;
    const double h = 1e-6;
    for (int k = 0; k < D; ++k) {
      Vec d = Vec::Zero();
      d(k) = h;
      Ni.col(k) = (edge_error(Xi * PoseT::exp(d), Xj, Z) - edge_error(Xi * PoseT::exp(-d), Xj, Z)) /
                  (2 * h);
      Nj.col(k) = (edge_error(Xi, Xj * PoseT::exp(d), Z) - edge_error(Xi, Xj * PoseT::exp(-d), Z)) /
                  (2 * h);
    }
    // Skip the rare draws where the error angle sits at the ±π wrap (2D) or
    // the quaternion sign flip (3D): the error is discontinuous there.
    if (!Ni.allFinite() || (Ni - Ji).cwiseAbs().maxCoeff() > 1.0) continue;
    EXPECT_LT((Ni - Ji).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
    EXPECT_LT((Nj - Jj).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
  }
}

TEST(EdgeError, Jacobians2DMatchNumeric) {
  check_jacobians<SE2d>([](std::mt19937_64& r) { return test::random_se2(r); });
}

TEST(EdgeError, Jacobians3DMatchNumeric) {
  check_jacobians<SE3d>([](std::mt19937_64& r) { return test::random_se3(r); });
}

TEST(EdgeError, ZeroWhenMeasurementMatches) {
  std::mt19937_64 rng(3);
  const SE3d a = test::random_se3(rng), b = test::random_se3(rng);
  EXPECT_LT(edge_error(a, b, a.inverse() * b).norm(), 1e-12);
  const SE2d c = test::random_se2(rng), d = test::random_se2(rng);
  EXPECT_LT(edge_error(c, d, c.inverse() * d).norm(), 1e-12);
}

TEST(EdgeError, G2oConvention3D) {
  // e = [t, q.xyz] of Z⁻¹ Xi⁻¹ Xj with w >= 0: a pure rotation of angle a
  // about z gives q.z = sin(a/2).
  const SE3d Xi;
  const SE3d Xj = SE3d(SO3d::rot_z(0.3), Eigen::Vector3d(1, 2, 3));
  const auto e = edge_error(Xi, Xj, SE3d());
  EXPECT_NEAR(e(0), 1.0, 1e-15);
  EXPECT_NEAR(e(5), std::sin(0.15), 1e-15);
  // Rotation by more than π flips the quaternion to w >= 0.
  const auto f = edge_error(Xi, SE3d(SO3d::rot_z(3.5), Eigen::Vector3d::Zero()), SE3d());
  EXPECT_NEAR(f(5), std::sin((3.5 - 2 * M_PI) / 2), 1e-12);
}

}  // namespace
}  // namespace rove
