// Monte-Carlo localization on MRPT's localization demo (real data, bundled)
// against MRPT 2.5.8's pf-localization on the same files, frozen by
// tools/mrpt_pf_localization_reference/make_reference.sh; a kidnapping
// spliced from the same log; a map from another building; and range-only
// localization on MRPT's UWB log.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <variant>

#include "pf_localization_test_util.h"
#include "rove/core/error.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/odometry_observation.h"
#include "rove/poses/angle.h"
#include "rove/slam/mcl.h"
#include "rove/slam/pf_localization_run.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Pose2 pose_of(const MclEstimate& e) {
  return Pose2(e.mean.translation().x(), e.mean.translation().y(), e.mean.angle());
}

// The issue's bar: over 10 seeds, once converged, the mean pose stays within
// 0.15 m and 3° of MRPT's estimate at ≥ 95 % of the steps.
TEST(PfLocalizationDemo, AgreesWithMrptOverTenSeeds) {
  const test::MrptPfReference ref = test::mrpt_pf_reference();
  ASSERT_GE(ref.median.size(), 25u) << "MRPT's reference lacks converged steps";
  std::size_t compared = 0, within = 0;
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    PfLocalizationRunOptions o;
    o.seed = seed;
    o.num_threads = 2;
    const PfLocalizationResult r = run_pf_localization(test::demo_config(), test::demo_rawlog(), o);
    ASSERT_EQ(r.steps.size(), 37u);
    ASSERT_TRUE(r.ok()) << "seed " << seed << ": " << r.message;
    EXPECT_LE(*r.converged_step, 12u) << "seed " << seed;
    EXPECT_EQ(r.peak_particles, 40000u);
    for (const auto& s : r.steps) {
      if (s.index < *r.converged_step) continue;
      const auto it = ref.median.find(static_cast<int>(s.index));
      if (it == ref.median.end()) continue;
      const Pose2 p = pose_of(s.estimate);
      const double dpos = std::hypot(p.x() - it->second.x(), p.y() - it->second.y());
      const double dphi = std::abs(wrap_to_pi(p.phi() - it->second.phi()));
      ++compared;
      if (dpos <= 0.15 && dphi <= 3 * kDeg) ++within;
    }
  }
  ASSERT_GT(compared, 200u);
  std::printf("%zu of %zu converged steps within 0.15 m and 3 deg of MRPT's estimate\n", within,
              compared);
  EXPECT_GE(static_cast<double>(within), 0.95 * static_cast<double>(compared))
      << within << " of " << compared << " steps within 0.15 m and 3 deg of MRPT";
}

// Global localization: the particles start uniform over every free cell of
// the map (76 m × 31 m), everything else as localization_demo.ini, with
// augmented MCL (0.001, 0.2): in this corridor the filter may first settle
// on a look-alike place 19 m away, which the recovery leaves once the scans
// stop fitting. Ten seeds here (bench/run_pf_localization_vs_mrpt.sh runs
// 50, with and without recovery, beside MRPT): at least nine end converged
// on the robot (within 0.3 m and 5° of MRPT's tracked estimate at the last
// step, 36), the issue's 95 %.
TEST(PfLocalizationDemo, GlobalLocalization) {
  const test::MrptPfReference ref = test::mrpt_pf_reference();
  const Pose2 truth = ref.median.at(36);
  int found = 0;
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    PfLocalizationConfig c = test::demo_config();
    PfLocalizationRunOptions o;
    o.seed = seed;
    o.num_threads = 2;
    ParticleInit init = c.options.init;
    init.mode = ParticleInitMode::FreeSpace;
    o.init = init;
    o.recovery = RecoveryOptions{0.001, 0.2};
    const PfLocalizationResult r = run_pf_localization(std::move(c), test::demo_rawlog(), o);
    const Pose2 p = pose_of(r.steps.back().estimate);
    const bool on = r.ok() && p.distance_to(truth) <= 0.3 &&
                    std::abs(wrap_to_pi(p.phi() - truth.phi())) <= 5 * kDeg;
    found += on ? 1 : 0;
    std::printf("global localization, seed %llu: %s, converged at step %s, final error %.3f m\n",
                static_cast<unsigned long long>(seed), std::string(to_string(r.termination)).c_str(),
                r.converged_step ? std::to_string(*r.converged_step).c_str() : "-",
                p.distance_to(truth));
  }
  EXPECT_GE(found, 9);
}

// A map of another building: the particles may concentrate somewhere, but
// the scans do not fit it, and the run says it did not converge.
TEST(PfLocalizationDemo, MapOfAnotherPlaceIsNotConverged) {
  PfLocalizationConfig c = test::demo_config();
  c.map_file = test_data::bundled_file("mrpt/malaga-cs-fac-building.simplemap.gz");
  PfLocalizationRunOptions o;
  o.num_threads = 2;
  ParticleInit init = c.options.init;
  init.mode = ParticleInitMode::FreeSpace;
  init.count = 20000;
  o.init = init;
  const PfLocalizationResult r = run_pf_localization(std::move(c), test::demo_rawlog(), o);
  EXPECT_FALSE(r.ok()) << r.message;
  ASSERT_FALSE(r.issues.empty());
  EXPECT_TRUE(r.issues.front().code == "not-converged" || r.issues.front().code == "lost");
}

struct DemoStep {
  std::shared_ptr<const ActionCollection> action;
  std::shared_ptr<const SensoryFrame> frame;
};

std::vector<DemoStep> demo_steps() {
  const AnyRawlog log = load_any_rawlog(test::demo_rawlog());
  std::vector<DemoStep> steps;
  std::shared_ptr<const ActionCollection> pending;
  for (const auto& e : log.entries) {
    if (const auto* a = std::get_if<std::shared_ptr<const ActionCollection>>(&e)) pending = *a;
    if (const auto* f = std::get_if<std::shared_ptr<const SensoryFrame>>(&e)) {
      if (pending) steps.push_back({pending, *f});
      pending.reset();
    }
  }
  return steps;
}

const RobotMovement2D* movement_of(const ActionCollection& a) {
  for (const auto& x : a.actions) {
    if (const auto* m = dynamic_cast<const RobotMovement2D*>(x.get())) return m;
  }
  return nullptr;
}

// The log cut after step 22 and continued from step 6: the robot is carried
// 5.6 m back along the corridor while its odometry reports step 23's small
// motion. With augmented MCL (recovery_alpha_slow 0.001, _fast 0.2) the
// filter is back on MRPT's path (within 0.3 m, and stays) within 15 steps in
// every seed. (Over seeds 0–9 it took 4–12 steps; with _fast 0.1, 4–19:
// bench/RESULTS.md.)
TEST(PfLocalizationDemo, RecoversFromAKidnapping) {
  const test::MrptPfReference ref = test::mrpt_pf_reference();
  const std::vector<DemoStep> steps = demo_steps();
  ASSERT_EQ(steps.size(), 37u);
  PfLocalizationConfig c = test::demo_config();
  MultiMetricMap map = std::move(c.map);
  load_localization_map(c, map);
  constexpr std::size_t kCut = 22, kResume = 6, kBound = 15;
  for (std::uint64_t seed = 0; seed < 3; ++seed) {
    MclOptions o = c.options;
    o.seed = seed;
    o.num_threads = 2;
    o.recovery.alpha_slow = 0.001;
    o.recovery.alpha_fast = 0.2;
    MonteCarloLocalization mcl(map, o);
    mcl.initialize();
    MclStepResult tracked;
    for (std::size_t k = 0; k <= kCut; ++k) {
      tracked = mcl.step(movement_of(*steps[k].action), *steps[k].frame);
    }
    ASSERT_LT(pose_of(tracked.estimate).distance_to(ref.median.at(static_cast<int>(kCut))), 0.15);
    std::optional<std::size_t> back;
    for (std::size_t k = kResume; k < steps.size(); ++k) {
      const RobotMovement2D* m = movement_of(*steps[k == kResume ? kCut + 1 : k].action);
      const MclStepResult r = mcl.step(m, *steps[k].frame);
      const auto it = ref.median.find(static_cast<int>(k));
      if (it == ref.median.end()) continue;
      const bool on = pose_of(r.estimate).distance_to(it->second) < 0.3;
      if (on && !back) back = k - kResume + 1;
      if (!on) back.reset();
    }
    ASSERT_TRUE(back.has_value()) << "seed " << seed << " never found the robot again";
    EXPECT_LE(*back, kBound) << "seed " << seed;
    std::printf("kidnapping, seed %llu: back on MRPT's path %zu steps after the jump\n",
                static_cast<unsigned long long>(seed), *back);
  }
}

// The demo as an observation-only log (layout #2, as MRPT's
// localization_demo_obsformat.rawlog): before each scan the odometry
// reading accumulated from the actions. The steps take the increment since
// the previous scan with [DummyOdometryParams]' Gaussian (0.10 m, 2°) and
// end on MRPT's path.
TEST(PfLocalizationDemo, ObservationOnlyLayout) {
  const test::MrptPfReference ref = test::mrpt_pf_reference();
  std::vector<RawlogEntry> entries;
  Pose2 odometry;
  std::optional<Pose2> first;
  for (const DemoStep& step : demo_steps()) {
    odometry = odometry + movement_of(*step.action)->odometry_increment;
    if (!first) first = odometry;
    auto reading = std::make_shared<OdometryObservation>();
    reading->odometry = odometry;
    reading->timestamp = step.frame->observations.front()->timestamp;
    entries.emplace_back(std::shared_ptr<const Observation>(std::move(reading)));
    for (const auto& o : step.frame->observations) entries.emplace_back(o);
  }
  const std::string path = ::testing::TempDir() + "pf_localization_obs_only.rrlog";
  RoveRawlogWriterOptions w;
  w.layout = RawlogLayout::Observations;
  save_rove_rawlog(path, entries, w);
  PfLocalizationRunOptions o;
  o.num_threads = 2;
  const PfLocalizationResult r = run_pf_localization(test::demo_config(), path, o);
  std::remove(path.c_str());
  ASSERT_EQ(r.steps.size(), 37u);
  EXPECT_TRUE(r.ok()) << r.message;
  const Pose2 p = pose_of(r.steps.back().estimate);
  EXPECT_LT(p.distance_to(ref.median.at(36)), 0.15);
  EXPECT_LT(std::abs(wrap_to_pi(p.phi() - ref.median.at(36).phi())), 3 * kDeg);
  // The odometry path starts at the first reading (its first step has no
  // motion), as MRPT's.
  EXPECT_LT(r.steps.back().odometry.distance_to(odometry - *first), 1e-9);
}

}  // namespace
}  // namespace rove

namespace rove {
namespace {

// Range-only localization on MRPT's UWB log (three beacons, 342 steps) with
// MRPT's ro-localization-demo.ini made for it (tests/data/uwb_pf_localization.ini
// says what changed): the position RMSE against the log's ground truth.
// MRPT 2.5.8's pf-localization on the same config: 1.50–1.63 m over five
// runs (bench/run_pf_localization_vs_mrpt.sh); rove 1.41–1.48 m. The
// ranges hold outliers of 10-25 sigma the Gaussian range model cannot
// absorb, and the run says so: it ends not converged ("lost"), the range
// residual above converged_max_range_residual.
TEST(PfLocalizationRangeOnly, UwbLogAgainstGroundTruth) {
  const std::string truth_path = test_data::mrpt_package_file("uwb_ro-localization_demo_GT.txt");
  PfLocalizationConfig c = load_pf_localization_config(IniFile::load(
      std::string(ROVE_SOURCE_DIR) + "/modules/slam/tests/data/uwb_pf_localization.ini"));
  const std::string rawlog = c.resolve(c.rawlog_file, "rawlog_file");
  PfLocalizationRunOptions o;
  o.num_threads = 2;
  const PfLocalizationResult r = run_pf_localization(std::move(c), rawlog, o);
  ASSERT_EQ(r.steps.size(), 342u);
  // Ground truth: `step x y phi` in the odometry frame, at (2, 4) m in the
  // beacons' frame.
  std::ifstream in(truth_path);
  std::map<std::uint64_t, Eigen::Vector2d> truth;
  double i = 0, x = 0, y = 0, phi = 0;
  while (in >> i >> x >> y >> phi) truth[static_cast<std::uint64_t>(i)] = {x + 2.0, y + 4.0};
  ASSERT_EQ(truth.size(), 342u);
  double sum = 0.0;
  for (const auto& s : r.steps) sum += (s.estimate.mean.translation() - truth.at(s.index)).squaredNorm();
  const double rmse = std::sqrt(sum / static_cast<double>(r.steps.size()));
  std::printf("UWB range-only localization: position RMSE %.3f m over %zu steps (%s)\n", rmse,
              r.steps.size(), std::string(to_string(r.termination)).c_str());
  EXPECT_LT(rmse, 2.0);
  EXPECT_GT(rmse, 0.3);  // if this fails, the range model improved: update the figures
  EXPECT_FALSE(r.ok());
}

}  // namespace
}  // namespace rove
