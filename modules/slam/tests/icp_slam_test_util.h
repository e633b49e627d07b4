#pragma once
// Shared helpers of the ICP-SLAM tests: the bundled demo files and MRPT's
// frozen icp-slam outputs (tools/mrpt_icp_slam_reference/make_reference.sh).

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "rove/poses/pose2.h"

namespace rove::test {

inline std::string data_path(const std::string& name) {
  return std::string(ROVE_SOURCE_DIR) + "/data/mrpt/" + name;
}
inline std::string telecom_rawlog() {
  return data_path("2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog");
}
inline std::string reference_path(const std::string& name) {
  return std::string(ROVE_SOURCE_DIR) + "/modules/slam/tests/data/" + name;
}

// MRPT's log_estimated_path.txt / log_odometry_path.txt: `step x y phi`.
inline std::vector<Pose2> load_mrpt_path(const std::string& path) {
  std::ifstream in(path);
  std::vector<Pose2> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '%') continue;
    std::istringstream s(line);
    double step = 0, x = 0, y = 0, phi = 0;
    if (s >> step >> x >> y >> phi) out.emplace_back(x, y, phi);
  }
  return out;
}

// `key value` lines.
inline std::map<std::string, double> load_counts(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, double> out;
  std::string key;
  double v = 0;
  while (in >> key >> v) out[key] = v;
  return out;
}

// Root-mean-square distance between the positions of two equally long paths.
inline double position_rmse(const std::vector<Pose2>& a, const std::vector<Pose2>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += a[i].squared_distance_to(b[i]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

}  // namespace rove::test
