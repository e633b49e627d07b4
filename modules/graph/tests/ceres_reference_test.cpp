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

// Both trust-region methods (dog-leg is the default) reach Ceres' χ².
void expect_matches_ceres(const std::string& file) {
  const Reference ref = reference_for(file);
  const bool bundled = file == "graph_2d_circle_50nodes.graph" || file == "w100.graph";
  const auto loaded = read_graph_2d(bundled ? test::posegraph_bundled(file) : test::posegraph_dataset(file));
  for (auto solver : {GraphSolver::DogLeg, GraphSolver::LevenbergMarquardt}) {
    auto g = loaded;
    initialize(g, parse_initial_guess(ref.init));
    GraphOptimizerOptions o;
    o.solver = solver;
    const auto r = optimize(g, o);
    ASSERT_TRUE(r.ok()) << to_string(solver) << ": " << r.message;
    EXPECT_NEAR(r.initial_chi2, ref.chi2_initial, 1e-9 * ref.chi2_initial) << file;
    EXPECT_NEAR(r.final_chi2, ref.chi2_final, 1e-6 * ref.chi2_final) << file << " "
                                                                     << to_string(solver);
    EXPECT_EQ(r.termination, GraphTermination::Converged) << file << " " << to_string(solver);
    EXPECT_GE(r.factorizations, 1);
    if (solver == GraphSolver::LevenbergMarquardt) {
      EXPECT_EQ(r.factorizations, r.iterations);  // LM: one per trial step
    } else {
      EXPECT_LE(r.factorizations, r.accepted_steps + 1);  // dog-leg: one per accepted step
    }
  }
}

TEST(CeresReference, Circle50) { expect_matches_ceres("graph_2d_circle_50nodes.graph"); }
TEST(CeresReference, W100) { expect_matches_ceres("w100.graph"); }
TEST(CeresReferenceDatasets, Intel) { expect_matches_ceres("intel.g2o"); }
TEST(CeresReferenceDatasets, IntelCarloneChordal) { expect_matches_ceres("intel_carlone.g2o"); }
TEST(CeresReferenceDatasets, M3500) { expect_matches_ceres("M3500.g2o"); }

// 3D: dog-leg reaches Ceres' χ². On these dense factors (≥ 100 flops per
// factor entry) the last steps are solved by CG on the previous
// factorization; that must not move the optimum: the same χ² as when every
// step is factorized, to rounding, and as Gauss–Newton, which reuses too.
void expect_3d_matches_ceres(const std::string& file) {
  const Reference ref = reference_for(file);
  auto loaded = read_graph_3d(test::posegraph_dataset(file));
  initialize(loaded, parse_initial_guess(ref.init));
  GraphOptimizerOptions o;
  auto g = loaded;
  const auto reused = optimize(g, o);
  ASSERT_TRUE(reused.ok()) << reused.message;
  EXPECT_NEAR(reused.initial_chi2, ref.chi2_initial, 1e-9 * ref.chi2_initial) << file;
  EXPECT_NEAR(reused.final_chi2, ref.chi2_final, 1e-6 * ref.chi2_final) << file;
  EXPECT_EQ(reused.termination, GraphTermination::Converged) << file;
  EXPECT_GE(reused.reused_factorizations, 1) << file;
  EXPECT_EQ(reused.factorizations + reused.reused_factorizations, reused.accepted_steps) << file;

  o.reuse_factorization = false;
  g = loaded;
  const auto fresh = optimize(g, o);
  ASSERT_TRUE(fresh.ok()) << fresh.message;
  EXPECT_EQ(fresh.reused_factorizations, 0);
  EXPECT_EQ(fresh.cg_iterations, 0);
  EXPECT_NEAR(reused.final_chi2, fresh.final_chi2, 1e-9 * fresh.final_chi2) << file;
  EXPECT_LT(reused.factorizations, fresh.factorizations) << file;

  o.reuse_factorization = true;
  o.solver = GraphSolver::GaussNewton;
  g = loaded;
  const auto gn = optimize(g, o);
  ASSERT_TRUE(gn.ok()) << gn.message;
  EXPECT_GE(gn.reused_factorizations, 1) << file;
  EXPECT_NEAR(gn.final_chi2, ref.chi2_final, 1e-6 * ref.chi2_final) << file;
}

TEST(CeresReferenceDatasets, Sphere2500) { expect_3d_matches_ceres("sphere2500.txt"); }
TEST(CeresReferenceDatasets, Torus3DSpanningTree) { expect_3d_matches_ceres("torus3D.g2o"); }

// 2D factors are too sparse for the reuse to pay: every step is factorized.
TEST(CeresReferenceDatasets, NoFactorizationReuseIn2D) {
  auto g = read_graph_2d(test::posegraph_dataset("M3500.g2o"));
  const auto r = optimize(g);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.reused_factorizations, 0);
  EXPECT_EQ(r.cg_iterations, 0);
}

// Dog-leg reuses its factorization when a step is rejected: on intel_carlone
// from the chordal guess LM needs ~60 factorizations, the dog-leg ~5.
TEST(CeresReferenceDatasets, DogLegFactorizesLessThanLm) {
  const Reference ref = reference_for("intel_carlone.g2o");
  auto lm_graph = read_graph_2d(test::posegraph_dataset("intel_carlone.g2o"));
  initialize(lm_graph, parse_initial_guess(ref.init));
  auto dl_graph = lm_graph;
  GraphOptimizerOptions o;
  o.solver = GraphSolver::LevenbergMarquardt;
  const auto lm = optimize(lm_graph, o);
  o.solver = GraphSolver::DogLeg;
  const auto dl = optimize(dl_graph, o);
  ASSERT_TRUE(lm.ok() && dl.ok());
  EXPECT_LT(dl.factorizations * 4, lm.factorizations);
  EXPECT_NEAR(dl.final_chi2, lm.final_chi2, 1e-9 * lm.final_chi2);
}

}  // namespace
}  // namespace rove
