// RGB-D sequence folders: TUM lists and associations, numbered frames,
// cameras, and bad folders.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "rove/core/error.h"
#include "rove/slam/rgbd_sequence.h"

namespace rove {
namespace {

namespace fs = std::filesystem;

class RgbdSequenceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rove_rgbd_seq_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& rel, const std::string& text) {
    fs::create_directories((dir_ / rel).parent_path());
    std::ofstream(dir_ / rel) << text;
  }
  fs::path dir_;
};

TEST_F(RgbdSequenceTest, AssociatesTumListsClosestFirst) {
  write("rgb.txt", "# color images\n1.000 rgb/1.png\n1.033 rgb/2.png\n1.100 rgb/3.png\n");
  write("depth.txt", "# depth\n1.010 depth/1.png\n1.030 depth/2.png\n1.500 depth/3.png\n");
  for (const char* f : {"rgb/1.png", "rgb/2.png", "rgb/3.png", "depth/1.png", "depth/2.png", "depth/3.png"}) {
    write(f, "x");
  }
  const RgbdSequence s = read_rgbd_sequence(dir_.string());
  EXPECT_EQ(s.format, RgbdSequenceFormat::Tum);
  ASSERT_EQ(s.frames.size(), 2u);
  // 1.033 takes 1.030 (3 ms); 1.000 then takes 1.010; 1.100 has none within 20 ms.
  EXPECT_DOUBLE_EQ(s.frames[0].time, 1.000);
  EXPECT_EQ(fs::path(s.frames[0].depth_path).filename(), "1.png");
  EXPECT_DOUBLE_EQ(s.frames[1].depth_time, 1.030);
  EXPECT_EQ(s.unassociated_color, 1u);
  EXPECT_EQ(s.camera_source, "tum");
  EXPECT_EQ(s.depth_scale, 5000.0);
  EXPECT_TRUE(s.reference.empty());
}

TEST_F(RgbdSequenceTest, ReadsAssociationsAndGroundTruth) {
  write("associations.txt", "2.0 rgb/b.png 2.001 depth/b.png\n1.0 rgb/a.png 1.001 depth/a.png\n");
  for (const char* f : {"rgb/a.png", "rgb/b.png", "depth/a.png", "depth/b.png"}) write(f, "x");
  write("groundtruth.txt", "# t x y z qx qy qz qw\n1.0 1 2 3 0 0 0 1\n2.0 1 2 4 0 0 0 1\n");
  RgbdSequenceOptions o;
  o.camera = "tum-fr1";
  const RgbdSequence s = read_rgbd_sequence(dir_.string(), o);
  ASSERT_EQ(s.frames.size(), 2u);
  EXPECT_DOUBLE_EQ(s.frames[0].time, 1.0);  // sorted by time
  EXPECT_EQ(s.camera.fx, 517.306408);
  EXPECT_TRUE(s.camera.has_distortion());
  ASSERT_EQ(s.reference.size(), 2u);
  EXPECT_DOUBLE_EQ(s.reference[1].pose.translation().z(), 4.0);
}

TEST_F(RgbdSequenceTest, NumberedFramesTakeTheCameraFileAndPoses) {
  for (int i : {1, 2, 10}) {
    write("color/" + std::to_string(i) + ".png", "x");
    write("depth/" + std::to_string(i) + ".pgm", "x");
  }
  write("parameters.txt", "camera.cx=325.5;\ncamera.cy=253.5;\ncamera.fx=518.0;\ncamera.fy=519.0;\ncamera.scale=1000.0;\n");
  write("pose.txt", "0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");
  const RgbdSequence s = read_rgbd_sequence(dir_.string());
  EXPECT_EQ(s.format, RgbdSequenceFormat::NumberedFrames);
  ASSERT_EQ(s.frames.size(), 3u);
  EXPECT_DOUBLE_EQ(s.frames[2].time, 10.0);  // numeric order, not text order
  EXPECT_EQ(s.depth_scale, 1000.0);
  EXPECT_EQ(s.camera.fx, 518.0);
  ASSERT_EQ(s.reference.size(), 3u);
  EXPECT_DOUBLE_EQ(s.reference[2].time, 10.0);
  EXPECT_DOUBLE_EQ(s.reference[2].pose.translation().x(), 2.0);
}

TEST_F(RgbdSequenceTest, NamedCamerasAndDepthScaleOverride) {
  write("color/1.png", "x");
  write("depth/1.png", "x");
  RgbdSequenceOptions o;
  o.camera = "icl-nuim";
  o.depth_scale = 1234.0;
  const RgbdSequence s = read_rgbd_sequence(dir_.string(), o);
  EXPECT_EQ(s.camera.fy, -480.0);
  EXPECT_EQ(s.depth_scale, 1234.0);
  EXPECT_FALSE(named_camera("tum-fr4").has_value());
}

TEST_F(RgbdSequenceTest, BadFoldersAreClearErrors) {
  auto message = [&](const RgbdSequenceOptions& o = {}) {
    try {
      read_rgbd_sequence(dir_.string(), o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message().find("not an RGB-D sequence"), std::string::npos);
  write("color/1.png", "x");
  write("depth/2.png", "x");
  EXPECT_NE(message().find("no depth image numbered 1"), std::string::npos);
  write("depth/1.png", "x");
  EXPECT_NE(message().find("needs a camera"), std::string::npos);
  RgbdSequenceOptions o;
  o.camera = "nosuchcamera";
  EXPECT_NE(message(o).find("neither a camera file nor a camera name"), std::string::npos);
  write("camera.yaml", "%YAML:1.0\nCamera.fx: 0\n");
  EXPECT_NE(message().find("camera.yaml"), std::string::npos);
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  write("associations.txt", "1.0 rgb/a.png 1.0\n");
  EXPECT_NE(message().find("associations.txt"), std::string::npos);
  write("associations.txt", "1.0 rgb/a.png 1.0 depth/a.png\n");
  EXPECT_NE(message().find("rgb/a.png"), std::string::npos);  // listed but missing
  EXPECT_THROW(read_rgbd_sequence((dir_ / "nope").string()), IoError);
}

}  // namespace
}  // namespace rove
