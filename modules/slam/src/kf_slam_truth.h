#pragma once
// Ground truth of a kf-slam run (rove/slam/kf_slam_run.h): MRPT's landmark
// and robot-path files, the true landmark of a reading, and the issues a
// finished run reports.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se3.h"
#include "rove/obs/bearing_range.h"
#include "rove/poses/pose3.h"
#include "rove/slam/kf_slam_run.h"

namespace rove {

namespace detail {
// Rows of whitespace-separated numbers of a ground-truth file; blank lines
// and lines starting with '%' or '#' skipped (MRPT's text matrices). Each
// row has its line number. ParseError (path, line, `key`) for a value that
// is not a finite number.
std::vector<std::pair<std::size_t, std::vector<double>>> read_rows(const std::string& path,
                                                                   const std::string& key);
}  // namespace detail

struct KfSlamTruth {
  // Landmark ID → true position (world, m).
  std::map<std::int64_t, Eigen::Vector3d> landmarks;
  // True robot pose per step.
  std::vector<SE3d> path;
  // Largest distance between a placed reading and its true landmark (m).
  double gate = 0.5;

  // The true landmark of a reading: its ID if it has one, else the nearest
  // true landmark to the reading placed from the true pose, within gate.
  std::optional<std::int64_t> reading_truth(const LandmarkMeasurement& m, const Pose3& T_rs,
                                            const std::optional<SE3d>& T_world_robot) const;
};

// Reads config.ground_truth_file and ground_truth_file_robot when named.
// ParseError naming file, line and column for malformed rows.
KfSlamTruth load_kf_slam_truth(const KfSlamConfig& config, double gate);

// Fills res.issues from a finished run.
void add_kf_slam_issues(KfSlamResult& res);

}  // namespace rove
