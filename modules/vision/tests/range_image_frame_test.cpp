// RGB-D frames from 3D range observations: the depth registered to the
// intensity camera, on known geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "rove/core/error.h"
#include "rove/poses/lie_conversion.h"
#include "rove/vision/range_image_frame.h"

namespace rove {
namespace {

PinholeCamera camera(std::uint32_t w, std::uint32_t h, double f) {
  PinholeCamera c;
  c.width = w;
  c.height = h;
  c.fx = c.fy = f;
  c.cx = (w - 1) / 2.0;
  c.cy = (h - 1) / 2.0;
  return c;
}

// An observation of the plane z = 2 (depth optical frame) with both cameras
// `cam`; the intensity camera's pose in the depth camera's optical frame is
// T_depth_intensity.
RangeImage3D plane_scan(const PinholeCamera& cam, const SE3d& T_depth_intensity, bool range_is_depth = true) {
  RangeImage3D o;
  o.depth_camera = cam;
  o.intensity_camera = cam;
  o.depth = DepthImage::zeros_u16(cam.width, cam.height, 1000.0);
  o.range_is_depth = range_is_depth;
  for (std::uint32_t v = 0; v < cam.height; ++v) {
    for (std::uint32_t u = 0; u < cam.width; ++u) {
      o.depth.set_meters(u, v, range_is_depth ? 2.0 : 2.0 * cam.unproject(u, v).norm());
    }
  }
  o.intensity = Image::zeros(cam.width, cam.height, 3, PixelType::U8);
  o.T_sensor_intensity = to_pose3(to_se3(sensor_from_optical()) * T_depth_intensity);
  return o;
}

TEST(VisionRangeImageFrame, EqualCamerasGiveTheDepthImageBack) {
  const PinholeCamera cam = camera(64, 48, 50.0);
  RangeImage3D o = plane_scan(cam, SE3d());
  o.max_range = 3.5;
  for (std::uint32_t v = 0; v < cam.height; ++v) {
    for (std::uint32_t u = 0; u < cam.width; ++u) o.depth.set_meters(u, v, (u * 7 + v * 3) % 11 == 0 ? 0.0 : 0.5 + 0.05 * ((u + v) % 61));
  }
  const RgbdFrame f = rgbd_frame_from_range_image(o);
  EXPECT_EQ(f.color, *o.intensity);
  std::size_t valid = 0;
  for (std::uint32_t v = 0; v < cam.height; ++v) {
    for (std::uint32_t u = 0; u < cam.width; ++u) {
      const double in = o.depth.meters(u, v);
      const double expected = in <= o.max_range ? in : 0.0;  // beyond max_range: no depth
      EXPECT_NEAR(f.depth.meters(u, v), expected, 1e-6) << u << " " << v;
      valid += expected > 0.0 ? 1 : 0;
    }
  }
  EXPECT_EQ(f.valid_depth_pixels, valid);
  EXPECT_EQ(intensity_camera_of(o), cam);
}

TEST(VisionRangeImageFrame, AShiftedIntensityCameraSeesThePlaneShifted) {
  const PinholeCamera cam = camera(640, 480, 525.0);
  // The intensity camera 5 cm to the right: the plane's points move
  // 525 · 0.05 / 2 = 13.1 px to the left in its image.
  const SE3d T_depth_intensity(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.05, 0.0, 0.0));
  for (const bool depth : {true, false}) {
    const RgbdFrame f = rgbd_frame_from_range_image(plane_scan(cam, T_depth_intensity, depth));
    // Ranges are stored in whole millimeters: z within half of one.
    const double tolerance = depth ? 1e-6 : 0.5e-3;
    for (std::uint32_t v = 0; v < cam.height; v += 7) {
      for (std::uint32_t u = 0; u < cam.width; u += 3) {
        const double z = f.depth.meters(u, v);
        if (u <= 625) {
          EXPECT_NEAR(z, 2.0, tolerance) << u << " " << v << " depth " << depth;
        } else if (u >= 627) {
          EXPECT_EQ(z, 0.0) << u << " " << v;  // outside the depth camera's view
        }
      }
    }
    EXPECT_GT(f.valid_depth_pixels, 626u * 480u);
    EXPECT_LT(f.valid_depth_pixels, 628u * 480u);
  }
}

TEST(VisionRangeImageFrame, TheNearestPointOfAPixelWins) {
  // A depth camera twice as fine as the intensity camera: four depth pixels
  // per intensity pixel, on a checkerboard of 1 m and 2 m.
  const PinholeCamera coarse = camera(40, 30, 40.0);
  RangeImage3D o = plane_scan(coarse, SE3d());
  o.depth_camera = camera(80, 60, 80.0);
  o.depth = DepthImage::zeros_u16(80, 60, 1000.0);
  for (std::uint32_t v = 0; v < 60; ++v) {
    for (std::uint32_t u = 0; u < 80; ++u) o.depth.set_meters(u, v, (u + v) % 2 == 0 ? 1.0 : 2.0);
  }
  const RgbdFrame f = rgbd_frame_from_range_image(o);
  for (std::uint32_t v = 1; v + 1 < 30; ++v) {
    for (std::uint32_t u = 1; u + 1 < 40; ++u) EXPECT_NEAR(f.depth.meters(u, v), 1.0, 1e-6) << u << " " << v;
  }
}

TEST(VisionRangeImageFrame, RefusesObservationsWithoutWhatItNeeds) {
  const PinholeCamera cam = camera(16, 12, 20.0);
  RangeImage3D no_intensity = plane_scan(cam, SE3d());
  no_intensity.intensity.reset();
  EXPECT_THROW(rgbd_frame_from_range_image(no_intensity), InvalidArgument);
  RangeImage3D wide = plane_scan(cam, SE3d());
  wide.intensity = Image::zeros(16, 12, 1, PixelType::U16);
  EXPECT_THROW(rgbd_frame_from_range_image(wide), InvalidArgument);
  RangeImage3D sized = plane_scan(cam, SE3d());
  sized.intensity = Image::zeros(8, 6, 3, PixelType::U8);
  EXPECT_THROW(rgbd_frame_from_range_image(sized), InvalidArgument);
  RangeImage3D no_depth = plane_scan(cam, SE3d());
  no_depth.depth = DepthImage::zeros_u16(0, 0, 1000.0);
  EXPECT_THROW(rgbd_frame_from_range_image(no_depth), InvalidArgument);
}

}  // namespace
}  // namespace rove
