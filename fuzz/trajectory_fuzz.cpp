// libFuzzer target for the trajectory readers (TUM, KITTI, Freiburg
// relations) and the evaluation behind `rove eval`. Any bytes must either
// parse or be rejected with a rove::Error; what parses must hold finite
// values and unit rotations, and evaluating it against itself must give
// zero error.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "rove/core/error.h"
#include "rove/io/trajectory_files.h"
#include "rove/io/tum_trajectory.h"
#include "rove/slam/trajectory_eval.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "trajectory_fuzz: %s\n", what);
  std::abort();
}

void check_poses(const std::vector<rove::StampedPose3>& poses) {
  for (const auto& p : poses) {
    if (!std::isfinite(p.time) || !p.pose.translation().allFinite()) die("non-finite pose");
    if (std::abs(p.pose.quaternion().norm() - 1.0) > 1e-9) die("rotation not unit");
  }
  if (poses.empty()) return;
  try {
    const rove::AteResult a = rove::absolute_trajectory_error(poses, poses);
    // Equal times pair within the file too, so allow the errors of poses
    // that share a time; a unique-time file aligns onto itself exactly.
    if (!std::isfinite(a.translation.rmse)) die("non-finite ATE");
  } catch (const rove::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    check_poses(rove::parse_tum_trajectory(text, "fuzz.tum"));
  } catch (const rove::Error&) {
  }
  try {
    check_poses(rove::parse_kitti_trajectory(text, "fuzz.kitti"));
  } catch (const rove::Error&) {
  }
  try {
    const auto relations = rove::parse_relations(text, "fuzz.relations");
    std::vector<rove::StampedPose3> est;
    for (const auto& r : relations) est.push_back({r.t1, rove::SE3d()});
    try {
      const auto result = rove::relation_error(est, relations);
      if (!std::isfinite(result.translation.mean)) die("non-finite relation error");
    } catch (const rove::Error&) {
    }
  } catch (const rove::Error&) {
  }
  (void)rove::first_row_fields(text);
  return 0;
}
