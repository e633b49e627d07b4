#pragma once
// Shared helpers of the pf-localization tests: the bundled demo and MRPT's
// frozen pf-localization path (tools/mrpt_pf_localization_reference/).

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "rove/core/ini.h"
#include "rove/poses/angle.h"
#include "rove/poses/pose2.h"
#include "rove/slam/pf_localization_config.h"
#include "rove/test_data.h"

namespace rove::test {

// MRPT's localization_demo.ini (bundled, unchanged) with the bundled map.
inline PfLocalizationConfig demo_config() {
  PfLocalizationConfig c = load_pf_localization_config(
      IniFile::load(test_data::bundled_file("mrpt/localization_demo.ini")));
  c.map_file = test_data::bundled_file("mrpt/localization_demo.simplemap.gz");
  return c;
}
inline std::string demo_rawlog() { return test_data::bundled_file("mrpt/localization_demo.rawlog"); }

// One step of MRPT's runs: the printed mean pose, sqrt(trace cov), count.
struct MrptPfStep {
  int run = 0, step = 0;
  double x = 0, y = 0, phi = 0;  // m, rad
  double sqrt_trace = 0;
  int particles = 0;
};

inline std::vector<MrptPfStep> load_mrpt_pf_reference() {
  std::ifstream in(std::string(ROVE_SOURCE_DIR) +
                   "/modules/slam/tests/data/mrpt_pf_localization_demo.txt");
  std::vector<MrptPfStep> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    MrptPfStep r;
    double phi_deg = 0, ess = 0;
    if (s >> r.run >> r.step >> r.x >> r.y >> phi_deg >> r.sqrt_trace >> r.particles >> ess) {
      r.phi = phi_deg * std::numbers::pi / 180.0;
      out.push_back(r);
    }
  }
  return out;
}

// MRPT's estimate per step: the median over its runs of x, y and of the
// heading (taken relative to the first run's, so the median does not
// straddle ±π), for the steps at which every run is concentrated
// (sqrt(trace cov) < 0.2, m and rad mixed as MRPT prints it).
struct MrptPfReference {
  std::map<int, Pose2> median;  // step → pose
};

inline MrptPfReference mrpt_pf_reference() {
  std::map<int, std::vector<MrptPfStep>> by_step;
  for (const auto& r : load_mrpt_pf_reference()) by_step[r.step].push_back(r);
  MrptPfReference ref;
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  };
  for (const auto& [step, runs] : by_step) {
    if (std::any_of(runs.begin(), runs.end(), [](const MrptPfStep& r) { return r.sqrt_trace >= 0.2; })) {
      continue;
    }
    std::vector<double> xs, ys, ds;
    for (const auto& r : runs) {
      xs.push_back(r.x);
      ys.push_back(r.y);
      ds.push_back(wrap_to_pi(r.phi - runs.front().phi));
    }
    ref.median[step] = Pose2(median(xs), median(ys), runs.front().phi + median(ds));
  }
  return ref;
}

}  // namespace rove::test
