#include "rove/slam/rbpf_slam_config.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "rove/bayes/particle_filter_options.h"
#include "rove/core/error.h"
#include "rove/maps/beacon_map.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/slam/config_path.h"

namespace rove {
namespace {

constexpr const char* kSec = "MappingApplication";
constexpr double kDeg = std::numbers::pi / 180.0;

// MRPT's particle-filter keys (TParticleFilterOptions), read by
// ParticleFilterOptions::from_config.
constexpr std::string_view kPfKeys[] = {
    "PF_algorithm", "resamplingMethod", "BETA", "sampleSize", "adaptiveSampleSize",
    "pfAuxFilterOptimal_MaximumSearchSamples", "powFactor", "max_loglikelihood_dyn_range",
    "pfAuxFilterStandard_FirstStageWeightsMonteCarlo", "pfAuxFilterOptimal_MLE"};

// The one map of the declaration: an occupancy grid or a beacon map;
// ConfigError otherwise.
const MetricMap& the_map(const MultiMetricMap& map, const ConfigSection& sec) {
  const MetricMap* only = nullptr;
  for (const auto& e : map.entries()) {
    const bool grid = dynamic_cast<const OccupancyGridMetricMap*>(e.map.get()) != nullptr;
    if (!grid && dynamic_cast<const BeaconMap*>(e.map.get()) == nullptr) {
      sec.fail(std::string(e.map->kind()) + "_count",
               fmt::format("rove's RBPF maps one occupancy grid or one beacon map per particle; a "
                           "{} map is not supported (set its count to 0)",
                           e.map->kind()));
    }
    if (only != nullptr) {
      sec.fail(std::string(e.map->kind()) + "_count",
               "exactly one map (one occupancy grid or one beacon map) is supported");
    }
    only = e.map.get();
  }
  if (only == nullptr) {
    sec.fail("occupancyGrid_count",
             "no map is declared: rove's RBPF builds one occupancy grid (occupancyGrid_count = 1) "
             "or one beacon map (beaconMap_count = 1) per particle");
  }
  return *only;
}

// Range-only SLAM: MRPT's RO-SLAM configs filter with pfStandardProposal.
void read_beacons(const BeaconMap& map, const ParticleFilterOptions& pf, RbpfSlamConfig& cfg,
                  const ConfigSection& sec) {
  if (pf.algorithm != ParticleFilterAlgorithm::StandardProposal) {
    sec.fail("PF_algorithm",
             fmt::format("{} is not supported with a beacon map: rove's range-only SLAM samples "
                         "the motion model and weighs by the ranges (0, pfStandardProposal)",
                         static_cast<int>(pf.algorithm)));
  }
  RoSlamOptions& b = cfg.beacons;
  b.particles = pf.sample_size;
  b.resampling = pf.resampling_method;
  b.beta = pf.beta;
  b.pow_factor = pf.pow_factor;
  b.insertion = map.insert_options;
  b.likelihood = map.likelihood_options;
  cfg.map = RbpfMapKind::Beacons;
  for (const char* key : {"pfAuxFilterOptimal_MaximumSearchSamples", "pfOptimalProposal_mapSelection",
                          "ICPGlobalAlign_MinQuality"}) {
    if (sec.has(key)) cfg.ignored_keys.push_back({kSec, key, "not used by range-only SLAM (PF_algorithm = 0)"});
  }
}

// The proposal of PF_algorithm / pfOptimalProposal_mapSelection.
RbpfProposal proposal_of(const ParticleFilterOptions& pf, int selection, const ConfigSection& sec) {
  switch (pf.algorithm) {
    case ParticleFilterAlgorithm::StandardProposal: return RbpfProposal::Standard;
    case ParticleFilterAlgorithm::AuxiliaryPFOptimal: return RbpfProposal::Optimal;
    case ParticleFilterAlgorithm::OptimalProposal: {
      if (selection != 0) {
        sec.fail("pfOptimalProposal_mapSelection",
                 fmt::format("{} selects a {} map for the ICP-based proposal; rove aligns with "
                             "the particle's occupancy grid only (0)",
                             selection, selection == 3 ? "points" : "non-grid"));
      }
      return RbpfProposal::Icp;
    }
    case ParticleFilterAlgorithm::AuxiliaryPFStandard: break;
  }
  sec.fail("PF_algorithm",
           "pfAuxiliaryPFStandard (1) is not supported for grid mapping; use 3 (optimal "
           "sampling), 2 (ICP-based) or 0 (standard)");
}

void read_grid(const OccupancyGridMetricMap& grid, RbpfSlamOptions& o, const IniFile& ini) {
  o.resolution = grid.grid().resolution();
  o.insertion = grid.insert_options;
  o.likelihood = grid.likelihood_options;
  const std::string lik = std::string(kSec) + "_occupancyGrid_00_likelihoodOpts";
  if (o.likelihood.method != GridLikelihoodMethod::LikelihoodFieldThrun) {
    throw ConfigError(ini.source(), lik, "likelihoodMethod",
                      fmt::format("{} is not supported by rove's RBPF: it evaluates scans with "
                                  "the likelihood field (4, lmLikelihoodField_Thrun)",
                                  static_cast<int>(o.likelihood.method)));
  }
  try {
    const TiledLikelihoodField field(o.resolution, o.likelihood, o.insertion);
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), lik, "LF_maxCorrsDistance", e.message());
  }
}

}  // namespace

std::string RbpfSlamConfig::resolve(const std::string& path, const std::string& key) const {
  return resolve_config_path(source, kSec, key, path);
}

RbpfSlamConfig load_rbpf_slam_config(const IniFile& ini) {
  RbpfSlamConfig cfg;
  cfg.source = ini.source();
  RbpfSlamOptions& o = cfg.options;
  const ConfigSection sec(ini, kSec, &cfg.ignored_keys);
  if (!ini.has_section(kSec)) {
    sec.fail("PF_algorithm", "the file has no [MappingApplication] section: not an rbpf-slam config");
  }
  cfg.rawlog_file = sec.get<std::string>("rawlog_file", "");
  cfg.rawlog_offset = sec.get<std::uint64_t>("rawlog_offset", 0);
  cfg.insertion_lin_distance = sec.get_in_range("insertionLinDistance", cfg.insertion_lin_distance, 0.0, 1e6);
  cfg.insertion_ang_distance =
      sec.get_in_range("insertionAngDistance_deg", cfg.insertion_ang_distance / kDeg, 0.0, 360.0) * kDeg;
  cfg.localize_lin_distance = sec.get_in_range("localizeLinDistance", cfg.localize_lin_distance, 0.0, 1e6);
  cfg.localize_ang_distance =
      sec.get_in_range("localizeAngDistance_deg", cfg.localize_ang_distance / kDeg, 0.0, 360.0) * kDeg;
  o.icp_min_quality = sec.get_in_range("ICPGlobalAlign_MinQuality", o.icp_min_quality, 0.0, 1.0);
  const int selection = sec.get<int>("pfOptimalProposal_mapSelection", 0);
  sec.ignore({"logOutput_dir", "LOG_FREQUENCY", "GENERATE_LOG_JOINT_H", "GENERATE_LOG_INFO",
              "SAVE_MAP_IMAGES", "SAVE_3D_SCENE", "SAVE_POSE_LOG", "SAVE_ENOSE_READINGS",
              "CAMERA_3DSCENE_FOLLOWS_ROBOT", "SHOW_PROGRESS_IN_WINDOW",
              "SHOW_PROGRESS_IN_WINDOW_DELAY_MS", "PROGRESS_WINDOW_WIDTH", "PROGRESS_WINDOW_HEIGHT",
              "verbosity_level"},
             "MRPT rbpf-slam GUI/logging switch; rove writes its outputs to -o DIR");
  sec.ignore({"max_loglikelihood_dyn_range", "pfAuxFilterOptimal_MLE",
              "pfAuxFilterStandard_FirstStageWeightsMonteCarlo"},
             "auxiliary particle-filter option; rove's proposals have no first stage");
  if (sec.get<bool>("adaptiveSampleSize", false)) {
    sec.fail("adaptiveSampleSize",
             "KLD-sampling (adaptiveSampleSize = 1) is not supported by rove's RBPF; set 0 and "
             "choose sampleSize");
  }
  sec.ignore_prefix("KLD_", "KLD-sampling option; used only with adaptiveSampleSize = 1");
  MultiMetricMapLoadReport report;
  const MultiMetricMap map = MultiMetricMap::from_config(ini, kSec, &report);
  cfg.ignored_keys.insert(cfg.ignored_keys.end(), report.ignored_keys.begin(), report.ignored_keys.end());
  // Everything else of the section is now read but the particle filter's and
  // the ICP's keys, whose loaders each demand that no key be left unread:
  // the PF keys are marked read first, so that the ICP loader reports only
  // truly unknown keys, then both load.
  for (const std::string_view key : kPfKeys) (void)sec.get<std::string>(key, "");
  o.icp = Icp2dOptions::from_config(sec);
  const ParticleFilterOptions pf = ParticleFilterOptions::from_config(sec);
  if (map.find("beaconMap") != nullptr) {
    read_beacons(dynamic_cast<const BeaconMap&>(the_map(map, sec)), pf, cfg, sec);
    try {
      cfg.beacons.check();
    } catch (const InvalidArgument& e) {
      throw ConfigError(ini.source(), kSec, "", e.message());
    }
    return cfg;
  }
  o.proposal = proposal_of(pf, selection, sec);
  if (o.proposal != RbpfProposal::Icp) {
    for (const char* key : {"pfOptimalProposal_mapSelection", "ICPGlobalAlign_MinQuality"}) {
      if (sec.has(key)) cfg.ignored_keys.push_back({kSec, key, "used by the ICP-based proposal (PF_algorithm = 2) only"});
    }
  }
  o.particles = pf.sample_size;
  o.resampling = pf.resampling_method;
  o.beta = pf.beta;
  o.pow_factor = pf.pow_factor;
  o.search_samples = pf.max_search_samples;
  if (o.search_samples < 4) {
    sec.fail("pfAuxFilterOptimal_MaximumSearchSamples",
             fmt::format("{} is below 4: too few poses to fit the proposal's Gaussian", o.search_samples));
  }
  read_grid(dynamic_cast<const OccupancyGridMetricMap&>(the_map(map, sec)), o, ini);
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), kSec, "", e.message());
  }
  return cfg;
}

}  // namespace rove
