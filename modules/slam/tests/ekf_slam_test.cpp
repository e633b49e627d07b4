#include "rove/slam/ekf_slam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "../src/ekf_slam_models.h"
#include "ekf_slam_sim.h"
#include "rove/bayes/distributions.h"
#include "rove/core/error.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

EkfSlamOptions quiet_options(int dim) {
  EkfSlamOptions o = EkfSlamOptions::defaults(dim);
  o.std_sensor_range = 0.1;
  o.std_sensor_yaw = 2.0 * kDeg;
  o.std_sensor_pitch = 2.0 * kDeg;
  return o;
}

// The sensor model's Jacobians against central differences.
TEST(EkfSlamModels, JacobiansMatchNumericDerivatives) {
  const double h = 1e-6;
  const Eigen::Vector3d p(2.0, -1.5, 0.7);
  Eigen::Vector3d z;
  Eigen::Matrix3d J, Jn;
  ASSERT_TRUE(detail::spherical(p, z, &J));
  for (int c = 0; c < 3; ++c) {
    Eigen::Vector3d zp, zm;
    detail::spherical(Eigen::Vector3d(p + h * Eigen::Vector3d::Unit(c)), zp, nullptr);
    detail::spherical(Eigen::Vector3d(p - h * Eigen::Vector3d::Unit(c)), zm, nullptr);
    Jn.col(c) = (zp - zm) / (2 * h);
  }
  EXPECT_TRUE(J.isApprox(Jn, 1e-7)) << J << "\n" << Jn;
  // from_spherical inverts spherical, and its Jacobian is the inverse.
  Eigen::Matrix3d Ji;
  EXPECT_TRUE(detail::from_spherical(z, Ji).isApprox(p, 1e-12));
  EXPECT_TRUE((Ji * J).isApprox(Eigen::Matrix3d::Identity(), 1e-9));
  // Positive pitch below the XY plane.
  EXPECT_GT(z[2], -1.0);
  EXPECT_LT(z[2], 0.0);  // p.z > 0: above the plane, negative pitch
  const Eigen::Vector2d p2(1.0, 3.0);
  Eigen::Vector2d z2;
  Eigen::Matrix2d J2, J2i;
  ASSERT_TRUE(detail::spherical(p2, z2, &J2));
  EXPECT_TRUE(detail::from_spherical(z2, J2i).isApprox(p2, 1e-12));
  EXPECT_TRUE((J2i * J2).isApprox(Eigen::Matrix2d::Identity(), 1e-9));
  // On the sensor's z axis the bearing has no derivative.
  EXPECT_FALSE(detail::spherical(Eigen::Vector3d(0, 0, 2), z, &J));
}

// d(X·exp(δ))⁻¹·p / dδ against central differences, for both groups.
template <class Pose>
void check_inverse_action_jacobian(const Pose& X, const typename Pose::Point& p) {
  constexpr int kD = Pose::Tangent::RowsAtCompileTime;
  const typename Pose::Point q = X.inverse() * p;
  const auto J = detail::inverse_action_jacobian(q);
  const double h = 1e-6;
  for (int c = 0; c < kD; ++c) {
    const typename Pose::Tangent d = h * Pose::Tangent::Unit(c);
    const typename Pose::Point num =
        ((X.oplus(d)).inverse() * p - (X.oplus(-d)).inverse() * p) / (2 * h);
    EXPECT_TRUE(num.isApprox(J.col(c), 1e-6)) << "column " << c << ": " << num.transpose()
                                               << " vs " << J.col(c).transpose();
  }
}

TEST(EkfSlamModels, RobotPoseJacobiansMatchNumericDerivatives) {
  check_inverse_action_jacobian(SE2d(1.0, -2.0, 0.7), Eigen::Vector2d(4.0, 1.0));
  SE3d::Tangent xi;
  xi << 1.0, -2.0, 0.5, 0.3, -0.2, 0.9;
  check_inverse_action_jacobian(SE3d::exp(xi), Eigen::Vector3d(4.0, 1.0, -1.0));
}

// With the robot pose known exactly, a landmark straight ahead is a linear
// Gaussian problem along the bearing axis: the second reading averages the
// first (hand-computed Kalman update: K = P/(P+R) = 1/2 per axis).
TEST(EkfSlam, LinearCaseMatchesHandComputedKalmanUpdate) {
  EkfSlamOptions o = quiet_options(2);
  o.stds_no_odometry = {0.0, 0.0, 0.0};
  EkfSlam2D slam(o);
  EkfSlamFrame<2> f;
  f.readings.push_back({7, Eigen::Vector2d(4.0, 0.0)});
  slam.step(std::nullopt, f);
  ASSERT_EQ(slam.landmark_count(), 1u);
  const double sr2 = 0.01, st2 = std::pow(2.0 * kDeg, 2);
  EXPECT_TRUE(slam.landmark(0).isApprox(Eigen::Vector2d(4.0, 0.0)));
  Eigen::Matrix2d P0;
  P0 << sr2, 0, 0, 16.0 * st2;
  EXPECT_TRUE(slam.landmark_covariance(0).isApprox(P0, 1e-12)) << slam.landmark_covariance(0);
  f.readings[0].z = Eigen::Vector2d(4.2, 0.0);
  const EkfSlamStepResult r = slam.step(std::nullopt, f);
  EXPECT_EQ(r.by_id, 1u);
  EXPECT_NEAR(slam.landmark(0).x(), 4.1, 1e-12);
  EXPECT_NEAR(slam.landmark(0).y(), 0.0, 1e-12);
  EXPECT_NEAR(slam.landmark_covariance(0)(0, 0), sr2 / 2, 1e-12);
  EXPECT_NEAR(slam.landmark_covariance(0)(1, 1), 16.0 * st2 / 2, 1e-12);
  EXPECT_NEAR(r.nis, 0.04 / (2 * sr2), 1e-9);  // ν = 0.2 m, S = 2σ²
  EXPECT_EQ(r.nis_dof, 2u);
  EXPECT_TRUE(slam.pose().is_approx(SE2d()));
}

// Prediction touches only the robot's rows and columns.
TEST(EkfSlam, PredictionLeavesTheMapBlockUnchanged) {
  test::SlamSim<3> sim(3);
  EkfSlam3D slam(sim.options());
  for (int k = 0; k < 5; ++k) {
    const auto odo = sim.move();  // before sense(): the readings are of the moved robot
    slam.step(odo, sim.sense());
  }
  ASSERT_GT(slam.landmark_count(), 3u);
  const Eigen::MatrixXd before = slam.covariance();
  slam.predict(sim.move());
  const Eigen::MatrixXd after = slam.covariance();
  const Eigen::Index m = before.rows() - 6;
  EXPECT_EQ(after.bottomRightCorner(m, m), before.bottomRightCorner(m, m));
  EXPECT_FALSE(after.topLeftCorner(6, 6).isApprox(before.topLeftCorner(6, 6)));
}

template <int Dim>
void expect_symmetric_psd(const EkfSlam<Dim>& slam) {
  const Eigen::MatrixXd P = slam.covariance();
  EXPECT_EQ(P, P.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(P);
  EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12 * es.eigenvalues().maxCoeff());
}

// Robot-pose NEES over Monte-Carlo runs of the simulated loop, where every
// noise follows the filter's models: the average NEES of N runs at step k
// times N is χ²(N·d); at least 90 % of the steps lie within its two-sided
// 95 % interval (Bar-Shalom et al. 2001, §5.4.2). 60 steps (landmarks
// revisited) stay short of the slow overconfidence of EKF-SLAM on long runs
// with large heading uncertainty (Bailey et al., IROS 2006).
template <int Dim>
void nees_test(std::uint64_t seed) {
  constexpr int kRuns = 25, kSteps = 60, kD = EkfSlamTraits<Dim>::kPoseDof;
  std::vector<double> nees(kSteps, 0.0);
  for (int run = 0; run < kRuns; ++run) {
    test::SlamSim<Dim> sim(seed + static_cast<std::uint64_t>(run));
    EkfSlam<Dim> slam(sim.options());
    // The first landmarks are seen from the start pose, which fixes the map
    // frame of both the filter and the simulation.
    slam.update(sim.sense());
    for (int k = 0; k < kSteps; ++k) {
      const auto odo = sim.move();  // before sense(): the readings are of the moved robot
      slam.step(odo, sim.sense());
      const Eigen::Matrix<double, kD, 1> e = sim.truth.ominus(slam.pose());
      nees[static_cast<std::size_t>(k)] += e.dot(slam.pose_covariance().ldlt().solve(e)) / kRuns;
    }
    expect_symmetric_psd(slam);
  }
  const double lo = chi_square_quantile(0.025, kRuns * kD) / kRuns;
  const double hi = chi_square_quantile(0.975, kRuns * kD) / kRuns;
  int inside = 0;
  double total = 0.0;
  for (double v : nees) inside += (v >= lo && v <= hi) ? 1 : 0, total += v;
  EXPECT_GE(inside, static_cast<int>(0.9 * kSteps)) << "lo " << lo << " hi " << hi;
  // The mean over the steps: the steps of a run are correlated, so it is
  // held to the bounds of one step's average (99 %), not of N·K samples.
  const double mean = total / kSteps;
  EXPECT_GE(mean, chi_square_quantile(0.005, kRuns * kD) / kRuns);
  EXPECT_LE(mean, chi_square_quantile(0.995, kRuns * kD) / kRuns);
}

TEST(EkfSlamConsistency, PlanarNeesWithinChiSquareBounds) { nees_test<2>(100); }
TEST(EkfSlamConsistency, SixDofNeesWithinChiSquareBounds) { nees_test<3>(200); }

// Batch (kfEKFNaive) and sequential (kfEKFAlaDavison) updates agree to the
// linearization error; the planar 3D filter agrees with the 2D one.
TEST(EkfSlam, BatchAndSequentialUpdatesAgree) {
  test::SlamSim<2> sim(11);
  EkfSlamOptions ob = sim.options(), os = sim.options();
  os.update = EkfSlamUpdate::Sequential;
  EkfSlam2D batch(ob), seq(os);
  for (int k = 0; k < 40; ++k) {
    const auto odo = sim.move();
    const auto frame = sim.sense();
    batch.step(odo, frame);
    seq.step(odo, frame);
  }
  ASSERT_EQ(batch.landmark_count(), seq.landmark_count());
  EXPECT_LT((batch.pose().translation() - seq.pose().translation()).norm(), 0.01);
  for (std::size_t i = 0; i < batch.landmark_count(); ++i) {
    EXPECT_LT((batch.landmark(i) - seq.landmark(i)).norm(), 0.01);
  }
}

TEST(EkfSlam, PlanarSixDofRunMatchesThePlanarFilter) {
  test::SlamSim<2> sim(5);
  EkfSlam2D slam2(sim.options());
  EkfSlamOptions o3 = EkfSlamOptions::defaults(3);
  o3.std_sensor_range = sim.std_range;
  o3.std_sensor_yaw = sim.std_yaw;
  o3.std_sensor_pitch = 1e-4;
  EkfSlam3D slam3(o3);
  for (int k = 0; k < 40; ++k) {
    const auto odo = sim.move();
    const auto frame = sim.sense();
    slam2.step(odo, frame);
    EkfSlamOdometry<3> odo3;
    const SE2d& U = odo.increment;
    odo3.increment = SE3d(SO3d::exp(Eigen::Vector3d(0, 0, U.angle())),
                          Eigen::Vector3d(U.translation().x(), U.translation().y(), 0));
    odo3.covariance.setIdentity();
    odo3.covariance *= 1e-12;
    const int idx[3] = {0, 1, 5};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) odo3.covariance(idx[r], idx[c]) = odo.covariance(r, c);
    }
    EkfSlamFrame<3> f3;
    for (const auto& r : frame.readings) f3.readings.push_back({r.id, {r.z[0], r.z[1], 0.0}});
    slam3.step(odo3, f3);
  }
  ASSERT_EQ(slam2.landmark_count(), slam3.landmark_count());
  EXPECT_LT((slam2.pose().translation() - slam3.pose().translation().head<2>()).norm(), 1e-4);
  for (std::size_t i = 0; i < slam2.landmark_count(); ++i) {
    EXPECT_LT((slam2.landmark(i) - slam3.landmark(i).head<2>()).norm(), 1e-4);
    EXPECT_TRUE(slam2.landmark_covariance(i).isApprox(
        slam3.landmark_covariance(i).topLeftCorner<2, 2>(), 1e-3));
  }
}

// Without IDs, NN and JCBB pair the simulated readings without a single
// mistake.
TEST(EkfSlam, DataAssociationOnSimulatedLoopMakesNoWrongPairings) {
  for (DataAssociationMethod m : {DataAssociationMethod::NearestNeighbor, DataAssociationMethod::Jcbb}) {
    test::SlamSim<3> sim(21, 20);
    sim.with_ids = false;
    EkfSlamOptions o = sim.options();
    o.data_association.method = m;
    o.data_association.chi2_probability = 0.999;
    EkfSlam3D slam(o);
    std::vector<std::size_t> truth_of;  // landmark index → true landmark
    std::set<std::size_t> seen;
    std::size_t wrong = 0, paired = 0;
    for (int k = 0; k < 80; ++k) {
      const auto odo = sim.move();
      auto frame = sim.sense();
      // The simulator's order of readings is the landmark order: keep it.
      std::vector<std::size_t> ids;
      {
        test::SlamSim<3> probe = sim;
        probe.with_ids = true;
        probe.std_range = probe.std_yaw = probe.std_pitch = 0.0;
        for (const auto& r : probe.sense().readings) ids.push_back(static_cast<std::size_t>(r.id));
      }
      ASSERT_EQ(ids.size(), frame.readings.size());
      seen.insert(ids.begin(), ids.end());
      const EkfSlamStepResult r = slam.step(odo, frame);
      for (std::size_t j = 0; j < r.outcome.size(); ++j) {
        if (r.outcome[j] == ReadingOutcome::NewLandmark) truth_of.push_back(ids[j]);
        if (r.outcome[j] == ReadingOutcome::Associated) {
          ++paired;
          wrong += truth_of[static_cast<std::size_t>(r.landmark[j])] != ids[j] ? 1 : 0;
        }
      }
    }
    EXPECT_EQ(wrong, 0u) << to_string(m);
    EXPECT_GT(paired, 400u);
    // A true pairing fails the 99.9 % individual gate once in a thousand and
    // starts a duplicate landmark.
    EXPECT_GE(slam.landmark_count(), seen.size());
    EXPECT_LE(slam.landmark_count() - seen.size(), 2u) << to_string(m) << ": duplicates";
  }
}

TEST(EkfSlam, BadReadings) {
  EkfSlam3D slam(quiet_options(3));
  EkfSlamFrame<3> f;
  f.readings.push_back({1, {3.0, 0.1, 0.0}});
  f.readings.push_back({2, {0.0, 0.2, 0.0}});   // range 0: no direction
  f.readings.push_back({1, {3.1, 0.1, 0.0}});   // ID repeated in the frame
  const EkfSlamStepResult r = slam.step(std::nullopt, f);
  EXPECT_EQ(r.created, 1u);
  EXPECT_EQ(r.skipped, 2u);
  EXPECT_EQ(r.outcome[1], ReadingOutcome::Skipped);
  EXPECT_EQ(r.outcome[2], ReadingOutcome::Skipped);
  f.readings = {{1, {3.0, std::nan(""), 0.0}}};
  EXPECT_THROW(slam.step(std::nullopt, f), InvalidArgument);
  EkfSlamOptions bad = quiet_options(3);
  bad.std_sensor_range = 0.0;
  EXPECT_THROW(EkfSlam3D{bad}, InvalidArgument);
}

// A sensor mounted off the robot's center: landmarks land where the true
// geometry puts them.
TEST(EkfSlam, SensorOffsetIsApplied) {
  EkfSlam3D slam(quiet_options(3));
  EkfSlamFrame<3> f;
  f.T_robot_sensor = SE3d(SO3d::exp(Eigen::Vector3d(0, 0, std::numbers::pi / 2)),
                          Eigen::Vector3d(0.5, 0.0, 1.0));
  f.readings.push_back({4, {2.0, 0.0, 0.0}});  // 2 m along the sensor's x = robot's y
  slam.step(std::nullopt, f);
  EXPECT_TRUE(slam.landmark(0).isApprox(Eigen::Vector3d(0.5, 2.0, 1.0), 1e-12)) << slam.landmark(0);
}

}  // namespace
}  // namespace rove
