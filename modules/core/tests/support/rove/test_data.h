#pragma once
// Where the tests of every module find their input files. Every module's test
// binary has this folder on its include path (cmake/RoveModule.cmake).
//
//   bundled_file("mrpt/x")        the project's data/ folder: small files with
//                                 their license notes, present in every clone;
//   mrpt_package_file("x")        MRPT's datasets from Debian's mrpt-common
//                                 (installed by scripts/install-deps);
//   shared_dataset("radish/x")    the large datasets, ROVE_DATASETS_DIR (by
//                                 default shared/datasets in the folder that
//                                 holds the project).
//
// Only a test whose suite name ends in "Datasets" may call shared_dataset():
// ctest labels those tests `datasets` and disables them when the folder is
// absent, unless ROVE_REQUIRE_DATASETS=1 (README, "Quick start").
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

namespace rove::test_data {

/// A file of the project's data/ folder, e.g. bundled_file("posegraph/w100.graph").
inline std::string bundled_file(std::string_view relative) {
  return std::string(ROVE_SOURCE_DIR) + "/data/" + std::string(relative);
}

/// A file of MRPT's datasets as installed by Debian's mrpt-common.
inline std::string mrpt_package_file(std::string_view name) {
  return "/usr/share/mrpt/datasets/" + std::string(name);
}

/// The folder of the large shared datasets, unchecked: the environment's
/// ROVE_DATASETS_DIR when set, else the one CMake was configured with.
inline std::string shared_datasets_dir() {
  if (const char* env = std::getenv("ROVE_DATASETS_DIR"); env != nullptr && *env != '\0') return env;
  return ROVE_DATASETS_DIR;
}

/// A file of the large shared datasets. A missing file fails the test (not a
/// skip): in a run without the folder these tests are disabled by ctest, so a
/// failure here means the folder is there but incomplete, or CI lacks it.
inline std::string shared_dataset(std::string_view relative) {
  const std::string path = shared_datasets_dir() + "/" + std::string(relative);
  EXPECT_TRUE(std::filesystem::exists(path))
      << "dataset missing: " << path
      << " (tests of a *Datasets suite need the shared datasets; `ctest -LE datasets` leaves them out)";
  return path;
}

}  // namespace rove::test_data
