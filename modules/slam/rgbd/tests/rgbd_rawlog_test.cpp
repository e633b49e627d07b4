// RGB-D SLAM over rawlogs of 3D range scans: a rendered room written by
// rove's rawlog writer, with a depth camera and an intensity camera that
// differ (intrinsics and a relative pose), and logs the pipeline cannot use.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>

#include "rove/core/error.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/comment_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/lie_conversion.h"
#include "rove/slam/rgbd_sequence.h"
#include "rove/slam/rgbd_slam.h"
#include "rove/slam/rgbd_slam_run.h"
#include "rgbd_test_room.h"

namespace rove {
namespace {

namespace fs = std::filesystem;
using namespace rgbd_test;

// A file in a fresh temporary folder, removed with it.
class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : dir_(fs::temp_directory_path() / ("rove_rgbd_rawlog_" + std::to_string(::getpid()) + "_" + name)) {
    fs::create_directories(dir_);
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  std::string path() const { return (dir_ / "log.rawlog").string(); }

 private:
  fs::path dir_;
};

// The depth camera: a longer focal length than the intensity camera's
// (test_camera, f = 525), its principal point off centre.
PinholeCamera depth_camera() {
  PinholeCamera c = test_camera();
  c.fx = c.fy = 570.0;
  c.cx = 322.0;
  c.cy = 236.0;
  return c;
}

// T_depth_intensity: the intensity camera 2.5 cm to the right of the depth
// camera, turned by a few mrad.
SE3d depth_from_intensity() {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.025, -0.002, 0.001, 0.002, -0.003, 0.001;
  return SE3d::exp(xi);
}

// The scan of the intensity camera at T_world_intensity.
RangeImage3D scan_at(const SE3d& T_world_intensity, double time, const std::string& label) {
  const SE3d T_world_depth = T_world_intensity * depth_from_intensity().inverse();
  RangeImage3D o;
  o.sensor_label = label;
  o.timestamp = Timestamp::from_seconds(time);
  o.depth_camera = depth_camera();
  o.depth = render(o.depth_camera, T_world_depth).depth;
  o.range_is_depth = true;
  o.max_range = 10.0;
  o.intensity_camera = test_camera();
  o.intensity = render(o.intensity_camera, T_world_intensity).color;
  o.T_sensor_intensity = to_pose3(to_se3(sensor_from_optical()) * depth_from_intensity());
  return o;
}

TEST(RgbdSlamRawlog, FollowsTheIntensityCameraOfARenderedRoom) {
  TempFile file("room");
  constexpr std::size_t kPath = 30, kFrames = 12;
  {
    RoveRawlogWriterOptions wo;
    wo.layout = RawlogLayout::Mixed;
    RoveRawlogWriter w(file.path(), wo);
    for (std::size_t i = 0; i < kFrames; ++i) {
      const RangeImage3D o = scan_at(true_pose(i, kPath), 1.7e9 + 0.1 * static_cast<double>(i), "KINECT");
      if (i % 2 == 0) {
        w.write(o);  // a bare observation
      } else {
        SensoryFrame sf;
        sf.add(std::make_shared<RangeImage3D>(o));
        w.write(sf);
      }
      if (i == 5) {
        CommentObservation c;
        c.text = "a comment between the scans";
        w.write(c);
        // Another sensor's scan: left out and counted.
        w.write(scan_at(true_pose(i, kPath), 1.7e9 + 0.1 * static_cast<double>(i) + 0.05, "OTHER"));
      }
    }
    w.close();
  }
  const RgbdSequence seq = read_rgbd_sequence(file.path());
  EXPECT_EQ(seq.format, RgbdSequenceFormat::Rawlog);
  EXPECT_EQ(to_string(seq.format), "rawlog");
  ASSERT_EQ(seq.frames.size(), kFrames);
  EXPECT_EQ(seq.sensor_label, "KINECT");
  EXPECT_EQ(seq.other_sensor_scans, 1u);
  EXPECT_EQ(seq.camera, test_camera());
  EXPECT_TRUE(seq.reference.empty());
  EXPECT_NEAR(seq.frames[3].time, 1.7e9 + 0.3, 1e-6);
  EXPECT_EQ(seq.frames[7].rawlog_entry, 9u);  // after the comment and the other sensor's scan

  RgbdSlam slam(seq.camera);
  const RgbdSlamRunResult r = run_rgbd_slam(slam, seq);
  EXPECT_EQ(r.frames, kFrames);
  EXPECT_TRUE(r.issues.empty());
  EXPECT_EQ(slam.stats().lost, 0u);
  EXPECT_EQ(slam.stats().no_features, 0u);
  // The trajectory is the intensity camera's, the world its first pose;
  // the same run on frames rendered with the intensity camera alone (depth
  // and color from one camera) is the reference for the registration.
  RgbdSlam one_camera(test_camera());
  for (std::size_t i = 0; i < kFrames; ++i) one_camera.process(render(test_camera(), true_pose(i, kPath)), static_cast<double>(i));
  one_camera.finish();
  const SE3d T0 = true_pose(0, kPath);
  for (std::size_t i = 0; i < kFrames; ++i) {
    const SE3d truth = T0.inverse() * true_pose(i, kPath);
    const SE3d err = truth.inverse() * slam.frame_pose(i);
    // Measured: at most 23.6 mm and 7.3 mrad (frame 10; 12 frames without
    // a loop back to the start, as the one-camera run).
    EXPECT_LT(err.translation().norm(), 0.025) << "frame " << i;
    EXPECT_LT(err.rotation().log().norm(), 0.008) << "frame " << i;
    // Measured: within 0.1 mm and 0.01 mrad of the one-camera run without
    // the geometric edges; with them (GICP reads the depth, which the
    // registration resamples into the intensity camera) within 1.3 mm.
    const SE3d diff = one_camera.frame_pose(i).inverse() * slam.frame_pose(i);
    EXPECT_LT(diff.translation().norm(), 0.002) << "frame " << i;
    EXPECT_LT(diff.rotation().log().norm(), 0.0003) << "frame " << i;
    EXPECT_NEAR(slam.frame_time(i), seq.frames[i].time, 1e-9);
  }
  // The map lies on the room's planes.
  std::size_t off = 0;
  const PointCloud map = slam.map_cloud();
  ASSERT_GT(map.size(), 1000u);
  for (const Eigen::Vector3f& q : map.points()) {
    const Eigen::Vector3d p = T0 * q.cast<double>();
    double d = std::numeric_limits<double>::infinity();
    for (const Plane& pl : kPlanes) d = std::min(d, std::abs(p[pl.axis] - pl.value));
    if (d > 0.02) ++off;
  }
  EXPECT_EQ(off, 0u);
}

TEST(RgbdSlamRawlog, ALogWithoutScansIsAnErrorNamingTheFile) {
  TempFile file("noscan");
  {
    RoveRawlogWriterOptions wo;
    wo.layout = RawlogLayout::Observations;
    RoveRawlogWriter w(file.path(), wo);
    CommentObservation c;
    c.text = "no scan here";
    w.write(c);
    w.close();
  }
  try {
    read_rgbd_sequence(file.path());
    ADD_FAILURE() << "accepted a log without 3D range scans";
  } catch (const ParseError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(file.path()), std::string::npos) << m;
    EXPECT_NE(m.find("no 3D range scan"), std::string::npos) << m;
  }
}

TEST(RgbdSlamRawlog, AScanWithoutIntensityOrWithBadTimesIsAnErrorNamingTheEntry) {
  struct Case {
    const char* name;
    const char* expected;
  };
  for (const Case& c : {Case{"nointensity", "entry 1: the 3D range scan has no intensity image"},
                        Case{"backwards", "entry 1: time"}, Case{"camera", "entry 1: the intensity camera differs"}}) {
    TempFile file(c.name);
    {
      RoveRawlogWriterOptions wo;
      wo.layout = RawlogLayout::Observations;
      RoveRawlogWriter w(file.path(), wo);
      w.write(scan_at(true_pose(0, 30), 10.0, "KINECT"));
      RangeImage3D second = scan_at(true_pose(1, 30), 10.1, "KINECT");
      if (std::string(c.name) == "nointensity") second.intensity.reset();
      if (std::string(c.name) == "backwards") second.timestamp = Timestamp::from_seconds(9.9);
      if (std::string(c.name) == "camera") second.intensity_camera.fx = 500.0;
      w.write(second);
      w.close();
    }
    try {
      read_rgbd_sequence(file.path());
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const ParseError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file.path()), std::string::npos) << m;
      EXPECT_NE(m.find(c.expected), std::string::npos) << m;
    }
  }
  // A camera for a rawlog is refused: its scans carry their cameras.
  TempFile file("withcamera");
  {
    RoveRawlogWriterOptions wo;
    wo.layout = RawlogLayout::Observations;
    RoveRawlogWriter w(file.path(), wo);
    w.write(scan_at(true_pose(0, 30), 10.0, "KINECT"));
    w.close();
  }
  RgbdSequenceOptions so;
  so.camera = "kinect";
  EXPECT_THROW(read_rgbd_sequence(file.path(), so), InvalidArgument);
  EXPECT_EQ(read_rgbd_sequence(file.path()).frames.size(), 1u);
}

}  // namespace
}  // namespace rove
