// RBPF grid mapping against ground truth (a robot driving a loop through the
// simulated building of the ICP-SLAM ground-truth test, with drifting
// odometry), determinism by seed, sharing of the maps' tiles, and the
// configuration reader's errors.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

#include "icp_slam_test_util.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/slam/rbpf_slam.h"
#include "rove/slam/rbpf_slam_config.h"
#include "rove/slam/rbpf_slam_run.h"
#include "rove/test_data.h"
#include "sim_building.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// The simulated drive: true poses, the odometry increments between them
/// (2 % scale error, 1 cm and 0.3° noise, 0.8° of heading drift per meter)
/// and a 361-ray scan per pose (1 cm range noise).
struct Drive {
  std::vector<Pose2> truth;
  std::vector<Pose2> increments;  // increments[k]: from pose k−1 to k (k ≥ 1)
  std::vector<RangeScan2D> scans;
};

Drive simulate(std::uint64_t seed) {
  const Eigen::Vector2d origin(0.0, 0.0);
  const auto walls = test::building(origin);
  Drive d;
  d.truth = test::loop_path(origin);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (std::size_t k = 0; k < d.truth.size(); ++k) {
    if (k == 0) {
      d.increments.emplace_back();
    } else {
      const Pose2 t = d.truth[k] - d.truth[k - 1];
      d.increments.emplace_back(1.02 * t.x() + 0.01 * unit(rng), 1.02 * t.y() + 0.01 * unit(rng),
                                t.phi() + kDeg * (0.3 * unit(rng) + 0.8 * t.norm()));
    }
    d.scans.push_back(test::simulate_scan(walls, d.truth[k], 0.01, unit, rng));
  }
  return d;
}

/// gridmapping_optimal_sampling.ini's filter with gridmapping_intel.ini's
/// sharper likelihood (LF_stdHit 0.05 m) on a 5 cm grid, weights tempered
/// by 0.3.
RbpfSlamOptions sim_options(std::uint64_t seed, int threads = 1) {
  RbpfSlamOptions o;
  o.proposal = RbpfProposal::Optimal;
  o.particles = 8;
  o.beta = 0.5;
  o.pow_factor = 0.3;
  o.search_samples = 100;
  o.resolution = 0.05f;
  o.insertion.max_distance_insertion = 30.0f;
  o.insertion.max_occupancy_update_certainty = 0.6f;
  o.likelihood.lf_decimation = 5;
  o.likelihood.lf_std_hit = 0.05f;
  o.likelihood.lf_max_corrs_distance = 0.3f;
  o.likelihood.lf_z_hit = 0.999f;
  o.likelihood.lf_z_random = 0.001f;
  o.likelihood.lf_max_range = 30.0f;
  o.seed = seed;
  o.num_threads = threads;
  return o;
}

/// Feeds the drive: an update every 0.5 m or 20° of odometry, each inserting.
struct Mapped {
  std::unique_ptr<RbpfSlam> slam;
  std::vector<std::size_t> steps;  // steps that updated
  std::size_t resamplings = 0;
  // Updates with more than kContradictedRays of the rays through walls.
  std::size_t contradicted = 0;
  // Every update, as a run records it.
  std::vector<RbpfSlamStep> updates;
};

/// With `odometry_only`, the increments' Gaussians are a hair wide: the
/// motion model's proposal then follows the odometry.
Mapped map_drive(const Drive& d, const RbpfSlamOptions& options, bool odometry_only = false) {
  Mapped m;
  m.slam = std::make_unique<RbpfSlam>(options);
  m.slam->insert(d.scans[0], 0);
  Pose2 acc;
  for (std::size_t k = 1; k < d.truth.size(); ++k) {
    acc = acc + d.increments[k];
    if (acc.norm() < 0.5 && std::abs(acc.phi()) < 20 * kDeg) continue;
    OdometryIncrement u;
    u.mean = SE2d(acc.x(), acc.y(), acc.phi());
    // A 5 % / 2° per meter Gaussian of the accumulated increment.
    const double dist = acc.norm();
    u.covariance = odometry_only
                       ? Eigen::Vector3d(1e-8, 1e-8, 1e-10).asDiagonal().toDenseMatrix()
                       : Eigen::Vector3d(std::pow(0.05 * dist + 0.01, 2), std::pow(0.05 * dist + 0.01, 2),
                                         std::pow((2.0 * dist + 1.0) * kDeg + 0.05 * std::abs(acc.phi()), 2))
                             .asDiagonal()
                             .toDenseMatrix();
    const RbpfUpdateResult r = m.slam->update(u, d.scans[k], k, true);
    m.resamplings += r.resampled ? 1 : 0;
    m.contradicted += r.through_walls > kContradictedRays ? 1 : 0;
    m.steps.push_back(k);
    RbpfSlamStep step;
    step.index = k;
    step.updated = true;
    step.update = r;
    m.updates.push_back(step);
    acc = Pose2();
  }
  return m;
}

/// Position RMSE of the best particle's path against the truth, both taken
/// relative to the first pose.
double path_rmse(const Drive& d, const RbpfSlam& slam) {
  const auto nodes = path_of(slam.particles()[slam.best()]);
  double s = 0.0;
  for (const auto& n : nodes) {
    const Pose2 est(n.pose.translation().x(), n.pose.translation().y(), n.pose.angle());
    const Pose2 truth = d.truth[n.step] - d.truth[0];
    s += std::pow(est.x() - truth.x(), 2) + std::pow(est.y() - truth.y(), 2);
  }
  return std::sqrt(s / static_cast<double>(nodes.size()));
}

/// Share of the map's occupied cells within `tol` meters of a true wall
/// (the map frame is the first pose's).
double walls_agree(const Drive& d, const TiledGrid& map, double tol) {
  const auto walls = test::building(Eigen::Vector2d(0.0, 0.0));
  const Pose2 T0 = d.truth[0];
  const auto cells = map.occupied_points(-50, 50, -50, 50);
  std::size_t near = 0;
  for (const auto& c : cells) {
    const Pose2 w = T0 + Pose2(c.x(), c.y(), 0.0);
    double best = 1e9;
    for (const auto& s : walls) {
      const Eigen::Vector2d e = s.b - s.a;
      const double t = std::clamp((w.translation() - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (s.a + t * e - w.translation()).norm());
    }
    near += best <= tol ? 1 : 0;
  }
  return cells.empty() ? 0.0 : static_cast<double>(near) / static_cast<double>(cells.size());
}

TEST(RbpfSlam, ClosesTheSimulatedLoop) {
  const Drive d = simulate(1);
  // Odometry alone drifts by meters around the loop.
  Pose2 odo;
  for (std::size_t k = 1; k < d.truth.size(); ++k) odo = odo + d.increments[k];
  const Pose2 true_end = d.truth.back() - d.truth.front();
  ASSERT_GT((odo.translation() - true_end.translation()).norm(), 1.0);
  // The map built along the odometry fails the wall check below.
  {
    TiledGrid odo_map(0.05f);
    RbpfSlamOptions o = sim_options(1);
    Pose2 p;
    for (std::size_t k = 0; k < d.truth.size(); k += 3) {
      if (k > 0) {
        for (std::size_t j = k - 2; j <= k; ++j) p = p + d.increments[j];
      }
      insert_scan(odo_map, d.scans[k], SE2d(p.x(), p.y(), p.phi()), o.insertion);
    }
    EXPECT_LT(walls_agree(d, odo_map, 0.15), 0.8);
  }
  // Eight seeds: with 8 particles one run in ten leaves a stretch of wall
  // a cell off (92.8–94.8 % of the cells within 0.15 m over 32 seeds, the
  // path still within 0.13 m), so single runs are held to looser bounds
  // than the seeds together.
  std::vector<double> rmses, agreements;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const Mapped m = map_drive(d, sim_options(seed));
    const RbpfSlam& slam = *m.slam;
    const double rmse = path_rmse(d, slam);
    EXPECT_LT(rmse, 0.15) << "seed " << seed;
    // The map's walls are where the true walls are: single, not doubled.
    const double agree = walls_agree(d, slam.particles()[slam.best()].map, 0.15);
    EXPECT_GT(agree, 0.9) << "seed " << seed;
    rmses.push_back(rmse);
    agreements.push_back(agree);
    // The scans do not contradict the map (the run is not flagged).
    EXPECT_LE(static_cast<double>(m.contradicted), kContradictedScans * static_cast<double>(m.steps.size()))
        << "seed " << seed;
    std::printf("seed %d: path RMSE %.3f m, %.1f %% of the occupied cells within 0.15 m of a wall\n",
                static_cast<int>(seed), rmse, 100.0 * agree);
    const auto nodes = path_of(slam.particles()[slam.best()]);
    const Pose2 end(nodes.back().pose.translation().x(), nodes.back().pose.translation().y(),
                    nodes.back().pose.angle());
    const Pose2 truth_end = d.truth[nodes.back().step] - d.truth[0];
    EXPECT_LT((end.translation() - truth_end.translation()).norm(), 0.15) << "seed " << seed;
    EXPECT_LT(std::abs(end.phi() - truth_end.phi()), 2.0 * kDeg) << "seed " << seed;
  }
  // Over 32 seeds: path RMSE 0.070 m, 99.2 % of the cells on a wall (mean).
  const auto mean = [](const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  };
  EXPECT_LT(mean(rmses), 0.1);
  EXPECT_GT(mean(agreements), 0.97);
}

/// A filter that can only follow the odometry (one particle, the motion
/// model's proposal with a tiny spread) closes the loop where the drifting
/// odometry puts it: the walls of the return overlay the first pass's at an
/// angle, its scans see through them, and the run's checks say so; the
/// optimal proposal's map of the same drive is not flagged.
TEST(RbpfSlam, ScansContradictAMapBuiltAlongTheOdometry) {
  const Drive d = simulate(1);
  RbpfSlamOptions o = sim_options(1);
  o.particles = 1;
  o.proposal = RbpfProposal::Standard;
  const Mapped odometry = map_drive(d, o, true);
  const std::vector<RbpfSlamStep>& steps = odometry.updates;
  const RbpfScanChecks c = scan_checks(steps);
  std::printf("along the odometry: %zu of %zu updates contradicted, mean fit %.3f\n", c.contradicted,
              c.updates, c.mean_fit);
  EXPECT_EQ(c.updates, steps.size());
  EXPECT_GT(static_cast<double>(c.contradicted), kContradictedScans * static_cast<double>(c.updates));
  EXPECT_GE(c.contradicted, 3u);
  // The fit alone does not tell: most points still lie near some wall.
  EXPECT_GT(c.mean_fit, 0.5);
  // The optimal proposal's map of the same drive.
  const Mapped m = map_drive(d, sim_options(1));
  std::printf("optimal proposal: %zu of %zu updates contradicted\n", m.contradicted, m.steps.size());
  EXPECT_LE(static_cast<double>(m.contradicted), kContradictedScans * static_cast<double>(m.steps.size()));
  EXPECT_LT(m.contradicted, c.contradicted);
}

TEST(RbpfSlamRun, ScanChecksCountUpdatesOnly) {
  std::vector<RbpfSlamStep> steps(5);
  steps[0].updated = false;  // not an update: not counted, whatever it holds
  steps[0].update.through_walls = 0.9;
  steps[0].update.fit = 0.0;
  steps[1].updated = true;
  steps[1].update.through_walls = 0.25;
  steps[1].update.fit = 0.5;
  steps[2].updated = true;
  steps[2].update.through_walls = kContradictedRays;  // at the bound: not contradicted
  steps[2].update.fit = 1.0;
  steps[3].updated = true;
  steps[3].update.through_walls = 1.0;
  steps[3].update.fit = 0.75;
  steps[4].updated = false;
  const RbpfScanChecks c = scan_checks(steps);
  EXPECT_EQ(c.updates, 3u);
  EXPECT_EQ(c.contradicted, 2u);
  EXPECT_DOUBLE_EQ(c.mean_fit, 0.75);
  const RbpfScanChecks none = scan_checks({});
  EXPECT_EQ(none.updates, 0u);
  EXPECT_EQ(none.contradicted, 0u);
  EXPECT_EQ(none.mean_fit, 1.0);
}

/// Regression test of the Intel log's bent corridors (MRPT's
/// gridmapping_intel.ini on the Radish log): the log's odometry turns 1.2°
/// too far per update on average. The likelihood of one in LF_decimation
/// points (45 of 180) is constant over a cell of motion, and on that plateau
/// the motion prior used to decide the optimal proposal's mode: every update
/// kept part of the bias (−0.29° per update against rove lidar-slam's path),
/// and after the first loop, at step 5,000, the most likely particle was
/// 10.8 m and 93° from lidar-slam's pose there (seed 1). The mode is now
/// refined on every point of the scan: 0.09 m and 1.8°.
TEST(RbpfSlamDatasets, IntelFirstLoopDoesNotBend) {
  const std::string log = test_data::shared_dataset("radish/intel.clf.bz2");
  const RbpfSlamConfig config = load_rbpf_slam_config(IniFile::load(test::data_path("gridmapping_intel.ini")));
  RbpfSlamRunOptions run;
  run.seed = 1;
  run.num_threads = 2;
  run.max_steps = 5001;
  const RbpfSlamResult r = run_rbpf_slam(config, log, run);
  ASSERT_EQ(r.path.size(), 5001u);
  // rove lidar-slam's pose of the same scan (the log's 5,002nd; its map
  // frame is the first scan's, 4 mm from the RBPF's first step).
  const Pose2 reference(9.8834, -7.2408, 53.736 * kDeg);
  const Pose2& p = r.path[5000];
  const double position = (p.translation() - reference.translation()).norm();
  const double heading = std::remainder(p.phi() - reference.phi(), 2.0 * std::numbers::pi) / kDeg;
  std::printf("[Intel] step 5000: %.3f m, %+.2f deg from lidar-slam's pose; %zu resamplings\n", position,
              heading, static_cast<std::size_t>(std::count_if(r.steps.begin(), r.steps.end(), [](const auto& s) {
                return s.updated && s.update.resampled;
              })));
  EXPECT_LT(position, 0.5);
  EXPECT_LT(std::abs(heading), 8.0);
}

TEST(RbpfSlam, SameSeedSameResultAnyThreadCount) {
  const Drive d = simulate(4);
  const Drive shorter{std::vector<Pose2>(d.truth.begin(), d.truth.begin() + 60),
                      std::vector<Pose2>(d.increments.begin(), d.increments.begin() + 60),
                      std::vector<RangeScan2D>(d.scans.begin(), d.scans.begin() + 60)};
  const Mapped a = map_drive(shorter, sim_options(7, 1));
  const Mapped b = map_drive(shorter, sim_options(7, 3));
  const Mapped c = map_drive(shorter, sim_options(8, 1));
  ASSERT_EQ(a.slam->particles().size(), b.slam->particles().size());
  bool differs_by_seed = false;
  for (std::size_t i = 0; i < a.slam->particles().size(); ++i) {
    const auto& pa = a.slam->particles()[i];
    const auto& pb = b.slam->particles()[i];
    EXPECT_TRUE(pa.pose.translation() == pb.pose.translation() && pa.pose.angle() == pb.pose.angle());
    EXPECT_TRUE(pa.map == pb.map);
    EXPECT_EQ(a.slam->log_weights()[i], b.slam->log_weights()[i]);
    differs_by_seed = differs_by_seed ||
                      pa.pose.translation() != c.slam->particles()[i].pose.translation();
  }
  EXPECT_TRUE(differs_by_seed);
}

TEST(RbpfSlam, ResampledCopiesShareTiles) {
  const Drive d = simulate(5);
  RbpfSlamOptions o = sim_options(3);
  o.particles = 16;
  o.beta = 1.0;  // resample after every update
  const Mapped always = map_drive(d, o);
  o.beta = 0.0;  // never
  const Mapped never = map_drive(d, o);
  EXPECT_EQ(always.resamplings, always.steps.size());
  EXPECT_EQ(never.resamplings, 0u);
  std::size_t largest = 0;
  for (const auto& p : always.slam->particles()) largest = std::max(largest, p.map.tile_count());
  // Copies share their tiles: the maps hold less than half of what 16
  // unshared maps would, and less than the maps of particles never
  // resampled (each of which wrote its own copy of every tile it touched).
  EXPECT_LT(2 * always.slam->distinct_tiles(), 16 * largest);
  EXPECT_LT(always.slam->distinct_tiles(), never.slam->distinct_tiles());
  EXPECT_GE(always.slam->distinct_tiles(), largest);
}

TEST(RbpfSlam, RejectsMalformedInput) {
  EXPECT_THROW(RbpfSlam([] {
                 RbpfSlamOptions o;
                 o.particles = 0;
                 return o;
               }()),
               InvalidArgument);
  const Drive d = simulate(6);
  RbpfSlam slam(sim_options(1));
  slam.insert(d.scans[0], 0);
  RangeScan2D bad = d.scans[1];
  OdometryIncrement u;
  u.mean = SE2d(0.5, 0.0, 0.0);
  u.covariance = Eigen::Matrix3d::Identity() * 1e-3;
  bad.ranges[100] = std::nanf("");  // flagged valid
  EXPECT_THROW(slam.update(u, bad, 1, true), InvalidArgument);
  bad = d.scans[1];
  OdometryIncrement negative = u;
  negative.covariance(0, 0) = -1.0;
  EXPECT_THROW(slam.update(negative, bad, 1, true), InvalidArgument);
}

// The configuration reader on MRPT's files and on broken variants of them.
std::string optimal_ini() {
  return read_input_file(test::data_path("gridmapping_optimal_sampling.ini"), 1 << 20, "test");
}

IniFile with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  return IniFile::parse(text, "test.ini");
}

TEST(RbpfSlamConfig, ReadsMrptFiles) {
  const RbpfSlamConfig c = load_rbpf_slam_config(IniFile::load(test::data_path("gridmapping_optimal_sampling.ini")));
  EXPECT_EQ(c.options.proposal, RbpfProposal::Optimal);
  EXPECT_EQ(c.options.particles, 25u);
  EXPECT_DOUBLE_EQ(c.options.pow_factor, 0.01);
  EXPECT_EQ(c.options.search_samples, 400u);
  EXPECT_FLOAT_EQ(c.options.resolution, 0.07f);
  EXPECT_FLOAT_EQ(c.options.likelihood.lf_std_hit, 0.2f);
  EXPECT_DOUBLE_EQ(c.insertion_lin_distance, 1.0);
  EXPECT_NEAR(c.localize_ang_distance, 40.0 * kDeg, 1e-12);
  EXPECT_FALSE(c.ignored_keys.empty());
  const RbpfSlamConfig intel = load_rbpf_slam_config(IniFile::load(test::data_path("gridmapping_intel.ini")));
  EXPECT_EQ(intel.options.particles, 20u);
  EXPECT_TRUE(intel.options.insertion.widening_beams_with_distance);
  const RbpfSlamConfig icp =
      load_rbpf_slam_config(IniFile::load(test::data_path("gridmapping_RBPF_grid_ICPbased_malaga.ini")));
  EXPECT_EQ(icp.options.proposal, RbpfProposal::Icp);
  EXPECT_DOUBLE_EQ(icp.options.icp_min_quality, 0.8);
}

TEST(RbpfSlamConfig, RefusesWhatItCannotDo) {
  const std::string text = optimal_ini();
  const auto refuses = [](const IniFile& ini, const std::string& key) {
    try {
      (void)load_rbpf_slam_config(ini);
      ADD_FAILURE() << "accepted a config with a bad " << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  refuses(with(text, "sampleSize=25", "sampleSize=0"), "sampleSize");
  refuses(with(text, "sampleSize=25", "sampleSize=-3"), "sampleSize");
  refuses(with(text, "adaptiveSampleSize\t= 0", "adaptiveSampleSize\t= 1"), "adaptiveSampleSize");
  refuses(with(text, "PF_algorithm\t\t= 3", "PF_algorithm\t\t= 1"), "PF_algorithm");
  refuses(with(text, "likelihoodMethod=4", "likelihoodMethod=1"), "likelihoodMethod");
  refuses(with(text, "occupancyGrid_count=1", "occupancyGrid_count=0"), "occupancyGrid_count");
  refuses(with(text, "pointsMap_count=0", "pointsMap_count=1"), "pointsMap_count");
  refuses(with(text, "BETA=0.50", "BETA=0.50\nmisspelledKey=1"), "misspelledKey");
  refuses(with(text, "\n[MappingApplication]", "\n[Mapping]"), "MappingApplication");
  refuses(IniFile::load(test::data_path("gridmapping_RBPF_ICPbased_intel.ini")), "pfOptimalProposal_mapSelection");
}

}  // namespace
}  // namespace rove
