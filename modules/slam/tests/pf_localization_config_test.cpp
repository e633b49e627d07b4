// Reading MRPT's pf-localization configuration files unchanged, and
// refusing bad ones with errors that name the key.

#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/ini.h"
#include "rove/maps/landmark_map.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/slam/pf_localization_config.h"
#include "rove/test_data.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string demo_config_text() {
  return read_input_file(test_data::bundled_file("mrpt/localization_demo.ini"), 1 << 20);
}

PfLocalizationConfig parse(const std::string& text, const std::string& name = "test.ini") {
  return load_pf_localization_config(IniFile::parse(text, name));
}

// Where the header line of [LocalizationExperiment] ends (a comment line
// also names the section).
std::size_t section_end(const std::string& t) {
  return t.find("\n[LocalizationExperiment]") + 25;
}

// Replaces the value of `key` in the demo config (the first line starting
// with it), or appends `key=value` to [LocalizationExperiment] if absent.
std::string demo_with(const std::string& key, const std::string& value) {
  std::string t = demo_config_text();
  const auto at = t.find("\n" + key + "=");
  if (at == std::string::npos) {
    return t.insert(section_end(t), "\n" + key + "=" + value);
  }
  const auto end = t.find('\n', at + 1);
  return t.replace(at + 1, end - at - 1, key + "=" + value);
}

std::string config_error_key(const std::string& text) {
  try {
    parse(text);
  } catch (const ConfigError& e) {
    return e.key();
  }
  return "(no error)";
}

TEST(PfLocalizationConfig, ReadsMrptDemoUnchanged) {
  const PfLocalizationConfig c = parse(demo_config_text());
  EXPECT_EQ(c.map_file, "../../datasets/localization_demo.simplemap.gz");
  EXPECT_EQ(c.rawlog_file, "../../datasets/localization_demo.rawlog");
  const MclOptions& o = c.options;
  EXPECT_EQ(o.init.count, 40000u);
  EXPECT_EQ(o.init.mode, ParticleInitMode::FreeSpaceInBox);
  EXPECT_EQ(o.init.min_x, -10.0);
  EXPECT_EQ(o.init.max_x, 10.0);
  EXPECT_EQ(o.init.min_y, -15.0);
  EXPECT_EQ(o.init.max_y, -5.0);
  EXPECT_NEAR(o.init.min_yaw, -std::numbers::pi, 1e-15);
  EXPECT_TRUE(o.pf.adaptive_sample_size);
  EXPECT_EQ(o.pf.algorithm, ParticleFilterAlgorithm::StandardProposal);
  EXPECT_EQ(o.pf.resampling_method, ResamplingMethod::Multinomial);
  EXPECT_EQ(o.pf.beta, 0.5);
  EXPECT_EQ(o.kld.bin_size_xy, 0.10);
  EXPECT_EQ(o.kld.max_sample_size, 40000u);
  EXPECT_EQ(o.kld.min_sample_size, 150u);
  // MRPT 2.5 reads KLD_binSize_PHI, not the file's KLD_binSize_PHI_deg:
  // the heading bin stays at MRPT's default, and the key is listed.
  EXPECT_NEAR(o.kld.bin_size_phi, 5 * kDeg, 1e-15);
  bool listed = false;
  for (const auto& k : c.ignored_keys) listed = listed || k.key == "KLD_binSize_PHI_deg";
  EXPECT_TRUE(listed);
  EXPECT_NEAR(o.dummy_odometry.min_std_xy_m, 0.10, 1e-15);
  EXPECT_NEAR(o.dummy_odometry.min_std_phi_rad, 2 * kDeg, 1e-15);
  EXPECT_FALSE(o.recovery.enabled());
  ASSERT_EQ(c.map.size(), 1u);
  const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(c.map.entries()[0].map.get());
  ASSERT_NE(g, nullptr);
  EXPECT_FLOAT_EQ(g->grid().resolution(), 0.06f);
  EXPECT_EQ(g->likelihood_options.method, GridLikelihoodMethod::LikelihoodFieldThrun);
  EXPECT_EQ(g->likelihood_options.lf_decimation, 20u);
  EXPECT_FLOAT_EQ(g->likelihood_options.lf_std_hit, 0.20f);
}

TEST(PfLocalizationConfig, ReadsMrptRangeOnlyDemoUnchanged) {
  const std::string path = "/usr/share/mrpt/config_files/pf-localization/ro-localization-demo.ini";
  const PfLocalizationConfig c = load_pf_localization_config(IniFile::load(path));
  EXPECT_TRUE(c.map_file.empty());
  EXPECT_EQ(c.options.init.mode, ParticleInitMode::UniformInBox);
  EXPECT_EQ(c.options.kld.max_sample_size, 5000u);
  ASSERT_EQ(c.map.size(), 1u);
  const auto* lm = dynamic_cast<const LandmarkMap*>(c.map.entries()[0].map.get());
  ASSERT_NE(lm, nullptr);
  EXPECT_EQ(lm->landmarks().size(), 15u);
  EXPECT_DOUBLE_EQ(lm->likelihood_options.beacon_ranges_std, 0.20);
  // Relative paths resolve beside the config, as MRPT's tree lays them out.
  EXPECT_EQ(c.resolve(c.rawlog_file, "rawlog_file"),
            "/usr/share/mrpt/config_files/pf-localization/../../datasets/RO-SLAM_demo.rawlog");
}

TEST(PfLocalizationConfig, RoveKeys) {
  std::string t = demo_with("recovery_alpha_slow", "0.001");
  t = t.insert(section_end(t),
               "\nrecovery_alpha_fast=0.1\ninit_PDF_mode_unused=1");
  EXPECT_EQ(config_error_key(t), "init_PDF_mode_unused");
  t = demo_with("recovery_alpha_slow", "0.001");
  t = t.insert(section_end(t),
               "\nrecovery_alpha_fast=0.1\nconverged_min_steps=5\ninit_PDF_std_yaw_deg=4");
  const PfLocalizationConfig c = parse(t);
  EXPECT_EQ(c.options.recovery.alpha_slow, 0.001);
  EXPECT_EQ(c.options.recovery.alpha_fast, 0.1);
  EXPECT_EQ(c.options.convergence.min_steps, 5u);
  EXPECT_NEAR(c.options.init.std_yaw, 4 * kDeg, 1e-15);
  EXPECT_EQ(parse(demo_with("init_PDF_mode", "2")).options.init.mode, ParticleInitMode::FreeSpace);
}

TEST(PfLocalizationConfig, BadValuesNameTheirKey) {
  EXPECT_EQ(config_error_key(demo_with("particles_count", "0")), "particles_count");
  EXPECT_EQ(config_error_key(demo_with("particles_count", "-5")), "particles_count");
  EXPECT_EQ(config_error_key(demo_with("particles_count", "100 200")), "particles_count");
  EXPECT_EQ(config_error_key(demo_with("particles_count", "many")), "particles_count");
  EXPECT_EQ(config_error_key(demo_with("init_PDF_mode", "7")), "init_PDF_mode");
  EXPECT_EQ(config_error_key(demo_with("init_PDF_max_x", "-20")), "init_PDF_max_x");
  std::string three_d = demo_config_text();
  three_d.replace(three_d.find("use_3D_poses = false"), 20, "use_3D_poses = true");
  EXPECT_EQ(config_error_key(three_d), "use_3D_poses");
  EXPECT_EQ(config_error_key(demo_with("partcles_count", "10")), "partcles_count");
  EXPECT_EQ(config_error_key(demo_with("recovery_alpha_slow", "0.5")), "recovery_alpha_fast");
  // A free-space start needs an occupancy grid.
  std::string no_grid = demo_config_text();
  no_grid.replace(no_grid.find("occupancyGrid_count=1"), 21, "occupancyGrid_count=0");
  EXPECT_EQ(config_error_key(no_grid), "init_PDF_mode");
  // An absurd particle count is refused before anything is allocated.
  EXPECT_THROW(parse(demo_with("particles_count", "4000000000")), ResourceError);
  // MRPT requires particles_count and init_PDF_mode.
  std::string t = demo_config_text();
  t.erase(t.find("particles_count=40000"), 21);
  EXPECT_EQ(config_error_key(t), "particles_count");
}

TEST(PfLocalizationConfig, MissingFilesAreNamed) {
  const PfLocalizationConfig c = parse(demo_config_text(), "/nonexistent/dir/x.ini");
  try {
    c.resolve(c.map_file, "map_file");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "map_file");
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos);
  }
}

}  // namespace
}  // namespace rove
