#include "kf_slam_truth.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "rove/bayes/distributions.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/poses/lie_conversion.h"

namespace rove {

std::vector<std::pair<std::size_t, std::vector<double>>> detail::read_rows(const std::string& path,
                                                                           const std::string& key) {
  const std::string text = read_input_file(path, kMaxTextInputBytes, "ground truth file");
  std::istringstream in(text);
  std::string line;
  std::size_t line_no = 0;
  std::vector<std::pair<std::size_t, std::vector<double>>> rows;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '%' || line[first] == '#') continue;
    std::istringstream ls(line);
    std::vector<double> v;
    double x = 0.0;
    while (ls >> x) v.push_back(x);
    if (!ls.eof()) {
      throw ParseError({path, line_no, std::nullopt, key},
                       fmt::format("value {} is not a number", v.size() + 1));
    }
    for (double e : v) {
      if (!std::isfinite(e)) throw ParseError({path, line_no, std::nullopt, key}, "not finite");
    }
    rows.emplace_back(line_no, std::move(v));
  }
  return rows;
}

std::optional<std::int64_t> KfSlamTruth::reading_truth(
    const LandmarkMeasurement& m, const Pose3& T_rs,
    const std::optional<SE3d>& T_world_robot) const {
  if (m.landmark_id >= 0) return m.landmark_id;
  if (!T_world_robot || landmarks.empty()) return std::nullopt;
  const Eigen::Vector3d p = *T_world_robot * (to_se3(T_rs) * m.point_in_sensor());
  double best = std::numeric_limits<double>::infinity();
  std::int64_t best_id = -1;
  for (const auto& [id, q] : landmarks) {
    const double d = (q - p).norm();
    if (d < best) best = d, best_id = id;
  }
  if (!(best <= gate)) return std::nullopt;
  return best_id;
}

KfSlamTruth load_kf_slam_truth(const KfSlamConfig& config, double gate) {
  KfSlamTruth t;
  t.gate = gate;
  if (!config.ground_truth_file.empty()) {
    const std::string path = config.resolve(config.ground_truth_file, "ground_truth_file");
    for (const auto& [line, v] : detail::read_rows(path, "ground_truth_file")) {
      if (v.size() < 7 || v[6] != std::floor(v[6])) {
        throw ParseError({path, line, std::nullopt, "ground_truth_file"},
                         fmt::format("expected rows of at least 7 numbers, x y z ... with the "
                                     "landmark ID (a whole number) 7th; this row has {}",
                                     v.size()));
      }
      const auto id = static_cast<std::int64_t>(v[6]);
      if (!t.landmarks.emplace(id, Eigen::Vector3d(v[0], v[1], v[2])).second) {
        throw ParseError({path, line, std::nullopt, "ground_truth_file"},
                         fmt::format("landmark ID {} appears twice", id));
      }
    }
  }
  if (!config.ground_truth_file_robot.empty()) {
    const std::string path =
        config.resolve(config.ground_truth_file_robot, "ground_truth_file_robot");
    for (const auto& [line, v] : detail::read_rows(path, "ground_truth_file_robot")) {
      if (v.size() == 6) {
        t.path.push_back(to_se3(Pose3(v[0], v[1], v[2], v[3], v[4], v[5])));
      } else if (v.size() == 3) {
        t.path.push_back(to_se3(Pose3(v[0], v[1], 0.0, v[2], 0.0, 0.0)));
      } else {
        throw ParseError({path, line, std::nullopt, "ground_truth_file_robot"},
                         fmt::format("expected 6 numbers (x y z yaw pitch roll) or 3 (x y phi) "
                                     "per row; this row has {}",
                                     v.size()));
      }
    }
  }
  return t;
}

void add_kf_slam_issues(KfSlamResult& res) {
  const KfSlamAssociationStats& a = res.association;
  auto add = [&](const char* code, std::string msg) { res.issues.push_back({code, std::move(msg)}); };
  if (a.readings == 0) add("no-readings", "the log has no range-bearing readings: nothing was mapped");
  if (a.wrong > 0) {
    add("wrong-associations",
        fmt::format("{} of {} pairings checked against the ground truth are wrong", a.wrong,
                    a.wrong + a.correct));
  }
  if (a.duplicates > 0) {
    add("duplicate-landmarks",
        fmt::format("{} new landmarks were started for landmarks already mapped", a.duplicates));
  }
  std::size_t once = 0;
  for (const auto& l : res.landmarks) once += l.observations == 1 ? 1 : 0;
  if (once > 0) {
    add("landmarks-seen-once",
        fmt::format("{} of {} landmarks were observed once: their position is the reading's "
                    "alone, never corrected",
                    once, res.landmarks.size()));
  }
  if (a.skipped > 0) {
    add("skipped-readings",
        fmt::format("{} readings were not used (range <= 0, or an ID repeated within a frame)",
                    a.skipped));
  }
  std::size_t skipped_updates = 0;
  for (const auto& s : res.steps) skipped_updates += s.update_skipped ? 1 : 0;
  if (skipped_updates > 0) {
    add("updates-skipped", fmt::format("{} steps skipped their update: the innovation covariance "
                                       "was not positive definite",
                                       skipped_updates));
  }
  if (a.node_limit_steps > 0) {
    add("association-node-limit",
        fmt::format("JCBB stopped at its node limit in {} steps (data_assoc_JCBB_max_nodes)",
                    a.node_limit_steps));
  }
  for (const auto& s : res.steps) res.nis_sum += s.nis, res.nis_dof += s.nis_dof;
  // The innovations of a consistent filter sum to a χ²(dof) variable; beyond
  // its 99.9 % quantile the filter is overconfident (its noise settings too
  // small for the data).
  if (res.nis_dof > 0) {
    const double bound = chi_square_quantile(0.999, static_cast<double>(res.nis_dof));
    if (res.nis_sum > bound) {
      add("innovations-too-large",
          fmt::format("the normalized innovations sum to {:.1f} over {} degrees of freedom, above "
                      "the 99.9 % chi-square bound {:.1f}: the sensor or motion noise of the "
                      "config is smaller than the data's",
                      res.nis_sum, res.nis_dof, bound));
    }
  }
}

}  // namespace rove
