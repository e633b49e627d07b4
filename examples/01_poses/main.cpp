// 01_poses: MRPT's worked example of pose composition, then the same chain
// with uncertainty. A landmark L is observed by a camera C mounted on a robot
// R; where is L in the camera's frame?
//
// Built against the installed rove package (find_package(rove)); exits with
// a non-zero status if the numbers differ from MRPT's.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"

int main() {
  constexpr double deg = std::numbers::pi / 180.0;
  const rove::Point3 L(0.0, 4.0, 2.0);                                // landmark, world frame
  const rove::Pose2 R(2.0, 1.0, 45.0 * deg);                          // T_world_robot
  const rove::Pose3 C(0.5, 0.5, 1.5, -90.0 * deg, 0.0, -90.0 * deg);  // T_robot_camera

  const rove::Pose3 T_world_camera = R + C;  // 2D + 3D gives 3D, as in MRPT
  const rove::Point3 L_camera = L - T_world_camera;
  const rove::Point3 L_again = T_world_camera + L_camera;
  std::printf("L seen from the camera: (%.6f, %.6f, %.6f)\n", L_camera.x, L_camera.y, L_camera.z);

  // The robot pose is uncertain: 5 cm and 2 degrees (one sigma).
  rove::Pose2Gaussian::Matrix cov = rove::Pose2Gaussian::Matrix::Zero();
  cov.diagonal() << 0.05 * 0.05, 0.05 * 0.05, (2.0 * deg) * (2.0 * deg);
  const rove::Pose3Gaussian camera = rove::to_3d(rove::Pose2Gaussian(R, cov)) + C;
  std::printf("camera position sigma: x %.4f m, y %.4f m\n", std::sqrt(camera.covariance()(0, 0)),
              std::sqrt(camera.covariance()(1, 1)));

  // MRPT's published result, and the round trip back to L.
  const bool ok = std::abs(L_camera.x - -3.03553) < 1e-5 && std::abs(L_camera.y - -0.5) < 1e-5 &&
                  std::abs(L_camera.z - 0.207106) < 1e-5 &&
                  (L_again.to_vector() - L.to_vector()).norm() < 1e-9;
  std::printf("%s\n", ok ? "matches MRPT" : "DIFFERS FROM MRPT");
  return ok ? 0 : 1;
}
