#include "rove/slam/pf_localization_config.h"

#include <algorithm>
#include <numbers>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/memory_budget.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/slam/config_path.h"

namespace rove {
namespace {

constexpr const char* kSec = "LocalizationExperiment";
constexpr double kDeg = std::numbers::pi / 180.0;
// Bytes a particle costs at its peak (state, log-weight, the step's copies
// and KLD bookkeeping), for the memory-budget check of particles_count.
constexpr std::uint64_t kBytesPerParticle = 160;

ParticleInitMode read_init_mode(const IniFile& ini, const ConfigSection& sec) {
  // MRPT reads init_PDF_mode as a boolean and requires it.
  const std::string v = ini.get<std::string>(kSec, "init_PDF_mode");
  std::string lower = v;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "false") return ParticleInitMode::FreeSpaceInBox;
  if (lower == "true") return ParticleInitMode::UniformInBox;
  const int mode = ini.get<int>(kSec, "init_PDF_mode");
  if (mode < 0 || mode > 3) {
    sec.fail("init_PDF_mode",
             fmt::format("{} is not a mode: 0 free cells in the box, 1 uniform in the box (MRPT); "
                         "2 free space of the whole map, 3 Gaussian around init_PDF_mean_* (rove)",
                         mode));
  }
  return static_cast<ParticleInitMode>(mode);
}

std::uint32_t read_particle_count(const IniFile& ini, const ConfigSection& sec) {
  const std::vector<std::int64_t> counts = ini.get_vector<std::int64_t>(kSec, "particles_count");
  if (counts.size() != 1) {
    sec.fail("particles_count",
             fmt::format("give one particle count ({} given); MRPT runs one experiment per value, "
                         "rove one run per call",
                         counts.size()));
  }
  if (counts[0] < 1 || counts[0] > 0xffffffffLL) {
    sec.fail("particles_count", fmt::format("{} particles: give at least 1", counts[0]));
  }
  const auto count = static_cast<std::uint32_t>(counts[0]);
  check_memory_budget(checked_bytes(count, kBytesPerParticle),
                      fmt::format("[{}] particles_count={} in {}", kSec, count, ini.source()));
  return count;
}

ParticleInit read_init(const IniFile& ini, const ConfigSection& sec) {
  ParticleInit init;
  if (ini.has(kSec, "particles_count")) init.count = read_particle_count(ini, sec);
  if (ini.has(kSec, "init_PDF_mode")) init.mode = read_init_mode(ini, sec);
  init.min_x = sec.get<double>("init_PDF_min_x", 0.0);
  init.max_x = sec.get<double>("init_PDF_max_x", 0.0);
  init.min_y = sec.get<double>("init_PDF_min_y", 0.0);
  init.max_y = sec.get<double>("init_PDF_max_y", 0.0);
  init.min_yaw = sec.get<double>("init_PDF_min_yaw_deg", -180.0) * kDeg;
  init.max_yaw = sec.get<double>("init_PDF_max_yaw_deg", 180.0) * kDeg;
  if (init.min_x > init.max_x) sec.fail("init_PDF_max_x", "below init_PDF_min_x");
  if (init.min_y > init.max_y) sec.fail("init_PDF_max_y", "below init_PDF_min_y");
  if (init.min_yaw > init.max_yaw) sec.fail("init_PDF_max_yaw_deg", "below init_PDF_min_yaw_deg");
  init.pose = SE2d(sec.get<double>("init_PDF_mean_x", 0.0), sec.get<double>("init_PDF_mean_y", 0.0),
                   sec.get<double>("init_PDF_mean_yaw_deg", 0.0) * kDeg);
  init.std_xy = sec.get_in_range("init_PDF_std_xy", init.std_xy, 0.0, 1e6);
  init.std_yaw = sec.get_in_range("init_PDF_std_yaw_deg", init.std_yaw / kDeg, 0.0, 1e6) * kDeg;
  // MRPT's 3D particle limits; rove localizes in 2D.
  sec.ignore({"init_PDF_min_z", "init_PDF_max_z", "init_PDF_min_pitch_deg", "init_PDF_max_pitch_deg",
              "init_PDF_min_roll_deg", "init_PDF_max_roll_deg"},
             "limits of MRPT's 3D particles (use_3D_poses); rove localizes in 2D");
  return init;
}

void read_rove_keys(const ConfigSection& sec, MclOptions& o) {
  o.recovery.alpha_slow = sec.get_in_range("recovery_alpha_slow", 0.0, 0.0, 0.999999);
  o.recovery.alpha_fast = sec.get_in_range("recovery_alpha_fast", 0.0, 0.0, 0.999999);
  const RecoveryOptions& r = o.recovery;
  if (!((r.alpha_slow == 0.0 && r.alpha_fast == 0.0) ||
        (r.alpha_slow > 0.0 && r.alpha_slow < r.alpha_fast))) {
    sec.fail("recovery_alpha_fast",
             fmt::format("recovery needs 0 < recovery_alpha_slow < recovery_alpha_fast, or both 0 "
                         "(off); got {} and {}",
                         r.alpha_slow, r.alpha_fast));
  }
  ConvergenceOptions& c = o.convergence;
  c.radius = sec.get_in_range("converged_radius", c.radius, 1e-9, 1e9);
  c.heading_radius =
      sec.get_in_range("converged_heading_radius_deg", c.heading_radius / kDeg, 1e-9, 180.0) * kDeg;
  c.min_mass = sec.get_in_range("converged_min_mass", c.min_mass, 1e-9, 1.0);
  c.min_steps = static_cast<std::uint32_t>(
      sec.get_in_range("converged_min_steps", c.min_steps, 1.0, 1e9));
  c.min_scan_fit = sec.get_in_range("converged_min_scan_fit", c.min_scan_fit, 0.0, 1.0);
  c.fit_distance = sec.get_in_range("converged_fit_distance", c.fit_distance, 1e-9, 1e9);
  c.max_range_residual =
      sec.get_in_range("converged_max_range_residual", c.max_range_residual, 1e-9, 1e9);
}

void read_filter_sections(const IniFile& ini, PfLocalizationConfig& cfg) {
  MclOptions& o = cfg.options;
  o.pf = ParticleFilterOptions::from_config(ConfigSection(ini, "PF_options", &cfg.ignored_keys));
  o.kld = KldOptions::from_config(ConfigSection(ini, "KLD_options", &cfg.ignored_keys));
  if (ini.has_section("DummyOdometryParams")) {
    const ConfigSection dummy(ini, "DummyOdometryParams", &cfg.ignored_keys);
    o.dummy_odometry.min_std_xy_m =
        dummy.get_in_range("minStdXY", o.dummy_odometry.min_std_xy_m, 0.0, 1e6);
    o.dummy_odometry.min_std_phi_rad =
        dummy.get_in_range("minStdPHI", o.dummy_odometry.min_std_phi_rad / kDeg, 0.0, 1e6) * kDeg;
    dummy.ignore({"additional_std_XYZ", "additional_std_angle"},
                 "odometry noise of MRPT's 3D particles; rove localizes in 2D");
    dummy.check_all_read();
  }
  if (ini.has_section("MotionModel")) {
    const ConfigSection motion(ini, "MotionModel", &cfg.ignored_keys);
    o.motion_model = MotionModelOptions::from_config(motion);
    motion.check_all_read();
  }
}

}  // namespace

std::string PfLocalizationConfig::resolve(const std::string& path, const std::string& key) const {
  return resolve_config_path(source, kSec, key, path);
}

PfLocalizationConfig load_pf_localization_config(const IniFile& ini) {
  PfLocalizationConfig cfg;
  cfg.source = ini.source();
  const ConfigSection sec(ini, kSec, &cfg.ignored_keys);
  if (!ini.has_section(kSec)) {
    sec.fail("particles_count",
             "the file has no [LocalizationExperiment] section: not a pf-localization config");
  }
  if (sec.get<bool>("use_3D_poses", false)) {
    sec.fail("use_3D_poses", "3D particles (CMonteCarloLocalization3D) are not supported; rove "
                             "localizes in 2D");
  }
  cfg.map_file = sec.get<std::string>("map_file", "");
  cfg.rawlog_file = sec.get<std::string>("rawlog_file", "");
  cfg.ground_truth_file = sec.get<std::string>("ground_truth_path_file", "");
  cfg.rawlog_offset = sec.get<std::uint64_t>("rawlog_offset", 0);
  cfg.initial_odometry =
      Pose2(sec.get<double>("initial_odo_x", 0.0), sec.get<double>("initial_odo_y", 0.0),
            sec.get<double>("initial_odo_phi", 0.0));
  cfg.options.init = read_init(ini, sec);
  read_rove_keys(sec, cfg.options);
  sec.ignore({"logOutput_dir", "3DSceneFrequency", "3DSceneFollowRobot", "experimentRepetitions",
              "SHOW_PROGRESS_3D_REAL_TIME", "SHOW_PROGRESS_3D_REAL_TIME_DELAY_MS", "SAVE_STATS_ONLY",
              "DO_RELIABILITY_ESTIMATE", "DO_SCAN_LIKELIHOOD_DEBUG", "STATS_CONF_INTERVAL",
              "experimentTestConvergenceAtStep"},
             "MRPT pf-localization GUI/logging/experiment switch; rove runs once and writes its "
             "outputs to -o DIR (--seed repeats a run)");
  sec.check_all_read();
  // Mandatory in MRPT, checked after the unknown keys so a misspelt one is
  // named as such.
  if (!ini.has(kSec, "particles_count")) {
    sec.fail("particles_count", "missing: the initial number of particles (MRPT requires it)");
  }
  if (!ini.has(kSec, "init_PDF_mode")) {
    sec.fail("init_PDF_mode", "missing: how the particles start (MRPT requires it)");
  }
  read_filter_sections(ini, cfg);

  MultiMetricMapLoadReport report;
  cfg.map = MultiMetricMap::from_config(ini, "MetricMap", &report);
  cfg.ignored_keys.insert(cfg.ignored_keys.end(), report.ignored_keys.begin(),
                          report.ignored_keys.end());
  ConfigSection(ini, "MetricMap", &cfg.ignored_keys).check_all_read();
  const bool has_grid = std::any_of(cfg.map.entries().begin(), cfg.map.entries().end(),
                                    [](const MetricMapEntry& e) {
                                      return dynamic_cast<const OccupancyGridMetricMap*>(
                                                 e.map.get()) != nullptr;
                                    });
  const ParticleInitMode mode = cfg.options.init.mode;
  if (!has_grid && (mode == ParticleInitMode::FreeSpaceInBox || mode == ParticleInitMode::FreeSpace)) {
    sec.fail("init_PDF_mode",
             fmt::format("mode {} draws particles over the free cells of an occupancy grid, but "
                         "[MetricMap] declares none (occupancyGrid_count)",
                         static_cast<int>(mode)));
  }
  if (!has_grid && cfg.options.recovery.enabled()) {
    sec.fail("recovery_alpha_slow",
             "recovery draws particles over the free cells of an occupancy grid, but [MetricMap] "
             "declares none (occupancyGrid_count)");
  }
  return cfg;
}

}  // namespace rove
