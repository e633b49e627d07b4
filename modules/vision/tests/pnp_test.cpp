// PnP and the 3D–3D fit on synthetic cameras with known poses; matching
// against OpenCV's brute-force matcher; ORB on textured and flat images.
#include <cstring>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>

#include "rove/core/error.h"
#include "rove/vision/binary_matching.h"
#include "rove/vision/orb.h"
#include "rove/vision/pnp.h"
#include "rove/vision/rigid_ransac_3d.h"

namespace rove {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

PinholeCamera camera() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 520.0;
  c.fy = 515.0;
  c.cx = 320.0;
  c.cy = 240.0;
  c.distortion = {0.05, -0.1, 0.001, -0.001, 0.02};
  return c;
}

struct Scene {
  std::vector<Eigen::Vector3d> world;
  std::vector<Eigen::Vector2d> pixels;
  SE3d T_camera_world;
};

// n points in front of the camera, seen through T_camera_world.
Scene make_scene(std::size_t n, double pixel_noise, std::size_t outliers, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, pixel_noise);
  Scene s;
  s.T_camera_world = SE3d::exp((Vector6d() << 0.3, -0.2, 0.5, 0.2, -0.3, 0.1).finished());
  const PinholeCamera c = camera();
  while (s.world.size() < n) {
    const Eigen::Vector3d p_cam(1.5 * uni(rng), 1.1 * uni(rng), 3.0 + 1.5 * uni(rng));
    const Eigen::Vector2d px = c.project(p_cam);
    if (px.x() < 0 || px.y() < 0 || px.x() > 639 || px.y() > 479) continue;
    s.world.push_back(s.T_camera_world.inverse() * p_cam);
    s.pixels.push_back(px + (pixel_noise > 0 ? Eigen::Vector2d(noise(rng), noise(rng))
                                             : Eigen::Vector2d::Zero()));
  }
  for (std::size_t i = 0; i < outliers; ++i) {
    s.pixels[i] = Eigen::Vector2d(320 + 300 * uni(rng), 240 + 220 * uni(rng));
  }
  return s;
}

double rotation_error(const SE3d& a, const SE3d& b) { return (a.inverse() * b).log().tail<3>().norm(); }
double translation_error(const SE3d& a, const SE3d& b) {
  return (a.translation() - b.translation()).norm();
}

TEST(VisionPnp, NoiseFreeIsExact) {
  const Scene s = make_scene(60, 0.0, 0, 1);
  const PnpResult r = solve_pnp_ransac(s.world, s.pixels, camera());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.inliers.size(), 60u);
  EXPECT_LT(rotation_error(r.T_camera_world, s.T_camera_world), 1e-9);
  EXPECT_LT(translation_error(r.T_camera_world, s.T_camera_world), 1e-9);
  EXPECT_LT(r.rmse_px, 1e-6);
}

TEST(VisionPnp, NoisyIsWithinBoundsAndCovarianceIsCalibrated) {
  // Over many scenes with 0.5 px noise, the error's Mahalanobis distance
  // under the reported covariance averages the 6 degrees of freedom.
  double sum_d2 = 0.0;
  const int trials = 40;
  for (int t = 0; t < trials; ++t) {
    const Scene s = make_scene(100, 0.5, 0, 100 + static_cast<std::uint64_t>(t));
    const PnpResult r = solve_pnp_ransac(s.world, s.pixels, camera());
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_GE(r.inliers.size(), 97u);
    EXPECT_LT(rotation_error(r.T_camera_world, s.T_camera_world), 3e-3);
    EXPECT_LT(translation_error(r.T_camera_world, s.T_camera_world), 1e-2);
    EXPECT_NEAR(r.rmse_px, 0.5 * std::sqrt(2.0), 0.2);
    const Vector6d e = (r.T_camera_world.inverse() * s.T_camera_world).log();
    sum_d2 += e.dot(r.covariance.ldlt().solve(e));
  }
  EXPECT_NEAR(sum_d2 / trials, 6.0, 1.5);
}

TEST(VisionPnp, OutliersAreRejected) {
  const Scene s = make_scene(100, 0.3, 40, 7);
  const PnpResult r = solve_pnp_ransac(s.world, s.pixels, camera());
  ASSERT_TRUE(r.ok()) << r.message;
  for (const std::size_t i : r.inliers) {
    if (i < 40) {
      // A random pixel can land near the truth; it must then be consistent.
      EXPECT_LT((camera().project(s.T_camera_world * s.world[i]) - s.pixels[i]).norm(), 2.5);
    }
  }
  EXPECT_GE(r.inliers.size(), 58u);
  EXPECT_LT(rotation_error(r.T_camera_world, s.T_camera_world), 3e-3);
  EXPECT_LT(translation_error(r.T_camera_world, s.T_camera_world), 1e-2);
}

TEST(VisionPnp, TooFewOrBadPairsAreReported) {
  const Scene s = make_scene(8, 0.0, 0, 2);
  EXPECT_EQ(solve_pnp_ransac(s.world, s.pixels, camera()).termination,
            RegistrationTermination::TooFewCorrespondences);
  Scene t = make_scene(30, 0.0, 0, 3);
  t.world[4].x() = std::numeric_limits<double>::quiet_NaN();
  const PnpResult r = solve_pnp_ransac(t.world, t.pixels, camera());
  EXPECT_EQ(r.termination, RegistrationTermination::InvalidInput);
  EXPECT_NE(r.message.find("pair 4"), std::string::npos);
  EXPECT_THROW(solve_pnp_ransac(t.world, std::span(t.pixels).first(3), camera()), InvalidArgument);
}

TEST(VisionRigidRansac3d, RecoversThePoseDespiteOutliers) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uni(-2.0, 2.0);
  std::normal_distribution<double> noise(0.0, 0.003);
  const SE3d T = SE3d::exp((Vector6d() << 0.1, 0.4, -0.2, -0.1, 0.25, 0.05).finished());
  std::vector<Eigen::Vector3d> target, source;
  for (int i = 0; i < 120; ++i) {
    const Eigen::Vector3d s(uni(rng), uni(rng), 3.0 + uni(rng));
    source.push_back(s);
    target.push_back(i < 40 ? Eigen::Vector3d(uni(rng), uni(rng), uni(rng))
                            : Eigen::Vector3d(T * s + Eigen::Vector3d(noise(rng), noise(rng),
                                                                      noise(rng))));
  }
  const RigidRansac3dResult r = fit_rigid_3d_ransac(target, source);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.inliers.size(), 80u);
  EXPECT_EQ(r.inliers.front(), 40u);
  EXPECT_LT(rotation_error(r.T_target_source, T), 2e-3);
  EXPECT_LT(translation_error(r.T_target_source, T), 5e-3);
}

std::vector<OrbDescriptor> random_descriptors(std::size_t n, std::mt19937_64& rng) {
  std::vector<OrbDescriptor> d(n);
  for (auto& x : d)
    for (auto& b : x) b = static_cast<std::uint8_t>(rng());
  return d;
}

cv::Mat to_mat(const std::vector<OrbDescriptor>& d) {
  cv::Mat m(static_cast<int>(d.size()), 32, CV_8U);
  for (std::size_t i = 0; i < d.size(); ++i) std::memcpy(m.ptr(static_cast<int>(i)), d[i].data(), 32);
  return m;
}

TEST(VisionMatching, CrossCheckAgreesWithOpenCvBruteForce) {
  std::mt19937_64 rng(11);
  std::vector<OrbDescriptor> train = random_descriptors(300, rng);
  std::vector<OrbDescriptor> query = random_descriptors(200, rng);
  for (std::size_t i = 0; i < 150; ++i) {  // 150 queries are noisy copies of train
    query[i] = train[(i * 7) % 300];
    for (int flip = 0; flip < 12; ++flip) query[i][rng() % 32] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
  }
  BinaryMatchOptions o;
  o.ratio = 0.0;
  o.max_distance = 256;
  o.cross_check = true;
  const auto ours = match_binary(query, train, o);
  cv::BFMatcher bf(cv::NORM_HAMMING, true);
  std::vector<cv::DMatch> theirs;
  bf.match(to_mat(query), to_mat(train), theirs);
  ASSERT_EQ(ours.size(), theirs.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(static_cast<int>(ours[i].query), theirs[i].queryIdx);
    EXPECT_EQ(static_cast<int>(ours[i].train), theirs[i].trainIdx);
    EXPECT_EQ(static_cast<float>(ours[i].distance), theirs[i].distance);
  }
  // With the ratio test the copies are found and the random queries are not.
  o.ratio = 0.8;
  o.max_distance = 64;
  const auto filtered = match_binary(query, train, o);
  EXPECT_GE(filtered.size(), 140u);
  for (const auto& m : filtered) {
    EXPECT_LT(m.query, 150u);
    EXPECT_EQ(m.train, (m.query * 7) % 300);
  }
  EXPECT_TRUE(match_binary({}, train, o).empty());
}

TEST(VisionMatching, RelativeFactorIsTheTutorialRule) {
  std::mt19937_64 rng(2);
  std::vector<OrbDescriptor> train = random_descriptors(3, rng);
  std::vector<OrbDescriptor> query = train;
  query[1][0] ^= 0x0f;                       // distance 4
  for (int k = 0; k < 6; ++k) query[2][k] = static_cast<std::uint8_t>(~query[2][k]);  // 48
  BinaryMatchOptions o;
  o.ratio = 0.0;
  o.cross_check = false;
  o.relative_factor = 4.0;  // keep < 4·max(0, 10) = 40
  const auto m = match_binary(query, train, o);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[1].distance, 4u);
}

TEST(VisionOrb, TexturedImageHasFeaturesFlatImageHasNone) {
  // ORB on one thread: OpenCV's pool threads, left alive at exit, make
  // LeakSanitizer's tracer fail (a fatal error after every test passed).
  const int threads = cv::getNumThreads();
  cv::setNumThreads(0);
  Image flat = Image::zeros(320, 240, 1, PixelType::U8);
  std::fill(flat.data.begin(), flat.data.end(), 128);
  EXPECT_TRUE(extract_orb(flat).keypoints.empty());
  Image checker = flat;
  for (std::uint32_t v = 0; v < 240; ++v)
    for (std::uint32_t u = 0; u < 320; ++u)
      checker.data[v * 320 + u] = ((u / 20 + v / 20) % 2 != 0) ? 230 : 25;
  const Features f = extract_orb(checker);
  EXPECT_GT(f.keypoints.size(), 50u);
  EXPECT_EQ(f.keypoints.size(), f.descriptors.size());
  for (const Keypoint& k : f.keypoints) {
    EXPECT_GE(k.u, 0.0);
    EXPECT_LT(k.u, 320.0);
  }
  cv::setNumThreads(threads);
}

}  // namespace
}  // namespace rove
