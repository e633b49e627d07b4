#include "rove/obs/range_scan_2d.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

// MRPT 2.5.8's CObservation2DRangeScan::getScanAngle, evaluated as MRPT does
// (single precision).
float mrpt_get_scan_angle(float aperture, bool right_to_left, std::size_t n, std::size_t idx) {
  float ang = -0.5f * aperture, da = aperture / static_cast<float>(n - 1);
  if (!right_to_left) {
    ang = -ang;
    da = -da;
  }
  return ang + da * static_cast<float>(idx);
}

// MRPT's CSinCosLookUpTableFor2DScans: accumulated in double.
std::vector<double> mrpt_lut_angles(double aperture, bool right_to_left, std::size_t n) {
  std::vector<double> out;
  double ang = (right_to_left ? -0.5 : 0.5) * aperture;
  const double da = (right_to_left ? 1.0 : -1.0) * (aperture / static_cast<double>(n - 1));
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(ang);
    ang += da;
  }
  return out;
}

RangeScan2D make_scan(std::size_t n, double aperture, bool right_to_left) {
  RangeScan2D s;
  s.aperture = aperture;
  s.right_to_left = right_to_left;
  s.set_ranges(std::vector<float>(n, 1.0f));
  return s;
}

TEST(RangeScan2D, RayAnglesClosedFormOddAndEven) {
  // Odd N = 5, aperture 2 rad: −1, −0.5, 0, 0.5, 1 (right to left).
  const RangeScan2D odd = make_scan(5, 2.0, true);
  const std::vector<double> expected_odd{-1.0, -0.5, 0.0, 0.5, 1.0};
  EXPECT_EQ(odd.ray_angles(), expected_odd);
  // Even N = 4, aperture 3 rad, left to right: 1.5, 0.5, −0.5, −1.5.
  const RangeScan2D even = make_scan(4, 3.0, false);
  const std::vector<double> expected_even{1.5, 0.5, -0.5, -1.5};
  EXPECT_EQ(even.ray_angles(), expected_even);
  // A 181-ray 180° scan: the middle ray points forward.
  const RangeScan2D sick = make_scan(181, kPi, true);
  EXPECT_DOUBLE_EQ(sick.ray_angle(0), -kPi / 2);
  EXPECT_NEAR(sick.ray_angle(90), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(sick.ray_angle(180), kPi / 2);
  EXPECT_NEAR(sick.ray_angle(1), -kPi / 2 + deg_to_rad(1.0), 1e-15);
}

TEST(RangeScan2D, RayAnglesMatchMrptBothDirectionsOddAndEven) {
  for (const bool rtl : {true, false}) {
    for (const std::size_t n : {2u, 3u, 180u, 181u, 360u, 361u, 1080u, 1081u}) {
      for (const double aperture : {kPi, deg_to_rad(270.0), 2.0 * kPi, 0.3}) {
        const RangeScan2D s = make_scan(n, aperture, rtl);
        const std::vector<double> lut = mrpt_lut_angles(aperture, rtl, n);
        for (std::size_t i = 0; i < n; ++i) {
          const double a = s.ray_angle(i);
          EXPECT_NEAR(a, mrpt_get_scan_angle(static_cast<float>(aperture), rtl, n, i), 2e-6)
              << "n=" << n << " i=" << i << " rtl=" << rtl;
          EXPECT_NEAR(a, lut[i], 1e-12) << "n=" << n << " i=" << i << " rtl=" << rtl;
        }
        EXPECT_DOUBLE_EQ(s.ray_angle(0), (rtl ? -0.5 : 0.5) * aperture);
        EXPECT_NEAR(s.ray_angle(n - 1), (rtl ? 0.5 : -0.5) * aperture, 1e-14);
      }
    }
  }
}

TEST(RangeScan2D, SetRangesDerivesValidity) {
  RangeScan2D s;
  s.max_range = 10.0f;
  s.set_ranges({1.0f, 0.0f, std::numeric_limits<float>::quiet_NaN(), 10.0f, 9.5f,
                std::numeric_limits<float>::infinity(), -1.0f});
  const std::vector<bool> expected{true, false, false, false, true, false, false};
  EXPECT_EQ(s.valid, expected);
}

TEST(RangeScan2D, ProjectionSkipsInvalidAndNonFiniteRays) {
  RangeScan2D s;
  s.aperture = kPi;  // 5 rays at −90°, −45°, 0°, 45°, 90°
  s.ranges = {1.0f, 2.0f, std::numeric_limits<float>::quiet_NaN(), 4.0f, 5.0f};
  s.valid = {true, true, true, false, true};  // the NaN ray is flagged valid on purpose
  s.T_robot_sensor = Pose3(0.2, 0.1, 0.3, kPi / 2, 0.0, 0.0);

  EXPECT_EQ(s.point_ray_indices(), (std::vector<std::size_t>{0, 1, 4}));
  const auto local = s.points_3d(ScanFrame::Sensor);
  ASSERT_EQ(local.size(), 3u);
  EXPECT_NEAR(local[0].x(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(local[0].y(), -1.0);
  EXPECT_DOUBLE_EQ(local[1].x(), 2.0 * std::cos(kPi / 4));
  EXPECT_DOUBLE_EQ(local[1].y(), -2.0 * std::sin(kPi / 4));
  EXPECT_NEAR(local[2].x(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(local[2].y(), 5.0);
  for (const auto& p : local) EXPECT_EQ(p.z(), 0.0);

  // Robot frame: yaw 90° maps (x, y) to (−y, x), then translate.
  const auto robot = s.points_3d(ScanFrame::Robot);
  ASSERT_EQ(robot.size(), 3u);
  EXPECT_NEAR(robot[0].x(), 1.2, 1e-12);
  EXPECT_NEAR(robot[0].y(), 0.1, 1e-12);
  EXPECT_NEAR(robot[0].z(), 0.3, 1e-12);
  EXPECT_NEAR(robot[2].x(), -4.8, 1e-12);
  EXPECT_NEAR(robot[2].y(), 0.1, 1e-12);

  const auto flat = s.points_2d();
  ASSERT_EQ(flat.size(), 3u);
  EXPECT_EQ(flat[1].x(), robot[1].x());
  EXPECT_EQ(flat[1].y(), robot[1].y());
}

TEST(RangeScan2D, ProjectionWithTiltedSensorMovesPointsOutOfPlane) {
  RangeScan2D s = make_scan(3, kPi, true);
  s.T_robot_sensor = Pose3(0.0, 0.0, 1.0, 0.0, deg_to_rad(30.0), 0.0);  // pitched down
  const auto p = s.points_3d();
  ASSERT_EQ(p.size(), 3u);
  // Center ray (1 m ahead) dips by sin(30°) = 0.5 m.
  EXPECT_NEAR(p[1].x(), std::cos(deg_to_rad(30.0)), 1e-12);
  EXPECT_NEAR(p[1].z(), 0.5, 1e-12);
}

TEST(RangeScan2D, BadInputIsRejected) {
  RangeScan2D s = make_scan(4, kPi, true);
  s.valid.pop_back();
  EXPECT_THROW((void)s.points_3d(), InvalidArgument);
  EXPECT_THROW(s.check(), InvalidArgument);

  RangeScan2D one = make_scan(1, kPi, true);
  EXPECT_THROW((void)one.ray_angle(0), InvalidArgument);
  EXPECT_THROW((void)one.points_3d(), InvalidArgument);

  RangeScan2D zero_aperture = make_scan(3, 0.0, true);
  EXPECT_THROW((void)zero_aperture.ray_angle(0), InvalidArgument);
  RangeScan2D nan_aperture = make_scan(3, std::nan(""), true);
  EXPECT_THROW(nan_aperture.check(), InvalidArgument);

  RangeScan2D ok = make_scan(3, kPi, true);
  EXPECT_THROW((void)ok.ray_angle(3), InvalidArgument);
  ok.intensity = {1, 2};
  EXPECT_THROW(ok.check(), InvalidArgument);

  const RangeScan2D empty;
  EXPECT_TRUE(empty.points_3d().empty());
}

}  // namespace
}  // namespace rove
