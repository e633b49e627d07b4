// Optimizer: ground truth, agreement between methods and thread counts,
// monotone χ², gauge, levels, robust kernels, and named failures.
#include <random>

#include <gtest/gtest.h>

#include "graph_test_util.h"
#include "rove/graph/evaluation.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/initialization.h"
#include "rove/graph/optimizer.h"

namespace rove {
namespace {

// A 3D loop-rich graph from ground-truth poses: odometry plus random loop
// closures, measurements exact (noise = 0) or perturbed.
PoseGraph3D synthetic_3d(std::mt19937_64& rng, int n, double noise, PoseGraph3D* truth = nullptr) {
  PoseGraph3D gt;
  SE3d pose;
  for (int v = 0; v < n; ++v) {
    gt.add_vertex(static_cast<VertexId>(v), pose);
    Eigen::Matrix<double, 6, 1> step;
    step << 1.0, 0.0, 0.05, 0.0, 0.02, 2 * M_PI / 20;
    pose = pose * SE3d::exp(step);
  }
  std::normal_distribution<double> nd(0.0, 1.0);
  PoseGraph3D g = gt;
  auto add = [&](int a, int b) {
    Eigen::Matrix<double, 6, 1> xi;
    for (int k = 0; k < 6; ++k) xi(k) = noise * nd(rng);
    const SE3d z = gt.pose(a).inverse() * gt.pose(b) * SE3d::exp(xi);
    Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Identity();
    info.bottomRightCorner<3, 3>() *= 40.0;
    g.add_edge(static_cast<VertexId>(a), static_cast<VertexId>(b), z, info);
  };
  for (int v = 0; v + 1 < n; ++v) add(v, v + 1);
  for (int v = 20; v < n; ++v) add(v - 20, v);  // one lap later: loop closures
  // Perturbed initial guess.
  for (int v = 1; v < n; ++v) {
    Eigen::Matrix<double, 6, 1> xi;
    for (int k = 0; k < 6; ++k) xi(k) = 0.1 * nd(rng);
    g.set_pose(static_cast<VertexId>(v), g.pose(static_cast<VertexId>(v)) * SE3d::exp(xi));
  }
  g.set_fixed(0);
  if (truth) *truth = gt;
  return g;
}

template <class Graph>
double max_position_error(const Graph& a, const Graph& b) {
  double m = 0.0;
  for (const auto& [id, v] : a.vertices())
    m = std::max(m, (v.pose.translation() - b.pose(id).translation()).norm());
  return m;
}

TEST(Optimizer, CircleReachesGroundTruth) {
  auto g = read_graph_2d(test::posegraph_bundled("graph_2d_circle_50nodes.graph"));
  const auto gt = read_graph_2d(test::posegraph_bundled("graph_2d_circle_50nodes_groundtruth.graph"));
  const double before = max_position_error(g, gt);
  const auto r = optimize(g);
  ASSERT_EQ(r.termination, GraphTermination::Converged) << r.message;
  EXPECT_EQ(r.gauge_anchor, VertexId{0});
  EXPECT_GT(before, 1.0);
  EXPECT_LT(max_position_error(g, gt), 0.05);
  EXPECT_LT(r.final_chi2, 0.01);
}

TEST(Optimizer, NoiselessSynthetic3DRecoversTruthWithEveryMethod) {
  for (auto solver : {GraphSolver::GaussNewton, GraphSolver::LevenbergMarquardt,
                      GraphSolver::DogLeg}) {
    for (auto ls : {LinearSolverType::Eigen, LinearSolverType::Block, LinearSolverType::Auto}) {
      std::mt19937_64 rng(1);
      PoseGraph3D truth;
      PoseGraph3D g = synthetic_3d(rng, 60, 0.0, &truth);
      GraphOptimizerOptions o;
      o.solver = solver;
      o.linear_solver = ls;
      const auto r = optimize(g, o);
      EXPECT_TRUE(r.ok()) << r.message;
      EXPECT_LT(r.final_chi2, 1e-16) << to_string(solver);
      EXPECT_LT(max_position_error(g, truth), 1e-8) << to_string(solver);
    }
  }
}

TEST(Optimizer, InitializationsAreExactOnNoiselessGraphs) {
  for (auto guess : {InitialGuess::Odometry, InitialGuess::SpanningTree, InitialGuess::Chordal}) {
    std::mt19937_64 rng(2);
    PoseGraph3D truth;
    PoseGraph3D g = synthetic_3d(rng, 60, 0.0, &truth);
    initialize(g, guess);
    EXPECT_LT(max_position_error(g, truth), 1e-9) << to_string(guess);
    EXPECT_LT(compute_chi2(g), 1e-15) << to_string(guess);
  }
}

TEST(Optimizer, ChordalBeatsOdometryOnNoisyGraph) {
  std::mt19937_64 rng(3);
  PoseGraph3D truth;
  PoseGraph3D g = synthetic_3d(rng, 100, 0.03, &truth);
  PoseGraph3D odo = g, chordal = g;
  initialize(odo, InitialGuess::Odometry);
  initialize(chordal, InitialGuess::Chordal);
  EXPECT_LT(compute_chi2(chordal), compute_chi2(odo));
  const auto r = optimize(chordal);
  EXPECT_TRUE(r.ok());
  EXPECT_LT(r.final_chi2, r.initial_chi2);
}

TEST(Optimizer, ThreadCountDoesNotChangeTheResult) {
  std::mt19937_64 rng(4);
  const PoseGraph3D g0 = synthetic_3d(rng, 150, 0.02);
  PoseGraph3D g1 = g0, g2 = g0;
  GraphOptimizerOptions o;
  o.num_threads = 1;
  const auto r1 = optimize(g1, o);
  o.num_threads = 2;
  const auto r2 = optimize(g2, o);
  EXPECT_EQ(r1.final_chi2, r2.final_chi2);
  EXPECT_EQ(r1.iterations, r2.iterations);
  for (const auto& [id, v] : g1.vertices()) {
    EXPECT_EQ(v.pose.translation(), g2.pose(id).translation());
  }
}

TEST(Optimizer, GaugeIsFixedByTheAnchor) {
  std::mt19937_64 rng(5);
  PoseGraph3D g = synthetic_3d(rng, 60, 0.02);
  const SE3d anchor = g.pose(0);
  optimize(g);
  EXPECT_EQ(g.pose(0).translation(), anchor.translation());
  EXPECT_EQ(g.pose(0).quaternion().coeffs(), anchor.quaternion().coeffs());
  // Without a fixed vertex the lowest id is held for the run.
  g.set_fixed(0, false);
  const SE3d v0 = g.pose(0);
  const auto r = optimize(g);
  EXPECT_EQ(r.gauge_anchor, VertexId{0});
  EXPECT_EQ(g.pose(0).translation(), v0.translation());
}

TEST(Optimizer, LevelsAndRemovalSelectEdges) {
  std::mt19937_64 rng(6);
  PoseGraph3D truth;
  PoseGraph3D g = synthetic_3d(rng, 60, 0.0, &truth);
  // A gross outlier at level 1 is ignored by a level-0 run.
  const std::size_t bad = g.add_edge(3, 50, SE3d::exp(Eigen::Matrix<double, 6, 1>::Constant(0.7)));
  g.set_edge_level(bad, 1);
  PoseGraph3D h = g;
  const auto r = optimize(h);
  EXPECT_EQ(r.num_edges_used, g.num_edges() - 1);
  EXPECT_LT(max_position_error(h, truth), 1e-8);
  g.remove_edge(bad);
  EXPECT_EQ(g.num_edges(), r.num_edges_used);
}

TEST(Optimizer, RobustKernelResistsOutliers) {
  std::mt19937_64 rng(7);
  PoseGraph3D truth;
  PoseGraph3D g = synthetic_3d(rng, 100, 0.01, &truth);
  for (int k = 0; k < 5; ++k) {
    g.add_edge(static_cast<VertexId>(10 + k * 15), static_cast<VertexId>(12 + k * 15),
               test::random_se3(rng, 5.0));
  }
  PoseGraph3D plain = g, robust = g;
  initialize(plain, InitialGuess::Odometry);
  initialize(robust, InitialGuess::Odometry);
  optimize(plain);
  GraphOptimizerOptions o;
  o.robust_kernel = RobustKernel(RobustKernelType::Cauchy, 1.0);
  const auto r = optimize(robust, o);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_LT(max_position_error(robust, truth), 0.5 * max_position_error(plain, truth));
  EXPECT_LT(max_position_error(robust, truth), 0.3);
}

TEST(Optimizer, DisconnectedVertexIsNamed) {
  PoseGraph2D g;
  for (VertexId v : {0, 1, 2, 7, 8}) g.add_vertex(v, SE2d());
  g.add_edge(0, 1, SE2d());
  g.add_edge(1, 2, SE2d());
  g.add_edge(7, 8, SE2d());
  g.set_fixed(0);
  const auto r = optimize(g);
  EXPECT_EQ(r.termination, GraphTermination::InvalidInput);
  ASSERT_EQ(r.issues.size(), 2u);
  EXPECT_EQ(r.issues[0].kind, GraphIssue::Kind::DisconnectedVertex);
  EXPECT_EQ(r.issues[0].vertex, 7u);
  EXPECT_NE(r.message.find("7, 8"), std::string::npos) << r.message;
}

TEST(Optimizer, NonFiniteResidualIsNamed) {
  PoseGraph2D g;
  g.add_vertex(0, SE2d(SO2d(), Eigen::Vector2d(1e308, 0)));
  g.add_vertex(1, SE2d(SO2d(), Eigen::Vector2d(1e308, 0)));
  g.add_vertex(2, SE2d(SO2d(), Eigen::Vector2d(-1e308, 0)));
  g.add_edge(0, 1, SE2d());
  g.add_edge(1, 2, SE2d());
  const auto r = optimize(g);
  EXPECT_EQ(r.termination, GraphTermination::NumericalFailure);
  ASSERT_FALSE(r.issues.empty());
  EXPECT_EQ(r.issues[0].edge, 1u);
  EXPECT_EQ(r.issues[0].kind, GraphIssue::Kind::NonFiniteResidual);
  EXPECT_NE(r.message.find("edge 1 (1 -> 2)"), std::string::npos) << r.message;
}

TEST(Optimizer, RankDeficientBlockIsNamed) {
  // Vertex 2's only edge is a gross outlier under Tukey: weight 0, so its
  // block is singular and Gauss-Newton must say which vertex.
  PoseGraph2D g;
  g.add_vertex(0, SE2d());
  g.add_vertex(1, SE2d(SO2d(), Eigen::Vector2d(1.5, 0)));
  g.add_vertex(2, SE2d(SO2d(), Eigen::Vector2d(100, 0)));
  g.add_edge(0, 1, SE2d(SO2d(), Eigen::Vector2d(1, 0)));
  g.add_edge(1, 2, SE2d(SO2d(), Eigen::Vector2d(1, 0)));
  g.set_fixed(0);
  GraphOptimizerOptions o;
  o.solver = GraphSolver::GaussNewton;
  o.robust_kernel = RobustKernel(RobustKernelType::Tukey, 1.0);
  const auto r = optimize(g, o);
  EXPECT_EQ(r.termination, GraphTermination::NumericalFailure);
  ASSERT_FALSE(r.issues.empty());
  EXPECT_EQ(r.issues[0].kind, GraphIssue::Kind::RankDeficientBlock);
  EXPECT_EQ(r.issues[0].vertex, 2u);
}

TEST(Optimizer, MethodsAgreeAndChiSquareNeverIncreases) {
  double chi2[3];
  int k = 0;
  for (auto solver : {GraphSolver::GaussNewton, GraphSolver::LevenbergMarquardt,
                      GraphSolver::DogLeg}) {
    // w100 from the odometry chain: far from the optimum, so steps get rejected.
    auto g = read_graph_2d(test::posegraph_bundled("w100.graph"));
    initialize(g, InitialGuess::Odometry);
    GraphOptimizerOptions o;
    o.solver = solver;
    o.function_tolerance = 1e-12;
    const auto r = optimize(g, o);
    ASSERT_EQ(r.termination, GraphTermination::Converged) << r.message;
    chi2[k++] = r.final_chi2;
    EXPECT_NEAR(r.final_chi2, compute_chi2(g), 1e-9 * r.final_chi2);
    if (solver == GraphSolver::GaussNewton) continue;
    double last = r.initial_chi2;
    for (const auto& it : r.history) {
      if (!it.accepted) continue;
      EXPECT_LT(it.chi2, last) << to_string(solver) << " iteration " << it.iteration;
      last = it.chi2;
    }
    EXPECT_DOUBLE_EQ(last, r.final_chi2);
  }
  EXPECT_NEAR(chi2[0], chi2[1], 1e-8 * chi2[1]);
  EXPECT_NEAR(chi2[2], chi2[1], 1e-8 * chi2[1]);
}

}  // namespace
}  // namespace rove

namespace rove {
namespace {

TEST(Evaluation, AlignmentRemovesARigidMotion) {
  std::mt19937_64 rng(11);
  PoseGraph3D truth, moved;
  const SE3d T = test::random_se3(rng, 10.0);
  for (VertexId v = 0; v < 20; ++v) {
    const SE3d p = test::random_se3(rng);
    truth.add_vertex(v, p);
    moved.add_vertex(v, T * p);
  }
  const auto e = aligned_position_error(moved, truth);
  EXPECT_EQ(e.matched, 20u);
  EXPECT_LT(e.rmse, 1e-12);
  // One vertex off by 1 m along x: RMSE is bounded by the displacement.
  moved.set_pose(5, moved.pose(5) * SE3d(SO3d(), Eigen::Vector3d(1, 0, 0)));
  const auto f = aligned_position_error(moved, truth);
  EXPECT_GT(f.rmse, 0.1);
  EXPECT_LT(f.rmse, 1.0 / std::sqrt(20.0) + 1e-9);
}

}  // namespace
}  // namespace rove
