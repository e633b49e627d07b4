#include "rove/obs/motion_model_options.h"

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

TEST(MotionModelOptions, LoadsMrptKeysInDegrees) {
  const IniFile ini = IniFile::parse(R"(
[MotionModel]
modelSelection = mmThrun
a1 = 0.05          // m/m
a2 = 0.001         // m/deg
a3 = 5             // deg/m
a4 = 0.05
minStdXY = 0.02
minStdPHI = 0.5    // deg
nParticlesCount = 100
alfa1_rot_rot = 0.1
alfa2_rot_trans = 2.0
alfa3_trans_trans = 0.02
alfa4_trans_rot = 0.001
additional_std_XY = 0.005
additional_std_phi = 0.1
)");
  const MotionModelOptions o =
      MotionModelOptions::from_config(ConfigSection(ini, "MotionModel"));
  EXPECT_EQ(o.model, MotionModel::Thrun);
  EXPECT_DOUBLE_EQ(o.gaussian.a1_m_per_m, 0.05);
  EXPECT_DOUBLE_EQ(o.gaussian.a2_m_per_rad, 0.001 * 180.0 / kPi);
  EXPECT_DOUBLE_EQ(o.gaussian.a3_rad_per_m, 5.0 * kPi / 180.0);
  EXPECT_DOUBLE_EQ(o.gaussian.a4_rad_per_rad, 0.05);
  EXPECT_DOUBLE_EQ(o.gaussian.min_std_xy_m, 0.02);
  EXPECT_DOUBLE_EQ(o.gaussian.min_std_phi_rad, deg_to_rad(0.5));
  EXPECT_EQ(o.thrun.particle_count, 100u);
  EXPECT_DOUBLE_EQ(o.thrun.alpha1_rot_rot, 0.1);
  EXPECT_DOUBLE_EQ(o.thrun.alpha2_rot_trans_rad_per_m, deg_to_rad(2.0));
  EXPECT_DOUBLE_EQ(o.thrun.alpha3_trans_trans, 0.02);
  EXPECT_DOUBLE_EQ(o.thrun.alpha4_trans_rot_m_per_rad, 0.001 * 180.0 / kPi);
  EXPECT_DOUBLE_EQ(o.thrun.additional_std_xy_m, 0.005);
  EXPECT_DOUBLE_EQ(o.thrun.additional_std_phi_rad, deg_to_rad(0.1));
  EXPECT_TRUE(ini.unread_keys("MotionModel").empty());
}

TEST(MotionModelOptions, MissingKeysKeepDefaults) {
  // MRPT's pf-localization [DummyOdometryParams] section: two keys only.
  const IniFile ini = IniFile::parse(
      "[DummyOdometryParams]\nminStdXY = 0.10\nminStdPHI = 2.0\n");
  const MotionModelOptions o = MotionModelOptions::from_config(
      ConfigSection(ini, "DummyOdometryParams"));
  MotionModelOptions expected;
  expected.gaussian.min_std_xy_m = 0.10;
  expected.gaussian.min_std_phi_rad = 2.0 * kPi / 180.0;
  EXPECT_EQ(o, expected);
  EXPECT_EQ(
      MotionModelOptions::from_config(ConfigSection(ini, "NoSuchSection")),
      MotionModelOptions{});
}

TEST(MotionModelOptions, BadValuesNameTheKey) {
  const auto load = [](const char *text) {
    const IniFile ini = IniFile::parse(text, "motion.ini");
    return MotionModelOptions::from_config(ConfigSection(ini, "M"));
  };
  try {
    (void)load("[M]\na1 = -0.5\n");
    FAIL() << "negative a1 accepted";
  } catch (const ConfigError &e) {
    EXPECT_EQ(e.key(), "a1");
    EXPECT_EQ(e.file(), "motion.ini");
    EXPECT_EQ(e.section(), "M");
  }
  EXPECT_THROW((void)load("[M]\nmodelSelection = mmFancy\n"), ConfigError);
  EXPECT_THROW((void)load("[M]\nnParticlesCount = 0\n"), ConfigError);
  EXPECT_THROW((void)load("[M]\nminStdXY = abc\n"), ConfigError);
  EXPECT_THROW((void)load("[M]\na3 = inf\n"), ConfigError);
  EXPECT_EQ(load("[M]\nmodelSelection = 1\n").model, MotionModel::Thrun);
}

} // namespace
} // namespace rove
