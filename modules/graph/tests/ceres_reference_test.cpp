// Final χ² against the Ceres 2.1 reference optimizer (tools/ceres_graph_reference,
// same cost, same initial guess; values frozen in tests/data/ceres_reference.txt).
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "graph_test_util.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/initialization.h"
#include "rove/graph/optimizer.h"

namespace rove {
namespace {

struct Reference {
  std::string file, init;
  double chi2_initial = 0, chi2_final = 0;
};

Reference reference_for(const std::string& file) {
  std::ifstream in(test::graph_test_data("ceres_reference.txt"));
  EXPECT_TRUE(in.good()) << "missing tests/data/ceres_reference.txt";
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Reference r;
    s >> r.file >> r.init >> r.chi2_initial >> r.chi2_final;
    if (r.file == file) return r;
  }
  ADD_FAILURE() << "no Ceres reference for " << file;
  return {};
}

void expect_matches_ceres(const std::string& file) {
  const Reference ref = reference_for(file);
  auto g = read_graph_2d(test::posegraph_dataset(file));
  initialize(g, parse_initial_guess(ref.init));
  const auto r = optimize(g);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_NEAR(r.initial_chi2, ref.chi2_initial, 1e-9 * ref.chi2_initial) << file;
  EXPECT_NEAR(r.final_chi2, ref.chi2_final, 1e-6 * ref.chi2_final) << file;
}

TEST(CeresReference, Circle50) { expect_matches_ceres("graph_2d_circle_50nodes.graph"); }
TEST(CeresReference, W100) { expect_matches_ceres("w100.graph"); }
TEST(CeresReference, Intel) { expect_matches_ceres("intel.g2o"); }
TEST(CeresReference, M3500) { expect_matches_ceres("M3500.g2o"); }

}  // namespace
}  // namespace rove
