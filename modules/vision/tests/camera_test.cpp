// Camera model round trips, undistortion and camera files.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/io/camera_file.h"
#include "rove/obs/pinhole_camera.h"
#include "rove/vision/undistort.h"

namespace rove {
namespace {

PinholeCamera tum_fr1() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 517.306;
  c.fy = 516.469;
  c.cx = 318.643;
  c.cy = 255.314;
  c.distortion = {0.262383, -0.953104, -0.005358, 0.002628, 1.163314};
  return c;
}

TEST(VisionCamera, ProjectUnprojectRoundTripWithDistortion) {
  const PinholeCamera c = tum_fr1();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(20.0, 620.0), v(20.0, 460.0), z(0.3, 6.0);
  for (int i = 0; i < 500; ++i) {
    const double pu = u(rng), pv = v(rng), depth = z(rng);
    const Eigen::Vector3d p = depth * c.unproject(pu, pv);
    EXPECT_NEAR(p.z(), depth, 1e-12);
    const Eigen::Vector2d back = c.project(p);
    EXPECT_NEAR(back.x(), pu, 1e-7);
    EXPECT_NEAR(back.y(), pv, 1e-7);
  }
}

TEST(VisionCamera, NegativeFocalLengthMirrorsTheImage) {
  PinholeCamera c;
  c.fx = 481.2;
  c.fy = -480.0;  // ICL-NUIM
  c.cx = 319.5;
  c.cy = 239.5;
  const Eigen::Vector3d p(0.2, 0.3, 2.0);  // y > 0: up in ICL-NUIM's camera frame
  const Eigen::Vector2d px = c.project(p);
  EXPECT_LT(px.y(), c.cy);  // above the center row
  EXPECT_NEAR(px.y(), 239.5 - 480.0 * 0.15, 1e-12);
  EXPECT_TRUE((2.0 * c.unproject(px.x(), px.y())).isApprox(p, 1e-12));
  c.fy = 0.0;
  EXPECT_THROW(c.check(), InvalidArgument);
}

TEST(VisionCamera, UndistortPointsGivesTheIdealPixel) {
  const PinholeCamera c = tum_fr1();
  const PinholeCamera ideal = undistorted_camera(c);
  EXPECT_FALSE(ideal.has_distortion());
  const Eigen::Vector3d p(0.4, -0.25, 1.5);
  const std::vector<Eigen::Vector2d> distorted{c.project(p)};
  const auto out = undistort_points(c, distorted);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].isApprox(ideal.project(p), 1e-9));
}

// An image whose value is a smooth function of the ray, rendered by the
// distorted camera, undistorts to the same function rendered by the ideal one.
TEST(VisionCamera, UndistortImageMatchesTheIdealRendering) {
  PinholeCamera c = tum_fr1();
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 130.0;
  c.cx = 79.5;
  c.cy = 59.5;
  c.distortion = {-0.2, 0.05, 0.001, -0.001, 0.0};
  const auto value = [](const Eigen::Vector3d& ray) {
    return 1000.0 + 400.0 * ray.x() + 300.0 * ray.y() * ray.y();
  };
  Image distorted = Image::zeros(c.width, c.height, 1, PixelType::F32);
  for (std::uint32_t v = 0; v < c.height; ++v) {
    for (std::uint32_t u = 0; u < c.width; ++u) {
      const auto f = static_cast<float>(value(c.unproject(u, v)));
      std::memcpy(distorted.data.data() + 4 * (v * c.width + u), &f, 4);
    }
  }
  const Image out = undistort_image(distorted, c);
  int compared = 0;
  for (std::uint32_t v = 10; v < c.height - 10; ++v) {
    for (std::uint32_t u = 10; u < c.width - 10; ++u) {
      float got = 0.0f;
      std::memcpy(&got, out.data.data() + 4 * (v * c.width + u), 4);
      const Eigen::Vector3d ray((u - c.cx) / c.fx, (v - c.cy) / c.fy, 1.0);
      EXPECT_NEAR(got, value(ray), 0.05) << u << "," << v;
      ++compared;
    }
  }
  EXPECT_GT(compared, 10000);
}

TEST(VisionCameraFile, ReadsTheTutorialParameters) {
  const CameraFile f = parse_camera_file(
      "# comment\ndetector=ORB\ngood_match_threshold=10\ncamera.cx=325.5;\ncamera.cy=253.5;\n"
      "camera.fx=518.0;\ncamera.fy=519.0;\ncamera.scale=1000.0;\n",
      "parameters.txt");
  EXPECT_EQ(f.format, CameraFileFormat::TutorialParameters);
  EXPECT_EQ(f.camera.fx, 518.0);
  EXPECT_EQ(f.camera.fy, 519.0);
  EXPECT_EQ(f.camera.cx, 325.5);
  EXPECT_EQ(f.camera.cy, 253.5);
  EXPECT_EQ(f.depth_scale, 1000.0);
  EXPECT_FALSE(f.camera.has_distortion());
}

TEST(VisionCameraFile, ReadsOrbSlamYaml) {
  const CameraFile f = parse_camera_file(
      "%YAML:1.0\n# TUM1\nCamera.fx: 517.306408\nCamera.fy: 516.469215\nCamera.cx: 318.643040\n"
      "Camera.cy: 255.313989\n\nCamera.k1: 0.262383\nCamera.k2: -0.953104\n"
      "Camera.p1: -0.005358\nCamera.p2: 0.002628\nCamera.k3: 1.163314\nCamera.width: 640\n"
      "Camera.height: 480\nCamera.fps: 30.0\nDepthMapFactor: 5000.0\n",
      "TUM1.yaml");
  EXPECT_EQ(f.format, CameraFileFormat::OrbSlamYaml);
  EXPECT_EQ(f.camera.fx, 517.306408);
  EXPECT_EQ(f.camera.distortion[4], 1.163314);
  EXPECT_EQ(f.camera.distortion[2], -0.005358);
  EXPECT_EQ(f.camera.width, 640u);
  EXPECT_EQ(f.camera.height, 480u);
  EXPECT_EQ(f.depth_scale, 5000.0);
}

TEST(VisionCameraFile, ReadsMrptCameraConfig) {
  const CameraFile f = parse_camera_file(
      "[CAMERA_PARAMS]\nresolution = [640 480]\ncx = 319.5\ncy = 239.5\nfx = 481.2\n"
      "fy = -480\ndist = [0.1 -0.2 0.001 0.002 0]\n",
      "camera.ini");
  EXPECT_EQ(f.format, CameraFileFormat::MrptConfig);
  EXPECT_EQ(f.camera.fy, -480.0);
  EXPECT_EQ(f.camera.width, 640u);
  EXPECT_EQ(f.camera.distortion[1], -0.2);
  EXPECT_FALSE(f.depth_scale.has_value());
}

TEST(VisionCameraFile, BadFilesNameTheSourceAndKey) {
  const auto message = [](std::string_view text) {
    try {
      parse_camera_file(text, "cam.txt");
    } catch (const ParseError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("hello world\n").find("not a camera file"), std::string::npos);
  EXPECT_NE(message("hello world\n").find("cam.txt"), std::string::npos);
  const std::string bad_number = message("camera.fx=5x18;\ncamera.fy=1\ncamera.cx=1\ncamera.cy=1\n");
  EXPECT_NE(bad_number.find("camera.fx"), std::string::npos) << bad_number;
  EXPECT_NE(bad_number.find(":1"), std::string::npos) << bad_number;
  EXPECT_NE(message("camera.fx=5\ncamera.fy=1\ncamera.cx=1\n").find("camera.cy"),
            std::string::npos);
  EXPECT_NE(message("fx = 0\nfy = 1\ncx = 1\ncy = 1\n").find("zero"), std::string::npos);
  EXPECT_NE(message("fx = 1\nfy = 1\ncx = 1\ncy = 1\ndist = [1 2]\n").find("dist"),
            std::string::npos);
  EXPECT_NE(message("Camera.fx: 1\nCamera.fy: 1\nCamera.cx: 1\nCamera.cy: 1\n"
                    "DepthMapFactor: -5\n").find("depth scale"),
            std::string::npos);
  EXPECT_THROW(read_camera_file("/nonexistent/camera.yaml"), IoError);
}

}  // namespace
}  // namespace rove
