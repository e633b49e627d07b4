#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/slam/config_path.h"
#include "rove/slam/kf_slam_run.h"

namespace rove {
namespace {

constexpr const char* kApp = "MappingApplication";
constexpr const char* kSlam = "RangeBearingKFSLAM";
constexpr const char* kKalman = "RangeBearingKFSLAM_KalmanFilter";

// MRPT's kf_implementation names.
enum class KfImplementation : std::uint8_t { Slam3D = 3, Slam2D = 2 };

}  // namespace

std::string KfSlamConfig::resolve(const std::string& path, const std::string& key) const {
  return resolve_config_path(source, kApp, key, path);
}

KfSlamConfig load_kf_slam_config(const IniFile& ini) {
  KfSlamConfig cfg;
  cfg.source = ini.source();
  const ConfigSection app(ini, kApp, &cfg.ignored_keys);
  const ConfigSection slam(ini, kSlam, &cfg.ignored_keys);
  const ConfigSection kf(ini, kKalman, &cfg.ignored_keys);
  if (!ini.has_section(kApp) && !ini.has_section(kSlam) && !ini.has_section(kKalman)) {
    throw ConfigError(cfg.source, kSlam, "",
                      "the file has none of [MappingApplication], [RangeBearingKFSLAM] and "
                      "[RangeBearingKFSLAM_KalmanFilter]: not a kf-slam config");
  }
  cfg.dim = static_cast<int>(app.get_enum<KfImplementation>(
      "kf_implementation", KfImplementation::Slam3D,
      {{"CRangeBearingKFSLAM", KfImplementation::Slam3D},
       {"CRangeBearingKFSLAM2D", KfImplementation::Slam2D}}));
  cfg.rawlog_file = app.get<std::string>("rawlog_file", "");
  cfg.ground_truth_file = app.get<std::string>("ground_truth_file", "");
  cfg.ground_truth_file_robot = app.get<std::string>("ground_truth_file_robot", "");
  const auto offset = app.get<std::int64_t>("rawlog_offset", 0);
  if (offset < 0) app.fail("rawlog_offset", fmt::format("{} steps: give 0 or more", offset));
  cfg.rawlog_offset = static_cast<std::uint64_t>(offset);
  app.ignore({"logOutput_dir", "SAVE_LOG_FREQUENCY", "SAVE_MAP_REPRESENTATIONS", "SAVE_3D_SCENES",
              "SHOW_3D_LIVE", "CAMERA_3DSCENE_FOLLOWS_ROBOT", "SAVE_DA_LOG"},
             "MRPT's per-step logs and 3D window; rove writes its outputs to -o");
  app.ignore({"ground_truth_data_association"},
             "rove checks the pairings against the landmark IDs or the ground-truth map instead");
  app.check_all_read();
  cfg.options = EkfSlamOptions::from_config(slam, kf, cfg.dim);
  slam.check_all_read();
  kf.check_all_read();
  return cfg;
}

}  // namespace rove
