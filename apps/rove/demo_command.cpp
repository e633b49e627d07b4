#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <string>

#include "commands.h"
#include "data_dir.h"
#include "rove/core/ini.h"
#include "rove/core/profiler.h"
#include "rove/core/timer.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/slam/icp_slam.h"

namespace rove::cli {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct DemoOptions {
  std::string config;  // empty: the bundled icp-slam_demo_classic.ini
  bool profile = false;
};

// Loads the icp-slam configuration MRPT ships exactly as `rove icp-slam`
// does (the same strict loader: unknown keys and out-of-range values are
// errors) and prints what it configures.
void show_config(const std::string& path) {
  const IcpSlamConfig config = load_icp_slam_config(IniFile::load(path));
  const IcpSlamOptions& o = config.options;
  fmt::print("MRPT icp-slam configuration: {}\n", path);
  fmt::print("  [ICP] {}, at most {} iterations, match distance {:.3g} m widened by {:.3g} deg/m,\n"
             "        ALFA {:.3g}, smallest threshold {:.3g} m, decimation {}\n",
             o.icp.algorithm == IcpAlgorithm::Classic ? "icpClassic" : "icpLevenbergMarquardt",
             o.icp.max_iterations, o.icp.threshold_dist, o.icp.threshold_ang / kDeg, o.icp.alfa,
             o.icp.smallest_threshold_dist, o.icp.corresponding_points_decimation);
  fmt::print("  [MappingApplication] localize every {:.3g} m / {:.3g} deg, insert every {:.3g} m / {:.3g} "
             "deg,\n        accept ICP goodness >= {:.3g}, {} map(s)",
             o.localization_lin_distance, o.localization_ang_distance / kDeg,
             o.insertion_lin_distance, o.insertion_ang_distance / kDeg,
             o.min_icp_goodness_to_accept, config.map.size());
  for (const auto& e : config.map.entries()) fmt::print(" {}", e.map->kind());
  fmt::print("\n");
  if (!config.ignored_keys.empty()) {
    fmt::print("  {} key(s) without effect in rove (MRPT GUI/logging switches)\n",
               config.ignored_keys.size());
  }
}

// MRPT's documented example of pose composition ("2D/3D poses" tutorial):
// a landmark L seen from a camera C mounted on a robot R.
void show_poses() {
  const Point3 L(0.0, 4.0, 2.0);
  const Pose2 R(2.0, 1.0, 45.0 * kDeg);
  const Pose3 C(0.5, 0.5, 1.5, -90.0 * kDeg, 0.0, -90.0 * kDeg);
  const Pose3 camera_in_world = R + C;
  const Point3 L_camera = L - camera_in_world;
  const Point3 back = camera_in_world + L_camera;
  fmt::print("\nPose composition (MRPT's worked example):\n");
  fmt::print("  robot R = {}   camera on robot C = {}\n", R, C);
  fmt::print("  camera in world R+C = {}\n", camera_in_world);
  fmt::print("  landmark L = {} seen from the camera: L-(R+C) = ({:.5f},{:.5f},{:.5f})\n", L,
             L_camera.x, L_camera.y, L_camera.z);
  fmt::print("  and back: (R+C)+(L-(R+C)) = {}   error {:.3g} m\n", back,
             (back.to_vector() - L.to_vector()).norm());

  // The same chain with uncertainty: the robot's pose known to 5 cm and 2 deg.
  Pose2Gaussian::Matrix cov = Pose2Gaussian::Matrix::Zero();
  cov(0, 0) = cov(1, 1) = 0.05 * 0.05;
  cov(2, 2) = std::pow(2.0 * kDeg, 2);
  const Pose2Gaussian robot(R, cov);
  const Pose3Gaussian camera = to_3d(robot) + C;
  const auto& P = camera.covariance();
  fmt::print("  with the robot known to 5 cm / 2 deg, the camera's standard deviations are\n"
             "  x {:.3f} m, y {:.3f} m, z {:.3f} m, yaw {:.2f} deg\n",
             std::sqrt(P(0, 0)), std::sqrt(P(1, 1)), std::sqrt(P(2, 2)),
             std::sqrt(P(3, 3)) / kDeg);
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  auto* cmd = app.add_subcommand(
      "demo", "Run rove on the bundled demo data (MRPT's icp-slam config, pose algebra)");
  cmd->add_option("--config", options->config, "An MRPT icp-slam .ini to read instead");
  cmd->add_flag("--profile", options->profile, "Print a profiler report at the end");
  cmd->callback([options] {
    Profiler profiler;
    const std::string config = options->config.empty()
                                   ? (data_dir() / "mrpt" / "icp-slam_demo_classic.ini").string()
                                   : options->config;
    {
      ScopedTimer t(profiler, "read config");
      show_config(config);
    }
    {
      ScopedTimer t(profiler, "pose algebra");
      show_poses();
    }
    if (options->profile) fmt::print("\n{}", profiler.report());
  });
}

}  // namespace rove::cli
