#include "rove/registration/icp_2d.h"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../src/icp_2d_internal.h"
#include "rove/core/error.h"
#include "rove/poses/lie_conversion.h"
#include "rove/core/ini.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

/// Points every `step` meters along the segment a→b.
void add_segment(std::vector<Eigen::Vector2d>& pts, Eigen::Vector2d a, Eigen::Vector2d b,
                 double step) {
  const double len = (b - a).norm();
  const int n = static_cast<int>(len / step);
  for (int i = 0; i <= n; ++i) pts.push_back(a + (b - a) * (i * step / len));
}

/// A 10 m × 6 m room with a pillar and a cabinet: well-constrained geometry.
std::vector<Eigen::Vector2d> room(double step) {
  std::vector<Eigen::Vector2d> p;
  add_segment(p, {-5, -3}, {5, -3}, step);
  add_segment(p, {5, -3}, {5, 3}, step);
  add_segment(p, {5, 3}, {-5, 3}, step);
  add_segment(p, {-5, 3}, {-5, -3}, step);
  add_segment(p, {1, 0}, {1.5, 0}, step);
  add_segment(p, {1.5, 0}, {1.5, 0.8}, step);
  add_segment(p, {-3, -3}, {-3, -1.5}, step);
  add_segment(p, {-3, -1.5}, {-2, -1.5}, step);
  return p;
}

/// Two parallel walls 2 m apart, 40 m long: nothing constrains x.
std::vector<Eigen::Vector2d> corridor(double step) {
  std::vector<Eigen::Vector2d> p;
  add_segment(p, {-20, -1}, {20, -1}, step);
  add_segment(p, {-20, 1}, {20, 1}, step);
  return p;
}

/// The map points seen from `T_map_scan`: source = T⁻¹ · p, with noise.
std::vector<Eigen::Vector2d> as_seen_from(const std::vector<Eigen::Vector2d>& map,
                                          const Pose2& T_map_scan, double noise,
                                          std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, noise);
  const Pose2 inv = T_map_scan.inverse();
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : map) {
    const Eigen::Vector2d q = inv.rotation() * p + inv.translation();
    out.push_back(q + (noise > 0 ? Eigen::Vector2d(n(rng), n(rng)) : Eigen::Vector2d::Zero()));
  }
  return out;
}

Icp2dOptions accurate_options() {
  Icp2dOptions o;
  o.threshold_dist = 0.5;
  o.threshold_ang = deg_to_rad(2);
  o.alfa = 0.8;
  o.smallest_threshold_dist = 0.02;
  o.max_iterations = 100;
  o.corresponding_points_decimation = 1;
  return o;
}

void expect_pose_near(const Pose2& a, const Pose2& b, double tol_xy, double tol_phi) {
  EXPECT_NEAR(a.x(), b.x(), tol_xy);
  EXPECT_NEAR(a.y(), b.y(), tol_xy);
  EXPECT_NEAR(wrap_to_pi(a.phi() - b.phi()), 0.0, tol_phi);
}

TEST(Icp2d, ClassicRecoversKnownPoseInARoom) {
  // A denser map than scan (as a map built from many scans), exact scan.
  const auto map = room(0.02);
  const Pose2 truth(0.2, -0.15, deg_to_rad(4));
  const auto scan = as_seen_from(room(0.1), truth, 0.0, 1);
  const IcpTarget2D target(map);
  const auto r = icp_2d(target, scan, SE2d(), accurate_options());
  ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  // Point-to-point pairs slide along walls sampled at 10 cm: sub-centimeter.
  expect_pose_near(to_pose2(r.T_target_source), truth, 0.01, deg_to_rad(0.3));
  EXPECT_GT(r.goodness, 0.9);
  EXPECT_LT(r.fitness, 1e-4);
  EXPECT_GT(r.conditioning, 0.05);
  // Covariance: positive definite and small for 500+ pairs at σ = 2 cm.
  EXPECT_GT(r.covariance.determinant(), 0.0);
  EXPECT_LT(r.covariance(0, 0), 1e-4);
}

TEST(Icp2d, EveryVariantRecoversANoisyScan) {
  const auto map = room(0.05);
  const Pose2 truth(-0.2, 0.3, deg_to_rad(-5));
  const auto scan = as_seen_from(map, truth, 0.005, 2);
  IcpTarget2DOptions topt;
  topt.normal_neighbors = 5;
  const IcpTarget2D target(map, topt);
  for (auto algo : {IcpAlgorithm::Classic, IcpAlgorithm::LevenbergMarquardt,
                    IcpAlgorithm::RobustLevenbergMarquardt}) {
    for (auto metric : {Icp2dMetric::PointToPoint, Icp2dMetric::PointToLine}) {
      if (algo == IcpAlgorithm::LevenbergMarquardt && metric == Icp2dMetric::PointToLine) continue;
      auto o = accurate_options();
      o.algorithm = algo;
      o.metric = metric;
      const auto r = icp_2d(target, scan, SE2d(), o);
      SCOPED_TRACE(::testing::Message() << "algorithm " << static_cast<int>(algo) << " metric "
                                        << static_cast<int>(metric));
      ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
      expect_pose_near(to_pose2(r.T_target_source), truth, 5e-3, deg_to_rad(0.1));
    }
  }
}

// Arithmetic::Mrpt runs MRPT's float computations (its se2_l2 fit, its LM).
TEST(Icp2dMrptCompat, MrptFitRecoversKnownPoses) {
  // Four points whose sums and products are exact in float: MRPT's
  // single-precision formula must give the exact motion (its signs and
  // which side is "global" are what this checks).
  const std::vector<Eigen::Vector2d> local = {{1, 0}, {0, 1}, {-1, 0}, {0, -2}};
  const Pose2 truth(2, 3, std::numbers::pi / 2);
  std::vector<Eigen::Vector2d> global;
  for (const auto& p : local) global.push_back(truth.rotation() * p + truth.translation());
  IcpTarget2DOptions mrpt_target;
  mrpt_target.arithmetic = Arithmetic::Mrpt;
  const IcpTarget2D exact(global, mrpt_target);
  Icp2dOptions o = accurate_options();
  o.arithmetic = Arithmetic::Mrpt;
  const auto r = icp_2d(exact, local, SE2d(2.05, 2.95, std::numbers::pi / 2 + 0.02), o);
  expect_pose_near(to_pose2(r.T_target_source), truth, 1e-6, 1e-6);

  // A real registration near the origin: MRPT's arithmetic lands where the
  // double one does, to float precision, for both of MRPT's methods.
  const auto map = room(0.02);
  const Pose2 room_truth(0.2, -0.15, deg_to_rad(4));
  const auto scan = as_seen_from(room(0.1), room_truth, 0.0, 1);
  const IcpTarget2D target(map);
  const IcpTarget2D target_f(map, mrpt_target);
  for (auto algo : {IcpAlgorithm::Classic, IcpAlgorithm::LevenbergMarquardt}) {
    Icp2dOptions od = accurate_options();
    od.algorithm = algo;
    Icp2dOptions of = od;
    of.arithmetic = Arithmetic::Mrpt;
    const auto d = icp_2d(target, scan, SE2d(), od);
    const auto f = icp_2d(target_f, scan, SE2d(), of);
    ASSERT_EQ(f.termination, RegistrationTermination::Converged) << f.message;
    expect_pose_near(to_pose2(f.T_target_source), room_truth, 0.01, deg_to_rad(0.3));
    expect_pose_near(to_pose2(d.T_target_source), room_truth, 0.01, deg_to_rad(0.3));
    // The classic run follows the same gate schedule; MRPT's LM steps are
    // bistable (docs/icp-slam.md), the two end within the sampling.
    if (algo == IcpAlgorithm::Classic)
      expect_pose_near(to_pose2(f.T_target_source), to_pose2(d.T_target_source), 2e-4, 2e-4);
  }
}

// Arithmetic::Mrpt holds the [ICP] options as MRPT reads them: the nearest
// float of every value. GCC 12's SLP vectorizer dropped 8 of these 12 round
// trips in Release builds (icp_2d_mrpt.cpp), and only the Telecom LM run
// showed it, by leaving MRPT's path; here each field has a value that float
// cannot hold, so a lost rounding fails by name. It can only fail in an
// optimized build: the sanitizer build (-O1) runs no SLP pass.
TEST(Icp2dMrptCompat, Gcc12SlpKeepsEveryOptionRoundedToFloat) {
  Icp2dOptions o;
  o.arithmetic = Arithmetic::Mrpt;
  o.min_abs_step_trans = 1e-6;
  o.min_abs_step_rot = 1.1e-6;
  o.threshold_dist = 0.3;
  o.alfa = 0.8;
  o.smallest_threshold_dist = 0.1;
  o.covariance_var_points = 4e-4;
  o.kernel_rho = 0.07;
  o.lm_initial_lambda = 1e-4;
  o.axy_aprox_derivatives = 0.05;
  o.ransac.mahalanobis_threshold = 3.1;
  o.ransac.normalization_std = 0.02;
  o.ransac.fuse_max_diff_xy = 0.01;
  o.threshold_ang = deg_to_rad(0.17);
  o.ransac.fuse_max_diff_phi = deg_to_rad(0.35);
  const Icp2dOptions r = detail::mrpt_rounded_options(o);

  const struct {
    const char* name;
    double given, rounded;
  } fields[] = {
      {"min_abs_step_trans", o.min_abs_step_trans, r.min_abs_step_trans},
      {"min_abs_step_rot", o.min_abs_step_rot, r.min_abs_step_rot},
      {"threshold_dist", o.threshold_dist, r.threshold_dist},
      {"alfa", o.alfa, r.alfa},
      {"smallest_threshold_dist", o.smallest_threshold_dist, r.smallest_threshold_dist},
      {"covariance_var_points", o.covariance_var_points, r.covariance_var_points},
      {"kernel_rho", o.kernel_rho, r.kernel_rho},
      {"lm_initial_lambda", o.lm_initial_lambda, r.lm_initial_lambda},
      {"axy_aprox_derivatives", o.axy_aprox_derivatives, r.axy_aprox_derivatives},
      {"ransac.mahalanobis_threshold", o.ransac.mahalanobis_threshold,
       r.ransac.mahalanobis_threshold},
      {"ransac.normalization_std", o.ransac.normalization_std, r.ransac.normalization_std},
      {"ransac.fuse_max_diff_xy", o.ransac.fuse_max_diff_xy, r.ransac.fuse_max_diff_xy},
  };
  for (const auto& f : fields) {
    const double nearest_float = static_cast<float>(f.given);
    ASSERT_NE(nearest_float, f.given) << f.name;
    EXPECT_EQ(f.rounded, nearest_float)
        << f.name << ": " << std::setprecision(17) << f.rounded << ", not the float "
        << nearest_float;
  }
  // The angles: MRPT's DEG2RAD of its float read of the degrees, in float.
  const auto mrpt_rad = [](double rad) {
    return static_cast<double>(static_cast<float>(rad_to_deg(rad)) *
                               std::numbers::pi_v<float> / 180.0f);
  };
  EXPECT_EQ(r.threshold_ang, mrpt_rad(o.threshold_ang));
  EXPECT_EQ(r.ransac.fuse_max_diff_phi, mrpt_rad(o.ransac.fuse_max_diff_phi));
}

// The default arithmetic is double: far from the origin it is as exact as
// at the origin, where MRPT's float sums (raw, uncentered coordinates) and
// float points lose precision. A room 2 km from the map's origin, the scan
// made of map points, the guess close enough that every pair is right from
// the first pairing: the closed-form fit gives the truth.
TEST(Icp2d, DoubleArithmeticStaysExactFarFromTheOrigin) {
  const Eigen::Vector2d far(2000.0, -1500.0);
  auto map = room(0.1);
  for (auto& p : map) p += far;
  const SE2d guess(far.x(), far.y(), 0.0);
  const Pose2 truth(far.x() + 0.01, far.y() - 0.008, deg_to_rad(0.1));
  const auto scan = as_seen_from(map, truth, 0.0, 11);
  Icp2dOptions o = accurate_options();
  const auto d = icp_2d(IcpTarget2D(map), scan, guess, o);
  ASSERT_EQ(d.termination, RegistrationTermination::Converged) << d.message;
  const double err_double = to_pose2(d.T_target_source).distance_to(truth);
  IcpTarget2DOptions mrpt_target;
  mrpt_target.arithmetic = Arithmetic::Mrpt;
  o.arithmetic = Arithmetic::Mrpt;
  const auto f = icp_2d(IcpTarget2D(map, mrpt_target), scan, guess, o);
  const double err_mrpt = to_pose2(f.T_target_source).distance_to(truth);
  std::printf("2 km from the origin: position error %.3g m (double), %.3g m (MRPT's float)\n",
              err_double, err_mrpt);
  EXPECT_LT(err_double, 1e-8);
  EXPECT_LT(std::abs(wrap_to_pi(d.T_target_source.angle() - truth.phi())), 1e-10);
  EXPECT_FALSE(err_mrpt <= err_double);  // (also when MRPT's run diverged: NaN)
}

// A target built for one arithmetic and an ICP in the other is a caller
// bug, said by name.
TEST(Icp2d, ArithmeticOfTargetAndIcpMustAgree) {
  const auto map = room(0.1);
  Icp2dOptions o;
  o.arithmetic = Arithmetic::Mrpt;
  try {
    (void)icp_2d(IcpTarget2D(map), map, SE2d(), o);
    FAIL() << "a double target was accepted by an MRPT-arithmetic ICP";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("arithmetic"), std::string::npos) << e.what();
  }
}

TEST(Icp2d, MrptDecimationUsesEveryPointOverTheRun) {
  const auto map = room(0.02);
  const Pose2 truth(0.1, 0.05, deg_to_rad(3));
  const auto scan = as_seen_from(room(0.05), truth, 0.003, 3);
  auto o = accurate_options();
  o.corresponding_points_decimation = 5;
  o.only_unique_robust = true;
  o.min_abs_step_trans = 1e-4;  // with noise, rotating subsets never repeat a step exactly
  o.min_abs_step_rot = 1e-4;
  const auto r = icp_2d(IcpTarget2D(map), scan, SE2d(), o);
  ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  expect_pose_near(to_pose2(r.T_target_source), truth, 0.01, deg_to_rad(0.3));
  // MRPT's goodness scales the count by the decimation: still ≈ 1.
  EXPECT_GT(r.goodness, 0.95);
}

TEST(Icp2d, CorridorIsReportedDegenerate) {
  const auto map = corridor(0.05);
  const Pose2 truth(0.3, 0.1, deg_to_rad(2));
  const auto scan = as_seen_from(map, truth, 0.0, 4);
  for (auto metric : {Icp2dMetric::PointToPoint, Icp2dMetric::PointToLine}) {
    IcpTarget2DOptions topt;
    topt.normal_neighbors = 5;
    auto o = accurate_options();
    o.metric = metric;
    const auto r = icp_2d(IcpTarget2D(map, topt), scan, SE2d(), o);
    EXPECT_EQ(r.termination, RegistrationTermination::Degenerate) << r.message;
    EXPECT_LT(r.conditioning, 1e-3);
    // The constrained directions are still right: y and phi.
    EXPECT_NEAR(r.T_target_source.translation().y(), 0.1, 1e-3);
    EXPECT_NEAR(r.T_target_source.angle(), deg_to_rad(2), 1e-3);
  }
}

TEST(Icp2d, AgainstAnOccupancyGrid) {
  OccupancyGrid grid(-6, 6, -4, 4, 0.05f);
  const auto walls = room(0.01);
  for (const auto& p : walls)
    grid.set_free_probability(grid.x_to_idx(p.x()), grid.y_to_idx(p.y()), 0.05f);
  const IcpTarget2D target = IcpTarget2D::from_grid(grid);
  ASSERT_GT(target.size(), 500u);
  const Pose2 truth(0.2, 0.1, deg_to_rad(4));
  const auto scan = as_seen_from(room(0.05), truth, 0.003, 5);
  auto o = accurate_options();
  o.smallest_threshold_dist = 0.05;
  const auto r = icp_2d(target, scan, SE2d(), o);
  ASSERT_EQ(r.termination, RegistrationTermination::Converged) << r.message;
  // Cell centers quantize the walls to 5 cm: within a cell.
  expect_pose_near(to_pose2(r.T_target_source), truth, 0.05, deg_to_rad(0.5));
}

TEST(Icp2d, ParallelEqualsSerial) {
  const auto map = room(0.05);
  const auto scan = as_seen_from(map, Pose2(0.1, 0.2, 0.05), 0.01, 6);
  IcpTarget2DOptions topt;
  topt.normal_neighbors = 5;
  const IcpTarget2D target(map, topt);
  for (auto algo : {IcpAlgorithm::Classic, IcpAlgorithm::RobustLevenbergMarquardt}) {
    auto o = accurate_options();
    o.algorithm = algo;
    o.metric = Icp2dMetric::PointToLine;
    o.only_unique_robust = true;
    const auto a = icp_2d(target, scan, SE2d(), o);
    o.num_threads = 3;
    const auto b = icp_2d(target, scan, SE2d(), o);
    EXPECT_EQ(a.T_target_source.translation().x(), b.T_target_source.translation().x());
    EXPECT_EQ(a.T_target_source.angle(), b.T_target_source.angle());
    EXPECT_EQ(a.covariance, b.covariance);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.correspondences, b.correspondences);
  }
}

TEST(Icp2d, BadInputsGiveHonestTerminations) {
  const auto map = room(0.1);
  const IcpTarget2D target(map);
  std::vector<Eigen::Vector2d> empty;
  EXPECT_EQ(icp_2d(target, empty, SE2d()).termination, RegistrationTermination::InvalidInput);
  EXPECT_EQ(icp_2d(IcpTarget2D(), map, SE2d()).termination, RegistrationTermination::InvalidInput);
  std::vector<Eigen::Vector2d> nans(10, Eigen::Vector2d(std::nan(""), 0));
  EXPECT_EQ(icp_2d(target, nans, SE2d()).termination, RegistrationTermination::InvalidInput);
  // Far from the map: no pair within the gate.
  const auto r = icp_2d(target, map, SE2d(100, 100, 0));
  EXPECT_EQ(r.termination, RegistrationTermination::TooFewCorrespondences);
  EXPECT_EQ(r.T_target_source.translation().x(), 100.0);
  // Non-finite source points among good ones are skipped.
  auto mixed = as_seen_from(map, Pose2(0.05, 0, 0), 0, 7);
  mixed.push_back({std::nan(""), 1.0});
  mixed.push_back({INFINITY, 1.0});
  const auto rm = icp_2d(target, mixed, SE2d(), accurate_options());
  EXPECT_EQ(rm.termination, RegistrationTermination::Converged) << rm.message;
  // Point-to-line without normals is a caller bug.
  auto o = accurate_options();
  o.metric = Icp2dMetric::PointToLine;
  EXPECT_THROW(icp_2d(target, map, SE2d(), o), InvalidArgument);
}

TEST(Icp2d, MaxIterationsIsNotConverged) {
  const auto map = room(0.05);
  const auto scan = as_seen_from(map, Pose2(0.3, 0.2, 0.1), 0.0, 8);
  auto o = accurate_options();
  o.max_iterations = 2;
  o.alfa = 0.9;
  const auto r = icp_2d(IcpTarget2D(map), scan, SE2d(), o);
  EXPECT_EQ(r.termination, RegistrationTermination::MaxIterations) << r.message;
  EXPECT_GE(r.iterations, 2u);
}

// The options of an [ICP] section given as text.
Icp2dOptions icp_options(const std::string& text, const std::string& file = "<string>") {
  const IniFile ini = IniFile::parse(text, file);
  return Icp2dOptions::from_config(ConfigSection(ini, "ICP"));
}

TEST(Icp2dOptions, LoadsMrptIcpSlamSection) {
  const std::string path = std::string(ROVE_SOURCE_DIR) + "/data/mrpt/icp-slam_demo_classic.ini";
  const IniFile ini = IniFile::load(path);
  const Icp2dOptions o = Icp2dOptions::from_config(ConfigSection(ini, "ICP"));
  EXPECT_EQ(o.max_iterations, 80u);
  // The values as written (double); MRPT's float reads are part of
  // Arithmetic::Mrpt, applied when an ICP runs in it.
  EXPECT_EQ(o.threshold_dist, 0.3);
  EXPECT_DOUBLE_EQ(o.threshold_ang, deg_to_rad(5.0));
  EXPECT_EQ(o.alfa, 0.8);
  EXPECT_EQ(o.smallest_threshold_dist, 0.05);
  EXPECT_EQ(o.min_abs_step_trans, 1e-6);
  EXPECT_EQ(o.kernel_rho, 0.07);
  EXPECT_EQ(o.axy_aprox_derivatives, 0.05);
  EXPECT_TRUE(o.only_closest_correspondences);
  EXPECT_TRUE(o.only_unique_robust);
  EXPECT_EQ(o.algorithm, IcpAlgorithm::Classic);
  EXPECT_EQ(o.corresponding_points_decimation, 5u);
  const IniFile lm = IniFile::load(std::string(ROVE_SOURCE_DIR) + "/data/mrpt/icp-slam_demo_LM.ini");
  EXPECT_EQ(Icp2dOptions::from_config(ConfigSection(lm, "ICP")).algorithm,
            IcpAlgorithm::LevenbergMarquardt);
  // rove's own key: the arithmetic (double unless said).
  EXPECT_EQ(o.arithmetic, Arithmetic::Double);
  EXPECT_EQ(icp_options("[ICP]\narithmetic = mrpt\n").arithmetic, Arithmetic::Mrpt);
  EXPECT_EQ(icp_options("[ICP]\narithmetic = double\n").arithmetic, Arithmetic::Double);
  try {
    (void)icp_options("[ICP]\narithmetic = single\n", "f.ini");
    FAIL() << "an unknown arithmetic was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "arithmetic");
    EXPECT_EQ(e.file(), "f.ini");
  }
}

TEST(Icp2dOptions, UnknownAndMalformedKeysAreReported) {
  const IniFile ini = IniFile::parse("[ICP]\nmaxIterations = 10\nthresholdDsit = 0.3\n", "t.ini");
  try {
    (void)Icp2dOptions::from_config(ConfigSection(ini, "ICP"));
    FAIL() << "no error for an unknown key";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "thresholdDsit");
    EXPECT_EQ(e.file(), "t.ini");
  }
  EXPECT_THROW(icp_options("[ICP]\nALFA = 1.5\n"), ConfigError);
  EXPECT_THROW(icp_options("[ICP]\nALFA = abc\n"), ConfigError);
  EXPECT_THROW(icp_options("[ICP]\nrobust_kernel = nope\n"),
               ConfigError);
  EXPECT_EQ(icp_options("[ICP]\nrobust_kernel = huber:0.1\n")
                .robust_kernel->type(),
            RobustKernelType::Huber);
}

TEST(Icp2dOptions, LevenbergMarquardtFlavoursAndTheirKeys) {
  const IniFile ini = IniFile::parse(
      "[A]\nICP_algorithm = icpRobustLevenbergMarquardt\n"
      "[B]\nICP_algorithm = icpLevenbergMarquardt\nAxy_aprox_derivatives = 0.02\n"
      "[C]\nICP_algorithm = icpLevenbergMarquardt\nmetric = point_to_line\n",
      "t.ini");
  EXPECT_EQ(Icp2dOptions::from_config(ConfigSection(ini, "A")).algorithm,
            IcpAlgorithm::RobustLevenbergMarquardt);
  const auto b = Icp2dOptions::from_config(ConfigSection(ini, "B"));
  EXPECT_EQ(b.algorithm, IcpAlgorithm::LevenbergMarquardt);
  EXPECT_EQ(b.axy_aprox_derivatives, 0.02);
  // MRPT's LM is point-to-point only: said by name, not silently changed.
  try {
    (void)Icp2dOptions::from_config(ConfigSection(ini, "C"));
    FAIL() << "point-to-line with MRPT's LM was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("icpRobustLevenbergMarquardt"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rove
