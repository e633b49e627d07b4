#include "rove/obs/range_image_3d.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

// A 4x3 depth image seen by a camera with fx = fy = 2, cx = 1.5, cy = 1:
// every pixel at 2 m except (0,0) (no return) and (1,0) (beyond max_range).
RangeImage3D make_rgbd() {
  RangeImage3D obs;
  obs.depth_camera.width = 4;
  obs.depth_camera.height = 3;
  obs.depth_camera.fx = 2.0;
  obs.depth_camera.fy = 2.0;
  obs.depth_camera.cx = 1.5;
  obs.depth_camera.cy = 1.0;
  obs.max_range = 5.0;
  obs.depth = DepthImage::zeros_u16(4, 3, 1000.0);
  auto& v = std::get<std::vector<std::uint16_t>>(obs.depth.values);
  for (auto& d : v) d = 2000;
  v[0] = 0;
  v[1] = 9000;
  return obs;
}

TEST(RangeImage3D, PinholeProjectionIsExactInTheOpticalFrame) {
  const RangeImage3D obs = make_rgbd();
  const RangeImageProjection p = obs.project({RangeImageFrame::Optical, std::nullopt});
  ASSERT_EQ(p.points.size(), 10u);
  for (std::size_t k = 0; k < p.points.size(); ++k) {
    const double u = p.pixel_u[k], v = p.pixel_v[k];
    EXPECT_FALSE(v == 0 && u < 2) << "invalid pixel projected";
    // z = d/scale, x = (u − cx)·z/fx, y = (v − cy)·z/fy, exact in binary.
    EXPECT_EQ(p.points[k].z(), 2.0);
    EXPECT_EQ(p.points[k].x(), (u - 1.5) * 2.0 / 2.0);
    EXPECT_EQ(p.points[k].y(), (v - 1.0) * 2.0 / 2.0);
  }
  // Row-major order: first kept pixel is (2, 0).
  EXPECT_EQ(p.pixel_u[0], 2u);
  EXPECT_EQ(p.pixel_v[0], 0u);
}

TEST(RangeImage3D, SensorFrameIsXForwardYLeftZUp) {
  const RangeImage3D obs = make_rgbd();
  const auto optical = obs.project({RangeImageFrame::Optical, std::nullopt});
  const auto sensor = obs.project({RangeImageFrame::Sensor, std::nullopt});
  ASSERT_EQ(optical.points.size(), sensor.points.size());
  for (std::size_t k = 0; k < sensor.points.size(); ++k) {
    EXPECT_NEAR(sensor.points[k].x(), optical.points[k].z(), 1e-12);
    EXPECT_NEAR(sensor.points[k].y(), -optical.points[k].x(), 1e-12);
    EXPECT_NEAR(sensor.points[k].z(), -optical.points[k].y(), 1e-12);
  }
}

TEST(RangeImage3D, RobotAndTargetFrames) {
  RangeImage3D obs = make_rgbd();
  obs.T_robot_sensor = Pose3(0.5, 0.0, 1.0, kPi / 2, 0.0, 0.0);
  const Pose3 T_world_robot(10.0, 20.0, 0.0, kPi, 0.0, 0.0);
  const auto sensor = obs.project({RangeImageFrame::Sensor, std::nullopt});
  const auto robot = obs.project({RangeImageFrame::Robot, std::nullopt});
  const auto world = obs.project({RangeImageFrame::Robot, T_world_robot});
  ASSERT_EQ(sensor.points.size(), world.points.size());
  for (std::size_t k = 0; k < sensor.points.size(); ++k) {
    const Eigen::Vector3d& s = sensor.points[k];
    // yaw 90°: (x, y, z) -> (−y, x, z), then + (0.5, 0, 1).
    EXPECT_NEAR(robot.points[k].x(), -s.y() + 0.5, 1e-12);
    EXPECT_NEAR(robot.points[k].y(), s.x(), 1e-12);
    EXPECT_NEAR(robot.points[k].z(), s.z() + 1.0, 1e-12);
    // yaw 180°: (x, y) -> (−x, −y), then + (10, 20).
    EXPECT_NEAR(world.points[k].x(), 10.0 - robot.points[k].x(), 1e-12);
    EXPECT_NEAR(world.points[k].y(), 20.0 - robot.points[k].y(), 1e-12);
    EXPECT_NEAR(world.points[k].z(), robot.points[k].z(), 1e-12);
  }
}

TEST(RangeImage3D, RangeImagesScaleTheUnitRay) {
  RangeImage3D obs = make_rgbd();
  obs.range_is_depth = false;
  const auto p = obs.project({RangeImageFrame::Optical, std::nullopt});
  ASSERT_EQ(p.points.size(), 10u);
  for (std::size_t k = 0; k < p.points.size(); ++k) {
    EXPECT_NEAR(p.points[k].norm(), 2.0, 1e-12);
    const double u = p.pixel_u[k], v = p.pixel_v[k];
    EXPECT_NEAR(p.points[k].x() / p.points[k].z(), (u - 1.5) / 2.0, 1e-12);
    EXPECT_NEAR(p.points[k].y() / p.points[k].z(), (v - 1.0) / 2.0, 1e-12);
  }
}

TEST(RangeImage3D, FloatImagesSkipNanNegativeAndFar) {
  RangeImage3D obs = make_rgbd();
  obs.depth = DepthImage::zeros_f32(4, 3, 1.0);
  auto& v = std::get<std::vector<float>>(obs.depth.values);
  for (auto& d : v) d = 1.25f;
  v[3] = std::numeric_limits<float>::quiet_NaN();
  v[4] = -1.0f;
  v[5] = 5.0f;   // exactly max_range: kept
  v[6] = 5.01f;  // beyond: dropped
  v[7] = std::numeric_limits<float>::infinity();
  const auto p = obs.project({RangeImageFrame::Optical, std::nullopt});
  EXPECT_EQ(p.points.size(), 8u);
  for (const auto& q : p.points) EXPECT_TRUE(q.allFinite());
}

TEST(RangeImage3D, DistortedCameraRoundTrips) {
  PinholeCamera cam;
  cam.width = 640;
  cam.height = 480;
  cam.fx = 525.0;
  cam.fy = 520.0;
  cam.cx = 319.5;
  cam.cy = 239.5;
  cam.distortion = {-0.28, 0.07, 1e-3, -5e-4, 0.01};
  for (const double u : {0.0, 100.0, 319.5, 500.0, 639.0}) {
    for (const double v : {0.0, 200.0, 479.0}) {
      const Eigen::Vector3d ray = cam.unproject(u, v);
      EXPECT_EQ(ray.z(), 1.0);
      const Eigen::Vector2d px = cam.project(3.0 * ray);
      EXPECT_NEAR(px.x(), u, 1e-8);
      EXPECT_NEAR(px.y(), v, 1e-8);
    }
  }
  // Without distortion, unproject is the closed form.
  cam.distortion = {};
  const Eigen::Vector3d r = cam.unproject(100.0, 50.0);
  EXPECT_EQ(r.x(), (100.0 - 319.5) / 525.0);
  EXPECT_EQ(r.y(), (50.0 - 239.5) / 520.0);
}

TEST(RangeImage3D, DefaultIntensityPoseIsTheOpticalRotation) {
  const Pose3 T = sensor_from_optical();
  // Optical z (forward) is sensor x, optical x (right) is sensor −y, optical y (down) is −z.
  EXPECT_TRUE(T.rotation().col(2).isApprox(Eigen::Vector3d(1, 0, 0), 1e-15));
  EXPECT_TRUE(T.rotation().col(0).isApprox(Eigen::Vector3d(0, -1, 0), 1e-15));
  EXPECT_TRUE(T.rotation().col(1).isApprox(Eigen::Vector3d(0, 0, -1), 1e-15));
  EXPECT_EQ(RangeImage3D().T_sensor_intensity, T);
}

TEST(RangeImage3D, BadInputIsRejected) {
  RangeImage3D zero_f = make_rgbd();
  zero_f.depth_camera.fx = 0.0;
  EXPECT_THROW((void)zero_f.project(), InvalidArgument);
  RangeImage3D nan_c = make_rgbd();
  nan_c.depth_camera.cy = std::nan("");
  EXPECT_THROW((void)nan_c.project(), InvalidArgument);
  RangeImage3D wrong_size = make_rgbd();
  wrong_size.depth_camera.width = 5;
  EXPECT_THROW((void)wrong_size.project(), InvalidArgument);
  RangeImage3D short_data = make_rgbd();
  std::get<std::vector<std::uint16_t>>(short_data.depth.values).pop_back();
  EXPECT_THROW((void)short_data.project(), InvalidArgument);
  RangeImage3D bad_scale = make_rgbd();
  bad_scale.depth.scale = 0.0;
  EXPECT_THROW((void)bad_scale.project(), InvalidArgument);
  PinholeCamera cam = make_rgbd().depth_camera;
  EXPECT_THROW((void)cam.project(Eigen::Vector3d(0, 0, -1)), InvalidArgument);
  DepthImage d = DepthImage::zeros_u16(2, 2, 1000.0);
  EXPECT_THROW(d.set_meters(0, 0, 70.0), InvalidArgument);  // 70000 units > 65535
  d.set_meters(1, 1, 1.2344);
  EXPECT_DOUBLE_EQ(d.meters(1, 1), 1.234);
}

}  // namespace
}  // namespace rove
