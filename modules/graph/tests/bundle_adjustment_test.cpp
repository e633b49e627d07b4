// Bundle adjustment against known answers: synthetic cameras looking at a
// cloud of points, exact and noisy measurements, gross outliers, depth,
// relative poses, and bad input.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/graph/bundle_adjustment.h"

namespace rove {
namespace {

constexpr double kF = 500.0;

struct Scene {
  std::vector<SE3d> cameras;           // true T_world_camera
  std::vector<Eigen::Vector3d> points; // true
  BundleAdjustmentProblem problem;     // measurements of the true scene
};

// `n_cameras` cameras on an arc 2 m from a box of points around (0, 0, 3),
// each looking at the box's centre; every point seen by every camera that
// has it in front within a 640×480 image.
Scene make_scene(int n_cameras, int n_points, bool depth, double pixel_noise, double inverse_depth_noise,
                 unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> box(-1.0, 1.0);
  std::normal_distribution<double> px(0.0, pixel_noise > 0 ? pixel_noise : 1.0);
  std::normal_distribution<double> id(0.0, inverse_depth_noise > 0 ? inverse_depth_noise : 1.0);
  Scene s;
  const Eigen::Vector3d centre(0, 0, 3);
  for (int i = 0; i < n_cameras; ++i) {
    const double a = -0.4 + 0.8 * i / std::max(1, n_cameras - 1);
    const Eigen::Vector3d eye = centre + Eigen::Vector3d(2.5 * std::sin(a), 0.1 * i, -2.5 * std::cos(a));
    const Eigen::Vector3d z = (centre - eye).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    Eigen::Matrix3d R;
    R.col(0) = x;
    R.col(1) = z.cross(x);
    R.col(2) = z;
    s.cameras.emplace_back(SO3d(R), eye);
  }
  for (int j = 0; j < n_points; ++j) s.points.push_back(centre + Eigen::Vector3d(box(rng), box(rng), box(rng)));
  BundleAdjustmentProblem& p = s.problem;
  p.fx = p.fy = kF;
  p.T_world_camera = s.cameras;
  p.points_world = s.points;
  for (std::size_t i = 0; i < s.cameras.size(); ++i) {
    for (std::size_t j = 0; j < s.points.size(); ++j) {
      const Eigen::Vector3d c = s.cameras[i].inverse() * s.points[j];
      const Eigen::Vector2d uv = kF * c.head<2>() / c.z();
      if (c.z() < 0.1 || std::abs(uv.x()) > 320 || std::abs(uv.y()) > 240) continue;
      BaObservation o;
      o.camera = i;
      o.point = j;
      o.normalized = c.head<2>() / c.z();
      if (pixel_noise > 0) o.normalized += Eigen::Vector2d(px(rng), px(rng)) / kF;
      o.sigma_px = pixel_noise > 0 ? pixel_noise : 1.0;
      if (depth) {
        o.inverse_depth = 1.0 / c.z() + (inverse_depth_noise > 0 ? id(rng) : 0.0);
        o.sigma_inverse_depth = inverse_depth_noise > 0 ? inverse_depth_noise : 0.01;
      }
      p.observations.push_back(o);
    }
  }
  return s;
}

// Moves every camera but the first and every point.
void perturb(BundleAdjustmentProblem& p, double meters, double radians, double point_meters, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t i = 1; i < p.T_world_camera.size(); ++i) {
    Eigen::Matrix<double, 6, 1> xi;
    xi << meters * n(rng), meters * n(rng), meters * n(rng), radians * n(rng), radians * n(rng), radians * n(rng);
    p.T_world_camera[i] = p.T_world_camera[i] * SE3d::exp(xi);
  }
  for (auto& x : p.points_world) x += point_meters * Eigen::Vector3d(n(rng), n(rng), n(rng));
}

double max_camera_error(const Scene& s, double* rotation = nullptr) {
  double worst = 0.0, worst_rot = 0.0;
  for (std::size_t i = 0; i < s.cameras.size(); ++i) {
    const auto xi = (s.cameras[i].inverse() * s.problem.T_world_camera[i]).log();
    worst = std::max(worst, xi.head<3>().norm());
    worst_rot = std::max(worst_rot, xi.tail<3>().norm());
  }
  if (rotation) *rotation = worst_rot;
  return worst;
}

// Over the points at least `min_views` cameras see (a point seen once
// without depth, or not at all, keeps its start value).
double max_point_error(const Scene& s, int min_views = 1) {
  std::vector<int> views(s.points.size(), 0);
  for (const BaObservation& o : s.problem.observations) ++views[o.point];
  double worst = 0.0;
  for (std::size_t j = 0; j < s.points.size(); ++j) {
    if (views[j] >= min_views) worst = std::max(worst, (s.points[j] - s.problem.points_world[j]).norm());
  }
  return worst;
}

std::size_t seen_points(const Scene& s) {
  std::vector<bool> seen(s.points.size(), false);
  for (const BaObservation& o : s.problem.observations) seen[o.point] = true;
  return static_cast<std::size_t>(std::count(seen.begin(), seen.end(), true));
}

TEST(BundleAdjustment, RecoversExactCamerasAndPointsWithDepth) {
  Scene s = make_scene(6, 150, true, 0.0, 0.0, 1);
  perturb(s.problem, 0.05, 0.03, 0.05, 2);
  ASSERT_GT(max_camera_error(s), 0.02);
  const BundleAdjustmentResult r = bundle_adjust(s.problem);
  ASSERT_TRUE(r.ok()) << r.message;
  double rot = 0.0;
  EXPECT_LT(max_camera_error(s, &rot), 1e-6);
  EXPECT_LT(rot, 1e-7);
  EXPECT_LT(max_point_error(s), 1e-6);
  EXPECT_EQ(r.outliers, 0u);
  EXPECT_LT(r.rmse_px, 1e-5);
  EXPECT_LE(r.iterations, 20) << "Gauss-Newton on exact data converges quadratically: the Jacobians are right";
  EXPECT_EQ(r.cameras_adjusted, 5u);
  EXPECT_EQ(r.points_adjusted, seen_points(s));
  EXPECT_GT(seen_points(s), 140u);
}

TEST(BundleAdjustment, RecoversExactSceneFromImagesAloneWithTwoCamerasFixed) {
  Scene s = make_scene(5, 120, false, 0.0, 0.0, 3);
  s.problem.fixed = {true, false, false, false, true};  // two fixed cameras set the scale
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t i = 1; i + 1 < s.problem.T_world_camera.size(); ++i) {
    Eigen::Matrix<double, 6, 1> xi;
    xi << 0.02 * n(rng), 0.02 * n(rng), 0.02 * n(rng), 0.01 * n(rng), 0.01 * n(rng), 0.01 * n(rng);
    s.problem.T_world_camera[i] = s.problem.T_world_camera[i] * SE3d::exp(xi);
  }
  for (auto& x : s.problem.points_world) x += 0.02 * Eigen::Vector3d(n(rng), n(rng), n(rng));
  const BundleAdjustmentResult r = bundle_adjust(s.problem);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(max_camera_error(s), 1e-6);
  EXPECT_LT(max_point_error(s, 2), 1e-5);
  EXPECT_EQ(r.cameras_adjusted, 3u);
}

TEST(BundleAdjustment, NoisyMeasurementsGiveCamerasWithinTheirNoise) {
  // 0.5 px and an inverse-depth noise of 0.002 /m (about 2 cm at 3 m).
  Scene s = make_scene(6, 300, true, 0.5, 0.002, 5);
  perturb(s.problem, 0.05, 0.03, 0.05, 6);
  const double before = max_camera_error(s);
  const BundleAdjustmentResult r = bundle_adjust(s.problem);
  ASSERT_TRUE(r.improved()) << r.message;
  double rot = 0.0;
  const double after = max_camera_error(s, &rot);
  EXPECT_LT(after, 0.005) << "from " << before;
  EXPECT_LT(rot, 0.002);
  EXPECT_NEAR(r.rmse_px, 0.5 * std::sqrt(2.0), 0.15);  // 2D residual of σ = 0.5 per axis
  // About 5 % of 3D observations lie beyond χ²₃'s 95 % bound after round 1.
  EXPECT_LT(r.outliers, r.inlier.size() / 10);
}

TEST(BundleAdjustment, GrossOutliersAreDroppedAndDoNotMoveTheCameras) {
  Scene s = make_scene(6, 300, true, 0.5, 0.002, 7);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> img(-0.5, 0.5);
  std::vector<bool> corrupted(s.problem.observations.size(), false);
  for (std::size_t k = 0; k < s.problem.observations.size(); k += 10) {
    s.problem.observations[k].normalized = Eigen::Vector2d(img(rng), img(rng));  // ±250 px
    corrupted[k] = true;
  }
  perturb(s.problem, 0.02, 0.01, 0.02, 9);
  BundleAdjustmentOptions o;
  o.rounds = 3;
  const BundleAdjustmentResult r = bundle_adjust(s.problem, o);
  ASSERT_TRUE(r.improved()) << r.message;
  std::size_t caught = 0, wrongly = 0, n_corrupted = 0;
  for (std::size_t k = 0; k < corrupted.size(); ++k) {
    n_corrupted += corrupted[k];
    if (corrupted[k] && !r.inlier[k]) ++caught;
    if (!corrupted[k] && !r.inlier[k]) ++wrongly;
  }
  EXPECT_GE(caught, n_corrupted * 95 / 100);
  EXPECT_LT(wrongly, (corrupted.size() - n_corrupted) / 10);
  EXPECT_LT(max_camera_error(s), 0.006);
}

TEST(BundleAdjustment, RelativePosesAloneMoveACameraToTheMeasurement) {
  BundleAdjustmentProblem p;
  p.fx = p.fy = kF;
  const SE3d a(SO3d::rot_z(0.3), Eigen::Vector3d(1, 2, 3));
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.4, -0.2, 0.1, 0.05, -0.3, 0.2;
  const SE3d T_a_b = SE3d::exp(xi);
  p.T_world_camera = {a, a};  // b starts at a
  BaRelativePose rel;
  rel.from = 0;
  rel.to = 1;
  rel.T_from_to = T_a_b;
  rel.information = Eigen::Matrix<double, 6, 6>::Identity() * 100.0;
  p.relative_poses.push_back(rel);
  const BundleAdjustmentResult r = bundle_adjust(p);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE((a * T_a_b).is_approx(p.T_world_camera[1], 1e-8));
  EXPECT_TRUE(a.is_approx(p.T_world_camera[0], 0.0));
  EXPECT_LT(r.final_cost, 1e-12);
}

TEST(BundleAdjustment, RelativePosesAndImagesAgreeOnTheExactScene) {
  Scene s = make_scene(4, 100, true, 0.0, 0.0, 10);
  for (std::size_t i = 0; i + 1 < s.cameras.size(); ++i) {
    BaRelativePose rel;
    rel.from = i;
    rel.to = i + 1;
    rel.T_from_to = s.cameras[i].inverse() * s.cameras[i + 1];
    rel.information = Eigen::Matrix<double, 6, 6>::Identity() * 1e4;
    s.problem.relative_poses.push_back(rel);
  }
  perturb(s.problem, 0.03, 0.02, 0.03, 11);
  const BundleAdjustmentResult r = bundle_adjust(s.problem);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(max_camera_error(s), 1e-6);
  EXPECT_LT(r.final_cost, 1e-9);
}

TEST(BundleAdjustment, BadProblemsAreRefusedNamingTheEntryAndLeftUntouched) {
  Scene s = make_scene(3, 20, true, 0.0, 0.0, 12);
  const SE3d before = s.problem.T_world_camera[1];
  auto expect_invalid = [&](BundleAdjustmentProblem p, const std::string& needle) {
    const BundleAdjustmentResult r = bundle_adjust(p);
    EXPECT_EQ(r.termination, GraphTermination::InvalidInput);
    EXPECT_NE(r.message.find(needle), std::string::npos) << r.message;
    EXPECT_TRUE(p.T_world_camera[1].is_approx(before, 0.0));
  };
  BundleAdjustmentProblem p = s.problem;
  p.observations[3].camera = 7;
  expect_invalid(p, "observation 3: camera 7 of 3");
  p = s.problem;
  p.observations[2].point = 99;
  expect_invalid(p, "observation 2: point 99");
  p = s.problem;
  p.observations[1].normalized.x() = std::nan("");
  expect_invalid(p, "observation 1");
  p = s.problem;
  p.observations[0].inverse_depth = -1.0;
  expect_invalid(p, "inverse depth must be positive");
  p = s.problem;
  p.observations[0].sigma_px = 0.0;
  expect_invalid(p, "sigma_px");
  p = s.problem;
  p.fixed = {false, false, false};
  expect_invalid(p, "no camera is fixed");
  p = s.problem;
  p.fixed = {true};
  expect_invalid(p, "fixed has 1 entries for 3 cameras");
  p = s.problem;
  p.points_world[4].y() = INFINITY;
  expect_invalid(p, "point 4");
  p = s.problem;
  p.fx = 0.0;
  expect_invalid(p, "focal lengths");
  p = s.problem;
  p.relative_poses.push_back({1, 1, SE3d(), Eigen::Matrix<double, 6, 6>::Identity()});
  expect_invalid(p, "relative pose 0");
  BundleAdjustmentOptions o;
  o.rounds = 0;
  EXPECT_THROW(bundle_adjust(s.problem, o), InvalidArgument);
}

TEST(BundleAdjustment, PointsBehindACameraAreDroppedNotFollowed) {
  Scene s = make_scene(4, 80, true, 0.0, 0.0, 13);
  // Observation 0's point moved behind its camera in the start values only.
  BundleAdjustmentProblem& p = s.problem;
  const BaObservation& o = p.observations[0];
  const SE3d T_cw = p.T_world_camera[o.camera].inverse();
  Eigen::Vector3d c = T_cw * p.points_world[o.point];
  c.z() = -c.z();
  p.points_world[o.point] = p.T_world_camera[o.camera] * c;
  const BundleAdjustmentResult r = bundle_adjust(p);
  ASSERT_TRUE(r.improved()) << r.message;
  EXPECT_LT(max_camera_error(s), 1e-5);
}

}  // namespace
}  // namespace rove
