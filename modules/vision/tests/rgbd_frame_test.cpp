// RGB-D frames: depth → cloud on known geometry, and bad files.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rove/core/error.h"
#include "rove/vision/rgbd_frame.h"

namespace rove {
namespace {

// A frame of the plane z = d0 + slope·x (camera frame) seen by `camera`.
RgbdFrame plane_frame(const PinholeCamera& camera, double scale) {
  RgbdFrame f;
  f.color = Image::zeros(camera.width, camera.height, 3, PixelType::U8);
  f.depth = DepthImage::zeros_f32(camera.width, camera.height, scale);
  for (std::uint32_t v = 0; v < camera.height; ++v) {
    for (std::uint32_t u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray = camera.unproject(u, v);
      // Ray z·(a, b, 1) meets z = 2 + 0.5·x at z = 2 / (1 − 0.5·a).
      const double z = 2.0 / (1.0 - 0.5 * ray.x());
      f.depth.set_meters(u, v, (u + v) % 7 == 0 ? 0.0 : z);
      std::uint8_t* px = f.color.data.data() + 3 * (v * camera.width + u);
      px[0] = static_cast<std::uint8_t>(u);
      px[1] = static_cast<std::uint8_t>(v);
      px[2] = 7;
    }
  }
  return f;
}

TEST(VisionRgbdCloud, PlaneIsRecoveredForAnyFocalSign) {
  for (const double fy : {500.0, -480.0}) {
    PinholeCamera c;
    c.width = 64;
    c.height = 48;
    c.fx = 60.0;
    c.fy = fy / 8.0;
    c.cx = 31.5;
    c.cy = 23.5;
    const RgbdFrame f = plane_frame(c, 1.0);
    const PointCloud cloud = rgbd_to_cloud(f, c);
    std::size_t expected = 0;
    for (std::uint32_t v = 0; v < c.height; ++v)
      for (std::uint32_t u = 0; u < c.width; ++u) expected += (u + v) % 7 == 0 ? 0 : 1;
    ASSERT_EQ(cloud.size(), expected);
    ASSERT_TRUE(cloud.has_colors());
    std::size_t i = 0;
    for (std::uint32_t v = 0; v < c.height; ++v) {
      for (std::uint32_t u = 0; u < c.width; ++u) {
        if ((u + v) % 7 == 0) continue;
        const Eigen::Vector3d p = cloud[i].cast<double>();
        EXPECT_NEAR(p.z(), 2.0 + 0.5 * p.x(), 1e-5);
        // Back on its own pixel (the sign of fy decides where y points).
        const Eigen::Vector2d px = c.project(p);
        EXPECT_NEAR(px.x(), u, 1e-3);
        EXPECT_NEAR(px.y(), v, 1e-3);
        EXPECT_EQ(cloud.colors()[i], (Rgb8{static_cast<std::uint8_t>(u),
                                           static_cast<std::uint8_t>(v), 7}));
        ++i;
      }
    }
  }
}

TEST(VisionRgbdCloud, TargetPoseStrideAndRangeApply) {
  PinholeCamera c;
  c.width = 64;
  c.height = 48;
  c.fx = c.fy = 60.0;
  c.cx = 31.5;
  c.cy = 23.5;
  const RgbdFrame f = plane_frame(c, 1.0);
  RgbdCloudOptions o;
  o.T_target_camera = SE3d::exp((Eigen::Matrix<double, 6, 1>() << 1, 2, 3, 0.1, -0.2, 0.3).finished());
  o.stride = 2;
  const PointCloud moved = rgbd_to_cloud(f, c, o);
  o.T_target_camera = SE3d();
  const PointCloud local = rgbd_to_cloud(f, c, o);
  ASSERT_EQ(moved.size(), local.size());
  SE3d T = SE3d::exp((Eigen::Matrix<double, 6, 1>() << 1, 2, 3, 0.1, -0.2, 0.3).finished());
  for (std::size_t i = 0; i < local.size(); ++i) {
    EXPECT_TRUE(moved[i].cast<double>().isApprox(T * local[i].cast<double>(), 1e-5));
  }
  o.max_depth = 1.5;  // the plane is at 2 m and beyond near the center
  EXPECT_EQ(rgbd_to_cloud(f, c, o).size(), 0u);
}

class VisionRgbdFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rove_vision_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const cv::Mat& m) {
    const std::string p = (dir_ / name).string();
    cv::imwrite(p, m);
    return p;
  }
  static std::string error_of(const std::string& color, const std::string& depth) {
    try {
      read_rgbd_frame(color, depth, 5000.0);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }
  std::filesystem::path dir_;
};

TEST_F(VisionRgbdFiles, ReadsAGoodPair) {
  cv::Mat depth(4, 5, CV_16UC1, cv::Scalar(5000));
  depth.at<std::uint16_t>(1, 2) = 0;
  const std::string color = write("c.png", cv::Mat(4, 5, CV_8UC3, cv::Scalar(10, 20, 30)));
  const RgbdFrame f = read_rgbd_frame(color, write("d.png", depth), 5000.0);
  EXPECT_EQ(f.valid_depth_pixels, 19u);
  EXPECT_EQ(f.depth.meters(0, 0), 1.0);
  EXPECT_EQ(f.depth.meters(2, 1), 0.0);
  EXPECT_EQ(f.color.data[0], 30);  // BGR on disk, RGB in memory
  EXPECT_EQ(f.color.data[2], 10);
}

TEST_F(VisionRgbdFiles, BadInputNamesTheFile) {
  const std::string color = write("c.png", cv::Mat(4, 5, CV_8UC3, cv::Scalar(1, 2, 3)));
  const std::string depth8 = write("d8.png", cv::Mat(4, 5, CV_8UC1, cv::Scalar(9)));
  const std::string zero = write("zero.png", cv::Mat(4, 5, CV_16UC1, cv::Scalar(0)));
  const std::string small = write("small.png", cv::Mat(3, 5, CV_16UC1, cv::Scalar(7)));
  const std::string text = (dir_ / "text.png").string();
  {
    std::ofstream(text) << "not an image";
  }
  std::string e = error_of(color, depth8);
  EXPECT_NE(e.find("d8.png"), std::string::npos);
  EXPECT_NE(e.find("8-bit"), std::string::npos) << e;
  e = error_of(color, zero);
  EXPECT_NE(e.find("zero.png"), std::string::npos);
  EXPECT_NE(e.find("no measurement"), std::string::npos) << e;
  e = error_of(color, small);
  EXPECT_NE(e.find("small.png"), std::string::npos);
  EXPECT_NE(e.find("5x3"), std::string::npos) << e;
  e = error_of((dir_ / "missing.png").string(), small);
  EXPECT_NE(e.find("missing.png"), std::string::npos) << e;
  e = error_of(text, small);
  EXPECT_NE(e.find("text.png"), std::string::npos) << e;
  EXPECT_NE(e.find("not a PNG file"), std::string::npos) << e;
  // JPEG colour images are refused by name (rove reads PNG frames).
  const std::string jpeg = write("c.jpg", cv::Mat(4, 5, CV_8UC3, cv::Scalar(1, 2, 3)));
  e = error_of(jpeg, small);
  EXPECT_NE(e.find("c.jpg"), std::string::npos) << e;
  EXPECT_NE(e.find("not a PNG file"), std::string::npos) << e;
  // A colour depth image, a 16-bit colour image as depth, an 8-bit PGM.
  e = error_of(color, write("d3.png", cv::Mat(4, 5, CV_16UC3, cv::Scalar(9, 9, 9))));
  EXPECT_NE(e.find("16-bit with 3 channel(s)"), std::string::npos) << e;
  const std::string pgm8 = (dir_ / "d8.pgm").string();
  {
    std::ofstream(pgm8, std::ios::binary) << "P5\n5 4\n255\n" << std::string(20, '\x09');
  }
  e = error_of(color, pgm8);
  EXPECT_NE(e.find("d8.pgm"), std::string::npos) << e;
  EXPECT_NE(e.find("8-bit"), std::string::npos) << e;
}

// Every PNG kind OpenCV writes reads as OpenCV reads it: gray and 16-bit
// colour images become 8-bit RGB (16-bit samples keep their high byte),
// alpha is dropped; 16-bit PGM depth (Kinect dumps) keeps its samples.
TEST_F(VisionRgbdFiles, ColourKindsAndPgmDepth) {
  cv::Mat depth(4, 5, CV_16UC1);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 5; ++c) depth.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(1000 + 300 * r + c);
  const std::string d = write("d.png", depth);
  cv::Mat gray(4, 5, CV_8UC1, cv::Scalar(77));
  cv::Mat rgba(4, 5, CV_8UC4, cv::Scalar(10, 20, 30, 128));  // B G R A
  cv::Mat deep(4, 5, CV_16UC3, cv::Scalar(0x1234, 0x5678, 0x9abc));
  for (const auto& [name, m] : {std::pair{"g.png", gray}, std::pair{"a.png", rgba}, std::pair{"deep.png", deep}}) {
    const RgbdFrame f = read_rgbd_frame(write(name, m), d, 1000.0);
    cv::Mat expected;
    if (m.channels() == 1) cv::cvtColor(m, expected, cv::COLOR_GRAY2RGB);
    else if (m.channels() == 4) cv::cvtColor(m, expected, cv::COLOR_BGRA2RGB);
    else if (m.depth() == CV_8U) cv::cvtColor(m, expected, cv::COLOR_BGR2RGB);
    else cv::cvtColor(cv::Mat(4, 5, CV_8UC3, cv::Scalar(0x12, 0x56, 0x9a)), expected, cv::COLOR_BGR2RGB);
    ASSERT_EQ(f.color.data.size(), expected.total() * 3) << name;
    EXPECT_EQ(0, std::memcmp(f.color.data.data(), expected.data, f.color.data.size())) << name;
    EXPECT_EQ(f.depth.meters(4, 3), (1000 + 300 * 3 + 4) / 1000.0) << name;
  }
  // The same depth as a 16-bit binary PGM (big-endian samples).
  std::string pgm = "P5\n# a Kinect dump\n5 4\n65535\n";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 5; ++c) {
      const auto v = depth.at<std::uint16_t>(r, c);
      pgm += static_cast<char>(v >> 8);
      pgm += static_cast<char>(v & 0xff);
    }
  const std::string p = (dir_ / "d.pgm").string();
  {
    std::ofstream(p, std::ios::binary) << pgm;
  }
  const RgbdFrame a = read_rgbd_frame(write("c.png", gray), d, 1000.0);
  const RgbdFrame b = read_rgbd_frame(write("c.png", gray), p, 1000.0);
  EXPECT_EQ(std::get<std::vector<std::uint16_t>>(a.depth.values),
            std::get<std::vector<std::uint16_t>>(b.depth.values));
  // Truncated: the error names the file and the offset.
  {
    std::ofstream(p, std::ios::binary) << pgm.substr(0, pgm.size() - 3);
  }
  const std::string e = error_of((dir_ / "c.png").string(), p);
  EXPECT_NE(e.find("d.pgm"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

}  // namespace
}  // namespace rove
