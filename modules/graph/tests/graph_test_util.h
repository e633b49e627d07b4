#pragma once
// Shared helpers of the rove::graph tests.
#include <filesystem>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "rove/graph/pose_graph.h"
#include "rove/test_data.h"

namespace rove::test {

/// Path of a file of the shared pose-graph datasets (only for suites named
/// *Datasets, see rove/test_data.h); a missing file fails the test loudly.
inline std::string posegraph_dataset(const std::string& name) {
  return test_data::shared_dataset("posegraph/" + name);
}

/// Path of a small pose graph bundled in data/posegraph (circle50, w100).
inline std::string posegraph_bundled(const std::string& name) {
  return test_data::bundled_file("posegraph/" + name);
}

/// Path of a committed test file of rove::graph.
inline std::string graph_test_data(const std::string& name) {
  return std::string(ROVE_SOURCE_DIR) + "/modules/graph/tests/data/" + name;
}

/// Random 3D pose with translation in [-s, s]³.
inline SE3d random_se3(std::mt19937_64& rng, double s = 2.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix<double, 6, 1> xi;
  for (int k = 0; k < 6; ++k) xi(k) = u(rng) * (k < 3 ? s : 1.5);
  return SE3d::exp(xi);
}

/// Random 2D pose with translation in [-s, s]².
inline SE2d random_se2(std::mt19937_64& rng, double s = 2.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return SE2d::exp(Eigen::Vector3d(u(rng) * s, u(rng) * s, u(rng) * 3.0));
}

}  // namespace rove::test
