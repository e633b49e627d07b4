#include "rove/registration/icp_3d.h"

#include <cmath>
#include <memory>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "rove/core/cpu.h"
#include "rove/core/error.h"
#include "rove/registration/icp_3d_multi_resolution.h"
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
    const auto r = icp_3d(target, source, SE3d(), o);
    SCOPED_TRACE(static_cast<int>(method));
    ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
    const auto [et, er] = pose_error(r.T_target_source.matrix(), truth.matrix());
    // Point-to-point is limited by the 15 cm sampling of the target surfaces.
    const bool p2p = method == Icp3dMethod::PointToPoint;
    EXPECT_LT(et, p2p ? 0.03 : 0.01);
    EXPECT_LT(er, p2p ? 0.01 : 3e-3);
    EXPECT_GT(r.goodness, 0.95);
    EXPECT_GT(r.conditioning, 0.01);
    EXPECT_TRUE(r.T_target_source.matrix().isApprox(r.T_target_source.matrix(), 1e-9));
    EXPECT_GT(r.covariance.determinant(), 0.0);
  }
}

// Issue 18 item 1: the LM damping started at 1e-6 and topped out near 1e3,
// nothing next to a GICP Hessian, so when the undamped step raised the cost
// every "damped" step did too and the run returned the initial guess as
// Converged. Stand-in for libpointmatcher's car pair: a floor and a wall, the
// source tilted 40° (the full step over-rotates) or 30° with a 0.75 m gate.
std::vector<Eigen::Vector3f> floor_and_wall(double step) {
  std::vector<Eigen::Vector3f> p;
  test::add_patch(p, {-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, step);
  test::add_patch(p, {-5, 3, 0}, {10, 0, 0}, {0, 0, 3}, step);
  return p;
}

TEST(Icp3d, RegressionGicpConvergedAtTheInitialGuessWhenEveryStepRaisedTheCost) {
  struct Case {
    double degrees, gate, step;
    bool reaches_truth;
  };
  for (const Case c : {Case{40, 2.0, 0.1, true}, Case{30, 0.75, 0.25, false}}) {
    SCOPED_TRACE(c.degrees);
    const auto scene = floor_and_wall(c.step);
    const Eigen::Isometry3d truth = make_pose(0, 0, 0, c.degrees * M_PI / 180, 0, 0);
    PrepareOptions po;
    po.covariances = true;
    po.neighbors = 10;
    const PreparedCloud3D target(scene, po);
    const PreparedCloud3D source(test::as_seen_from(scene, truth, 0.0, 1), po);
    Icp3dOptions o;
    o.max_correspondence_distance = c.gate;
    o.degeneracy_threshold = 0;
    const auto r = icp_3d(target, source, SE3d(), o);
    const bool unmoved = r.T_target_source.matrix().isIdentity(0);
    // Never "Converged" on the initial guess when a step was needed.
    EXPECT_FALSE(r.ok() && unmoved) << r.message;
    if (c.reaches_truth) {
      ASSERT_TRUE(r.ok()) << r.message;
      const auto [et, er] = pose_error(r.T_target_source.matrix(), truth.matrix());
      EXPECT_LT(et, 1e-4);
      EXPECT_LT(er, 1e-4);
    } else if (unmoved) {
      EXPECT_EQ(r.termination, RegistrationTermination::Stalled) << r.message;
      EXPECT_NE(r.message.find("initial guess"), std::string::npos) << r.message;
    }
  }
}

// The other side of the rule: a run that starts at the optimum, where no step
// lowers the cost and none is needed, is Converged.
TEST(Icp3d, StartingAtTheOptimumConverges) {
  PrepareOptions po;
  po.covariances = true;
  const PreparedCloud3D cloud(test::room_3d(0.25), po);
  const auto r = icp_3d(cloud, cloud, SE3d(), {});
  EXPECT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  EXPECT_TRUE(r.T_target_source.matrix().isApprox(Eigen::Matrix4d::Identity(), 1e-9));
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
    const auto r = icp_3d(target, source, SE3d(), o);
    EXPECT_EQ(r.termination, RegistrationTermination::Degenerate) << r.message;
    EXPECT_LT(r.conditioning, 1e-6);
  }
}

TEST(Icp3d, ParallelEqualsSerial) {
  const auto scene = test::room_3d(0.3);
  const auto src = test::as_seen_from(scene, make_pose(0.1, 0.1, 0, 0, 0, 0.05), 0.01, 3);
  const PreparedCloud3D t1(scene, full(1)), t2(scene, full(2));
  const PreparedCloud3D s1(src, full(1)), s2(src, full(2));
  for (std::size_t i = 0; i < t1.size(); ++i) ASSERT_EQ(t1.covariance(i), t2.covariance(i));
  Icp3dOptions o;
  const auto a = icp_3d(t1, s1, SE3d(), o);
  o.num_threads = 2;
  const auto b = icp_3d(t2, s2, SE3d(), o);
  EXPECT_EQ(a.T_target_source.matrix(), b.T_target_source.matrix());
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.information, b.information);
}

// GICP's linearization and the KD-tree's k-nearest set have AVX2 versions
// (rove/core/cpu.h); they must give the very same run as the baseline
// ones: the same covariances, pose, iterations and information matrix, bit
// for bit. The pair count is not a multiple of four, so the last step of
// the linearization runs with padded lanes.
TEST(Icp3d, BothInstructionSetsGiveTheSameRun) {
  if (!detail::cpu_has_avx2()) GTEST_SKIP() << "this processor has no AVX2: only the baseline kernels exist";
  const bool initial = avx2_enabled();
  struct Restore {
    bool on;
    ~Restore() { detail::set_avx2_enabled(on); }
  } restore{initial};
  const auto scene = test::room_3d(0.2);
  const auto src = test::as_seen_from(scene, make_pose(0.1, -0.05, 0.02, 0.01, 0, 0.06), 0.01, 3);
  Icp3dOptions o;
  o.method = Icp3dMethod::Gicp;
  detail::set_avx2_enabled(true);
  const PreparedCloud3D ta(scene, full()), sa(src, full());
  const auto a = icp_3d(ta, sa, SE3d(), o);
  detail::set_avx2_enabled(false);
  const PreparedCloud3D tb(scene, full()), sb(src, full());
  const auto b = icp_3d(tb, sb, SE3d(), o);
  for (std::size_t i = 0; i < ta.size(); ++i) ASSERT_EQ(ta.covariance(i), tb.covariance(i)) << "point " << i;
  for (std::size_t i = 0; i < ta.neighborhoods().size(); ++i)
    ASSERT_EQ(ta.neighborhoods()[i], tb.neighborhoods()[i]) << "entry " << i;
  EXPECT_EQ(a.termination, RegistrationTermination::Converged) << a.message;
  EXPECT_NE(a.correspondences % 4, 0u);
  EXPECT_EQ(a.T_target_source.matrix(), b.T_target_source.matrix());
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.correspondences, b.correspondences);
  EXPECT_EQ(a.information, b.information);
  EXPECT_EQ(a.fitness, b.fitness);
}

// Normals and covariances are computed in the tree's order with each search
// bounded by the previous one; they must be exactly those of an unbounded
// search per point (k = 10 and 20; a noisy scene, so no ties at the k-th
// distance, where either neighbour set would be right).
TEST(PreparedCloud3D, BoundedSearchesGiveTheUnboundedSurfaces) {
  const auto scene = test::as_seen_from(test::room_3d(0.12), Eigen::Isometry3d::Identity(), 0.01, 5);
  for (std::size_t k : {10u, 20u}) {
    PrepareOptions o = full();
    o.neighbors = k;
    const PreparedCloud3D cloud(scene, o);
    ASSERT_EQ(cloud.size(), scene.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      Eigen::Vector3f n;
      Eigen::Matrix3d c;
      local_surface_3d(cloud.tree(), cloud.points()[i], k, o.gicp_epsilon, &n, &c);
      ASSERT_EQ(cloud.normals()[i], n) << "point " << i << ", k " << k;
      ASSERT_EQ(cloud.covariance(i), c) << "point " << i << ", k " << k;
    }
  }
}

// The trig-free smallest eigenpair against Eigen's solver: separated,
// planar (λ₁ = 0), double and triple eigenvalues, at several scales.
TEST(SmallestEigenpair, MatchesEigenOnEverySpectrum) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  const std::vector<Eigen::Vector3d> spectra = {{0.1, 0.5, 1.0}, {0.0, 0.3, 2.0},  {1e-6, 1.0, 1.0},
                                                {0.2, 0.2, 1.0}, {0.7, 0.7, 0.7},  {0.0, 0.0, 1.0},
                                                {1e-3, 1e-3, 5.0}, {0.45, 0.5, 0.55}};
  for (const double scale : {1e-6, 1.0, 1e4}) {
    for (const auto& ev : spectra) {
      for (int trial = 0; trial < 20; ++trial) {
        const Eigen::Matrix3d Q =
            Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
        const Eigen::Matrix3d C = scale * Q * ev.asDiagonal() * Q.transpose();
        double lambda = -1;
        Eigen::Vector3d v;
        ASSERT_TRUE(smallest_eigenpair_psd(C, lambda, v));
        SCOPED_TRACE(testing::Message() << "spectrum " << ev.transpose() << " scale " << scale);
        EXPECT_NEAR(v.norm(), 1.0, 1e-12);
        // A double root of the cubic is found to about the square root of
        // the rounding, relative to the largest eigenvalue.
        EXPECT_NEAR(lambda, scale * ev.minCoeff(), 1e-7 * scale);
        // A simple smallest eigenvalue fixes the direction (up to sign). At
        // a double root the cubic's value sinks into rounding about 1e-8
        // from the root, which leaves the vector that far out of the plane.
        if (ev(1) - ev(0) > 0.05) {
          EXPECT_NEAR(std::abs(v.dot(Q.col(0))), 1.0, 1e-9);
          EXPECT_LT((C * v - lambda * v).norm(), 1e-9 * scale);
        } else {
          EXPECT_LT((C * v - lambda * v).norm(), 1e-7 * scale * ev.maxCoeff());
        }
      }
    }
  }
  double lambda = 0;
  Eigen::Vector3d v;
  EXPECT_FALSE(smallest_eigenpair_psd(Eigen::Matrix3d::Zero(), lambda, v));
  EXPECT_FALSE(smallest_eigenpair_psd(Eigen::Matrix3d::Constant(NAN), lambda, v));
}

// The batched eigenpairs equal the one-at-a-time ones bit for bit, for
// every spectrum above, zero and non-finite matrices among them, and any
// count (groups of four with a remainder), in both the AVX2 and the
// baseline version.
TEST(SmallestEigenpair, BatchEqualsOneAtATime) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  const std::vector<Eigen::Vector3d> spectra = {{0.1, 0.5, 1.0}, {0.0, 0.3, 2.0},  {1e-6, 1.0, 1.0},
                                                {0.2, 0.2, 1.0}, {0.7, 0.7, 0.7},  {0.0, 0.0, 1.0},
                                                {1e-3, 1e-3, 5.0}, {0.45, 0.5, 0.55}, {0.0, 0.0, 0.0}};
  std::vector<Eigen::Matrix3d> C;
  for (int trial = 0; trial < 40; ++trial)
    for (const auto& ev : spectra) {
      const Eigen::Matrix3d Q =
          Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
      C.push_back(std::exp(g(rng)) * Q * ev.asDiagonal() * Q.transpose());
    }
  C[7] = Eigen::Matrix3d::Constant(NAN);
  C[20](1, 2) = INFINITY;
  C[30](0, 0) = -INFINITY;
  // Both versions of the batch (rove/core/cpu.h): the AVX2 one where the
  // processor has it, the baseline one.
  const bool initial = avx2_enabled();
  struct Restore {
    bool on;
    ~Restore() { detail::set_avx2_enabled(on); }
  } restore{initial};
  for (const bool avx2 : {true, false}) {
    detail::set_avx2_enabled(avx2);
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{4}, std::size_t{5},
                                C.size()}) {
      std::vector<double> lambda(n, -7);
      std::vector<Eigen::Vector3d> v(n, Eigen::Vector3d::Constant(-7));
      std::unique_ptr<bool[]> found(new bool[n]);
      smallest_eigenpairs_psd(std::span(C.data(), n), lambda, v, std::span(found.get(), n));
      for (std::size_t i = 0; i < n; ++i) {
        double l1 = -7;
        Eigen::Vector3d v1 = Eigen::Vector3d::Constant(-7);
        const bool f1 = smallest_eigenpair_psd(C[i], l1, v1);
        ASSERT_EQ(found[i], f1) << "matrix " << i << " of " << n << ", avx2 " << avx2_enabled();
        ASSERT_EQ(lambda[i], l1) << "matrix " << i << " of " << n << ", avx2 " << avx2_enabled();
        ASSERT_EQ(v[i], v1) << "matrix " << i << " of " << n << ", avx2 " << avx2_enabled();
      }
    }
  }
  std::vector<double> lambda(2);
  std::vector<Eigen::Vector3d> v(3);
  bool found[3];
  EXPECT_THROW(smallest_eigenpairs_psd(std::span(C.data(), 3), lambda, v, found), InvalidArgument);
}

// The neighbourhoods kept for pairing are the k nearest of each point, as
// the tree finds them, with their squared distances.
TEST(PreparedCloud3D, KeepsTheNeighbourhoods) {
  const auto scene = test::as_seen_from(test::room_3d(0.2), Eigen::Isometry3d::Identity(), 0.01, 6);
  PrepareOptions o;
  o.covariances = true;
  o.neighbors = 7;
  const PreparedCloud3D cloud(scene, o);
  ASSERT_EQ(cloud.neighbors_per_point(), 7u);
  ASSERT_EQ(cloud.neighborhoods().size(), 7 * cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto want = cloud.tree().knn(cloud.points()[i], 7);
    for (std::size_t j = 0; j < 7; ++j) {
      ASSERT_EQ(cloud.neighborhoods()[i * 7 + j], want[j]) << "point " << i << ", rank " << j;
    }
  }
  EXPECT_FALSE(PreparedCloud3D(scene).has_neighborhoods());
  // Not kept on request, with the same covariances.
  PrepareOptions without = o;
  without.neighborhoods = false;
  const PreparedCloud3D bare(scene, without);
  EXPECT_FALSE(bare.has_neighborhoods());
  EXPECT_EQ(bare.neighbors_per_point(), 0u);
  ASSERT_EQ(bare.size(), cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) ASSERT_EQ(bare.covariance(i), cloud.covariance(i)) << i;
  // Fewer points than neighbours: every point is in every row.
  const std::vector<Eigen::Vector3f> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const PreparedCloud3D small(three, o);
  EXPECT_EQ(small.neighbors_per_point(), 3u);
}

// Pairs found by walking the target's neighbourhoods equal the tree's:
// point-to-point ICP ignores normals, so a target with them (and so with
// neighbourhoods) must give the very same run as a bare one.
TEST(Icp3d, NeighbourhoodWalkPairsAsTheTree) {
  const auto scene = test::room_3d(0.15);
  const auto src = test::as_seen_from(test::room_3d(0.25), make_pose(0.3, -0.2, 0.05, 0.03, -0.02, 0.1), 0.01, 7);
  PrepareOptions with;
  with.normals = true;
  with.neighbors = 8;
  const PreparedCloud3D bare(scene), walk(scene, with), source(src);
  for (double gate : {0.1, 0.5, 2.0}) {
    Icp3dOptions o;
    o.method = Icp3dMethod::PointToPoint;
    o.max_correspondence_distance = gate;
    const auto a = icp_3d(bare, source, SE3d(), o);
    const auto b = icp_3d(walk, source, SE3d(), o);
    SCOPED_TRACE(gate);
    EXPECT_EQ(a.T_target_source.matrix(), b.T_target_source.matrix());
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.correspondences, b.correspondences);
  }
}

TEST(Icp3d, BadInputs) {
  const auto scene = test::room_3d(0.3);
  const PreparedCloud3D target(scene, full());
  const PreparedCloud3D empty(std::vector<Eigen::Vector3f>{}, full());
  EXPECT_EQ(icp_3d(target, empty, SE3d()).termination,
            RegistrationTermination::InvalidInput);
  EXPECT_EQ(icp_3d(empty, target, SE3d()).termination,
            RegistrationTermination::InvalidInput);
  // Only NaN points: nothing left after preparation.
  const PreparedCloud3D nans(std::vector<Eigen::Vector3f>(5, Eigen::Vector3f::Constant(NAN)), full());
  EXPECT_EQ(nans.size(), 0u);
  EXPECT_EQ(icp_3d(target, nans, SE3d()).termination,
            RegistrationTermination::InvalidInput);
  // Far away: no pair.
  const auto far = icp_3d(target, target, SE3d(make_pose(100, 0, 0, 0, 0, 0).matrix()));
  EXPECT_EQ(far.termination, RegistrationTermination::TooFewCorrespondences);
  // Missing covariances for GICP / normals for point-to-plane are caller bugs.
  const PreparedCloud3D bare(scene);
  EXPECT_THROW(icp_3d(bare, bare, SE3d()), InvalidArgument);
  Icp3dOptions p2l;
  p2l.method = Icp3dMethod::PointToPlane;
  EXPECT_THROW(icp_3d(bare, bare, SE3d(), p2l), InvalidArgument);
  // A non-finite initial pose cannot even be made.
  Eigen::Matrix4d bad = Eigen::Matrix4d::Identity();
  bad(0, 0) = NAN;
  EXPECT_THROW(icp_3d(target, target, SE3d(bad)), InvalidArgument);
}

// Issue 18 item 9: a thread count is capped (rove::kMaxThreads), never started
// as asked; 0 means all hardware threads.
TEST(Icp3d, RegressionThreadCountIsCapped) {
  Icp3dOptions o;
  o.num_threads = 100000;
  EXPECT_THROW(o.check(), InvalidArgument);
  o.num_threads = -1;
  EXPECT_THROW(o.check(), InvalidArgument);
  o.num_threads = 0;
  EXPECT_NO_THROW(o.check());
  PrepareOptions p;
  p.num_threads = 100000;
  EXPECT_THROW(PreparedCloud3D(test::room_3d(0.5), p), InvalidArgument);
}

TEST(Icp3dMultiResolution, RecoversAKnownTransformCoarseToFine) {
  const auto scene = test::room_3d(0.05);
  const Eigen::Isometry3d truth = make_pose(0.3, -0.2, 0.05, 0.02, -0.03, 0.1);
  const auto src = test::as_seen_from(scene, truth, 0.002, 4);
  for (auto method : {Icp3dMethod::PointToPoint, Icp3dMethod::PointToPlane, Icp3dMethod::Gicp}) {
    Icp3dMultiResolutionOptions o;
    // The last level at full resolution: the source is the scene's own
    // points moved, so point-to-point gets exact partners there.
    o.voxel_sizes = {0.3, 0.1, 0.0};
    o.icp.method = method;
    const auto r = icp_3d_multi_resolution(scene, src, SE3d(), o);
    SCOPED_TRACE(static_cast<int>(method));
    ASSERT_EQ(r.levels.size(), 3u);
    ASSERT_EQ(r.result.termination, RegistrationTermination::Converged) << r.result.message;
    EXPECT_EQ(r.total_iterations,
              r.levels[0].iterations + r.levels[1].iterations + r.levels[2].iterations);
    EXPECT_EQ(r.source_points.back(), src.size());
    EXPECT_LT(r.source_points[0], r.source_points[1]);
    const auto [et, er] = pose_error(r.result.T_target_source.matrix(), truth.matrix());
    EXPECT_LT(et, 0.01);
    EXPECT_LT(er, 3e-3);
  }
}

TEST(Icp3dMultiResolution, ParallelEqualsSerial) {
  const auto scene = test::room_3d(0.1);
  const auto src = test::as_seen_from(scene, make_pose(0.1, 0.1, 0, 0, 0, 0.05), 0.01, 5);
  Icp3dMultiResolutionOptions o;
  o.voxel_sizes = {0.3, 0.0};
  const auto a = icp_3d_multi_resolution(scene, src, SE3d(), o);
  o.icp.num_threads = 2;
  const auto b = icp_3d_multi_resolution(scene, src, SE3d(), o);
  EXPECT_EQ(a.result.T_target_source.matrix(), b.result.T_target_source.matrix());
  EXPECT_EQ(a.total_iterations, b.total_iterations);
}

TEST(Icp3dMultiResolution, BadInputs) {
  const auto scene = test::room_3d(0.3);
  const std::vector<Eigen::Vector3f> none;
  const std::vector<Eigen::Vector3f> nans(5, Eigen::Vector3f::Constant(NAN));
  const std::vector<Eigen::Vector3f> one{Eigen::Vector3f(1, 2, 3)};
  for (auto method : {Icp3dMethod::PointToPoint, Icp3dMethod::PointToPlane, Icp3dMethod::Gicp}) {
    Icp3dMultiResolutionOptions o;
    o.icp.method = method;
    const SE3d I;
    const auto e1 = icp_3d_multi_resolution(scene, none, I, o);
    EXPECT_EQ(e1.result.termination, RegistrationTermination::InvalidInput) << e1.result.message;
    EXPECT_EQ(e1.levels.size(), 1u);
    EXPECT_EQ(icp_3d_multi_resolution(none, scene, I, o).result.termination,
              RegistrationTermination::InvalidInput);
    EXPECT_EQ(icp_3d_multi_resolution(scene, nans, I, o).result.termination,
              RegistrationTermination::InvalidInput);
    const auto single = icp_3d_multi_resolution(scene, one, I, o);
    EXPECT_EQ(single.result.termination, RegistrationTermination::TooFewCorrespondences)
        << single.result.message;
    EXPECT_TRUE(single.result.T_target_source.matrix().allFinite());
  }
  Icp3dMultiResolutionOptions bad;
  bad.voxel_sizes = {};
  EXPECT_THROW(icp_3d_multi_resolution(scene, scene, SE3d(), bad),
               InvalidArgument);
  bad.voxel_sizes = {0.25, NAN};
  EXPECT_THROW(icp_3d_multi_resolution(scene, scene, SE3d(), bad),
               InvalidArgument);
  bad.voxel_sizes = {0.25};
  bad.distance_factor = 0;
  EXPECT_THROW(icp_3d_multi_resolution(scene, scene, SE3d(), bad),
               InvalidArgument);
}

}  // namespace
}  // namespace rove
