#include "rove/registration/icp_3d.h"

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "synthetic_3d.h"

namespace rove {
namespace {

using test::make_pose;
using test::pose_error;

PrepareOptions full(int threads = 1) {
  PrepareOptions o;
  o.normals = true;
  o.covariances = true;
  o.neighbors = 10;
  o.num_threads = threads;
  return o;
}

TEST(Icp3d, EveryMethodRecoversAKnownTransform) {
  const auto scene = test::room_3d(0.15);
  const Eigen::Isometry3d truth = make_pose(0.2, -0.15, 0.05, 0.02, -0.03, 0.08);
  const auto src = test::as_seen_from(test::room_3d(0.25), truth, 0.002, 1);
  const PreparedCloud3D target(scene, full());
  const PreparedCloud3D source(src, full());
  for (auto method : {Icp3dMethod::PointToPoint, Icp3dMethod::PointToPlane, Icp3dMethod::Gicp}) {
    Icp3dOptions o;
    o.method = method;
    o.max_correspondence_distance = 0.5;
    o.translation_epsilon = 1e-5;
    o.rotation_epsilon = 1e-5;
    o.max_iterations = 100;
    const auto r = icp_3d(target, source, Eigen::Isometry3d::Identity(), o);
    SCOPED_TRACE(static_cast<int>(method));
    ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
    const auto [et, er] = pose_error(r.matrix, truth.matrix());
    // Point-to-point is limited by the 15 cm sampling of the target surfaces.
    const bool p2p = method == Icp3dMethod::PointToPoint;
    EXPECT_LT(et, p2p ? 0.03 : 0.01);
    EXPECT_LT(er, p2p ? 0.01 : 3e-3);
    EXPECT_GT(r.goodness, 0.95);
    EXPECT_GT(r.conditioning, 0.01);
    EXPECT_TRUE(r.T_target_source.mean().matrix().isApprox(r.matrix, 1e-9));
    EXPECT_GT(r.T_target_source.covariance().determinant(), 0.0);
  }
}

TEST(Icp3d, SinglePlaneIsDegenerate) {
  const auto scene = test::plane_3d(0.2);
  const Eigen::Isometry3d truth = make_pose(0.1, 0.1, 0.05, 0.01, 0.01, 0.02);
  const auto src = test::as_seen_from(scene, truth, 0.0, 2);
  const PreparedCloud3D target(scene, full());
  const PreparedCloud3D source(src, full());
  for (auto method : {Icp3dMethod::PointToPoint, Icp3dMethod::PointToPlane, Icp3dMethod::Gicp}) {
    Icp3dOptions o;
    o.method = method;
    const auto r = icp_3d(target, source, Eigen::Isometry3d::Identity(), o);
    EXPECT_EQ(r.termination, RegistrationTermination::Degenerate) << r.message;
    EXPECT_LT(r.conditioning, 1e-6);
  }
}

TEST(Icp3d, ParallelEqualsSerial) {
  const auto scene = test::room_3d(0.3);
  const auto src = test::as_seen_from(scene, make_pose(0.1, 0.1, 0, 0, 0, 0.05), 0.01, 3);
  const PreparedCloud3D t1(scene, full(1)), t2(scene, full(2));
  const PreparedCloud3D s1(src, full(1)), s2(src, full(2));
  for (std::size_t i = 0; i < t1.size(); ++i) ASSERT_EQ(t1.covariances()[i], t2.covariances()[i]);
  Icp3dOptions o;
  const auto a = icp_3d(t1, s1, Eigen::Isometry3d::Identity(), o);
  o.num_threads = 2;
  const auto b = icp_3d(t2, s2, Eigen::Isometry3d::Identity(), o);
  EXPECT_EQ(a.matrix, b.matrix);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.information, b.information);
}

TEST(Icp3d, BadInputs) {
  const auto scene = test::room_3d(0.3);
  const PreparedCloud3D target(scene, full());
  const PreparedCloud3D empty(std::vector<Eigen::Vector3f>{}, full());
  EXPECT_EQ(icp_3d(target, empty, Eigen::Isometry3d::Identity()).termination,
            RegistrationTermination::InvalidInput);
  EXPECT_EQ(icp_3d(empty, target, Eigen::Isometry3d::Identity()).termination,
            RegistrationTermination::InvalidInput);
  // Only NaN points: nothing left after preparation.
  const PreparedCloud3D nans(std::vector<Eigen::Vector3f>(5, Eigen::Vector3f::Constant(NAN)), full());
  EXPECT_EQ(nans.size(), 0u);
  EXPECT_EQ(icp_3d(target, nans, Eigen::Isometry3d::Identity()).termination,
            RegistrationTermination::InvalidInput);
  // Far away: no pair.
  const auto far = icp_3d(target, target, make_pose(100, 0, 0, 0, 0, 0));
  EXPECT_EQ(far.termination, RegistrationTermination::TooFewCorrespondences);
  // Missing covariances for GICP / normals for point-to-plane are caller bugs.
  const PreparedCloud3D bare(scene);
  EXPECT_THROW(icp_3d(bare, bare, Eigen::Isometry3d::Identity()), InvalidArgument);
  Icp3dOptions p2l;
  p2l.method = Icp3dMethod::PointToPlane;
  EXPECT_THROW(icp_3d(bare, bare, Eigen::Isometry3d::Identity(), p2l), InvalidArgument);
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad(0, 0) = NAN;
  EXPECT_THROW(icp_3d(target, target, bad), InvalidArgument);
}

}  // namespace
}  // namespace rove
