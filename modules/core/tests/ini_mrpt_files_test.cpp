// rove::IniFile on every config file MRPT ships (Debian package mrpt-common,
// /usr/share/mrpt/config_files). The folder is required: these tests fail,
// not skip, without it. Expected values were read from the files and
// cross-checked against MRPT 2.5.8's own CConfigFile::read_string.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "rove/core/error.h"
#include "rove/core/ini.h"

namespace {

namespace fs = std::filesystem;
using rove::IniFile;

const fs::path kDir = "/usr/share/mrpt/config_files";

// The one shipped file with a line MRPT silently skips: line 8 of it is the
// wrapped tail of the previous line's comment ("random seed").
const char* const kFileWithStrayLine = "simul-landmarks/simul_landmarks_demo_EKF-SLAM.ini";

std::vector<fs::path> mrpt_ini_files() {
  std::vector<fs::path> files;
  if (!fs::is_directory(kDir)) return files;
  for (const auto& e : fs::recursive_directory_iterator(kDir)) {
    if (e.is_regular_file() && e.path().extension() == ".ini") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

IniFile load(const std::string& relative) { return IniFile::load((kDir / relative).string()); }

TEST(IniMrptFiles, FolderIsInstalled) {
  ASSERT_TRUE(fs::is_directory(kDir))
      << kDir << " is missing: install the Debian package mrpt-common";
  EXPECT_GE(mrpt_ini_files().size(), 90u);
}

TEST(IniMrptFiles, EveryFileLoads) {
  const auto files = mrpt_ini_files();
  ASSERT_GE(files.size(), 90u) << "MRPT config files not found in " << kDir;
  std::vector<std::string> strict_failures;
  std::size_t keys = 0;
  for (const auto& f : files) {
    const std::string rel = fs::relative(f, kDir).string();
    try {
      const auto ini = IniFile::load(f.string());
      for (const auto& s : ini.sections()) keys += ini.keys(s).size();
    } catch (const rove::ParseError& e) {
      strict_failures.push_back(rel);
      EXPECT_EQ(rel, kFileWithStrayLine) << e.what();
    }
    // Non-strict (MRPT's own behaviour) loads every file.
    rove::IniOptions lenient;
    lenient.strict = false;
    EXPECT_NO_THROW(IniFile::load(f.string(), lenient)) << rel;
  }
  EXPECT_EQ(strict_failures, std::vector<std::string>{kFileWithStrayLine});
  EXPECT_GT(keys, 3000u);
}

TEST(IniMrptFiles, StrayLineIsReportedStrictAndSkippedLeniently) {
  const std::string path = (kDir / kFileWithStrayLine).string();
  try {
    IniFile::load(path);
    FAIL() << "expected a ParseError";
  } catch (const rove::ParseError& e) {
    EXPECT_EQ(e.location().source, path);
    EXPECT_EQ(e.location().line, 8u);
  }
  rove::IniOptions lenient;
  lenient.strict = false;
  const auto ini = IniFile::load(path, lenient);
  ASSERT_EQ(ini.skipped_lines().size(), 1u);
  EXPECT_EQ(ini.skipped_lines()[0].line, 8u);
  EXPECT_EQ(ini.skipped_lines()[0].text, "random seed");
  EXPECT_EQ(ini.get<int>("Params", "random_seed"), 123);
  EXPECT_EQ(ini.get<int>("Params", "nSteps"), 250);
}

TEST(IniMrptFiles, IcpSlamDemoClassic) {
  const auto ini = load("icp-slam/icp-slam_demo_classic.ini");
  EXPECT_EQ(ini.get<int>("ICP", "maxIterations"), 80);
  EXPECT_DOUBLE_EQ(ini.get<double>("ICP", "minAbsStep_trans"), 1e-6);
  EXPECT_DOUBLE_EQ(ini.get<double>("ICP", "thresholdDist"), 0.3);
  EXPECT_DOUBLE_EQ(ini.get<double>("ICP", "ALFA"), 0.8);
  EXPECT_DOUBLE_EQ(ini.get<double>("ICP", "smallestThresholdDist"), 0.05);
  EXPECT_TRUE(ini.get<bool>("ICP", "onlyClosestCorrespondences"));
  EXPECT_EQ(ini.get<std::string>("ICP", "ICP_algorithm"), "icpClassic");
  EXPECT_EQ(ini.get<unsigned>("ICP", "corresponding_points_decimation"), 5u);
  EXPECT_EQ(ini.get<std::string>("MappingApplication", "rawlog_file"),
            "../../datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog");
  EXPECT_EQ(ini.get<int>("MappingApplication", "rawlog_offset"), 0);
  EXPECT_EQ(ini.get<std::string>("MappingApplication", "logOutput_dir"), "LOG_ICP-SLAM");
  EXPECT_EQ(ini.get<int>("MappingApplication", "LOG_FREQUENCY"), 50);
  EXPECT_FALSE(ini.get<bool>("MappingApplication", "SAVE_POSE_LOG"));
  EXPECT_TRUE(ini.get<bool>("MappingApplication", "SHOW_LASER_SCANS_3D"));
  EXPECT_DOUBLE_EQ(ini.get<double>("MappingApplication", "localizationLinDistance"), 0.2);
  EXPECT_DOUBLE_EQ(ini.get<double>("MappingApplication", "insertionAngDistance"), 45.0);
  EXPECT_DOUBLE_EQ(ini.get<double>("MappingApplication", "minICPgoodnessToAccept"), 0.40);
  // Case-insensitive as in MRPT.
  EXPECT_EQ(ini.get<int>("icp", "MAXITERATIONS"), 80);
}

TEST(IniMrptFiles, ReactiveNavDefinesCommentsAndContinuations) {
  const auto ini = load("navigation-ptgs/reactive2d_config.ini");
  // @define + ${} (MRPT reads "1.0", "60.0", "10.0").
  EXPECT_EQ(ini.raw("CAbstractPTGBasedReactive", "robotMax_V_mps"), "1.0");
  EXPECT_DOUBLE_EQ(ini.get<double>("CAbstractPTGBasedReactive", "robotMax_V_mps"), 1.0);
  EXPECT_DOUBLE_EQ(ini.get<double>("CAbstractPTGBasedReactive", "robotMax_W_degps"), 60.0);
  EXPECT_DOUBLE_EQ(ini.get<double>("CAbstractPTGBasedReactive", "ref_distance"), 10.0);
  // Trailing '#' comment: MRPT's read_string keeps it, its atof reads 10.0.
  EXPECT_EQ(ini.raw("CReactiveNavigationSystem", "PTG0_refDistance"),
            "10.0 # Maximum distance to build PTGs (in meters), i.e. the visibility \"range\" of "
            "tentative paths");
  EXPECT_DOUBLE_EQ(ini.get<double>("CReactiveNavigationSystem", "PTG0_refDistance"), 10.0);
  EXPECT_DOUBLE_EQ(ini.get<double>("CReactiveNavigationSystem", "PTG0_resolution"), 0.05);
  // Backslash continuations, joined exactly as MRPT joins them.
  EXPECT_EQ(ini.get<std::string>("CMultiObjectiveMotionOptimizerBase", "score1_formula"),
            "var effective_trg_d_norm := max(0,target_d_norm-move_cur_d); \tif(collision_free_"
            "distance>effective_trg_d_norm, \t\t1/(1+effective_trg_d_norm^2), \t\t0)");
  // Ends with ';' (an exprtk statement): get<> drops it, raw() keeps it.
  EXPECT_EQ(ini.raw("CMultiObjectiveMotionOptimizerBase", "score5_formula"),
            "var dif:=abs(target_k-move_k); \tif (dif>(num_paths/2)) \t{ \t\tdif:=num_paths-dif; "
            "\t}; \texp(-abs(dif / (num_paths/10.0)));");
  EXPECT_EQ(ini.get<std::string>("CMultiObjectiveMotionOptimizerBase", "scores_to_normalize"), "");
}

TEST(IniMrptFiles, ValuesMrptReadsWithAtof) {
  // "1\t\t;number of gridmaps to generate": MRPT's atoi reads 1.
  EXPECT_EQ(load("icp-slam/icp-gas-mapping.ini").get<int>("MappingApplication", "gasGrid_count"), 1);
  // "3;": a C-style terminator, MRPT's atof reads 3.
  EXPECT_DOUBLE_EQ(
      load("graphslam-engine/laser_odometry.ini").get<double>("OptimizerParameters", "optimization_distance"),
      3.0);
  // "0.2// position on the robot (meters)": no space before "//".
  const auto cams = load("rawlog-grabber/two_cameras_1394.ini");
  EXPECT_DOUBLE_EQ(cams.get<double>("XCamera1394_2", "pose_x"), 0.2);
  EXPECT_EQ(cams.get<std::uint64_t>("XCamera1394_1", "dc1394_camera_guid"), 0x000a47010b083041ULL);
  EXPECT_EQ(load("graphslam-engine/odometry_2DRangeScans.ini")
                .get<unsigned>("VisualizationParameters", "laser_scans_color"),
            0x00BFFFu);
  // A typo in MRPT's file: a literal "\n" after the value. MRPT's atoi reads
  // 1; rove refuses to guess.
  const auto r3d = load("navigation-ptgs/reactive3d_config.ini");
  EXPECT_EQ(r3d.raw("STM_CONFIG", "Stm_active"), "1 \\n\t\t\t; Utilize it(1) or not(0)");
  EXPECT_THROW(r3d.get<int>("STM_CONFIG", "Stm_active"), rove::ConfigError);
}

TEST(IniMrptFiles, VectorsAndMatrices) {
  const auto shape = load("navigation-ptgs/ptrrt_config_example1.ini").get_matrix<double>("PTG_CONFIG", "robot_shape");
  EXPECT_EQ(shape, (std::vector<std::vector<double>>{{-0.2, 0.2, 0.2, -0.2}, {-0.1, -0.1, 0.1, 0.1}}));
  const auto r3d = load("navigation-ptgs/reactive3d_config.ini");
  EXPECT_EQ(r3d.get_vector<double>("LASER_CONFIG", "LASER2_POSE"),
            (std::vector<double>{0, 0, 1.1, 0, 0, 0}));
  EXPECT_EQ(r3d.get_vector<double>("CReactiveNavigationSystem3D", "LEVEL3_VECTORX"),
            (std::vector<double>{0.30, -0.15, -0.15}));
}

}  // namespace
