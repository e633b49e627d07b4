// TORO / g2o / binary reading and writing, and the errors bad files give.
#include <cstdio>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "graph_test_util.h"
#include "rove/core/error.h"
#include "rove/graph/graph_io.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/memory_stream.h"

namespace rove {
namespace {

// Expects parse to throw ParseError at `line` whose message contains `needle`.
template <class F>
void expect_parse_error(F&& parse, std::size_t line, const std::string& needle) {
  try {
    parse();
    ADD_FAILURE() << "no error, expected one on line " << line << " about '" << needle << "'";
  } catch (const ParseError& e) {
    ASSERT_TRUE(e.location().line.has_value()) << e.what();
    EXPECT_EQ(*e.location().line, line) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.graph"), std::string::npos) << e.what();
  }
}

TEST(GraphIo, Toro2DInformationOrder) {
  // TORO: inf_xx inf_xy inf_yy inf_tt inf_xt inf_yt; g2o: xx xy xt yy yt tt.
  const auto g = parse_graph_2d(
      "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
      "EDGE2 0 1 1 0 0 10 1 20 30 2 3\n"
      "EDGE_SE2 1 2 1 0 0 10 1 2 20 3 30\n",
      "test.graph");
  ASSERT_EQ(g.num_edges(), 2u);
  Eigen::Matrix3d expected;
  expected << 10, 1, 2, 1, 20, 3, 2, 3, 30;
  EXPECT_EQ(g.edges()[0].information, expected);
  EXPECT_EQ(g.edges()[1].information, expected);
}

TEST(GraphIo, EquivMergesAndDropsSelfLoops) {
  const auto g = parse_graph_2d(
      "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nVERTEX2 2 2 0 0\nVERTEX2 5 0.1 0 0\n"
      "EDGE2 0 1 1 0 0 1 0 1 1 0 0\nEDGE2 1 2 1 0 0 1 0 1 1 0 0\n"
      "EDGE2 2 5 -2 0 0 1 0 1 1 0 0\nEDGE2 0 5 0 0 0 1 0 1 1 0 0\n"
      "EQUIV 5 0\nFIX 5\n",
      "test.graph");
  EXPECT_EQ(g.num_vertices(), 3u);
  EXPECT_FALSE(g.has_vertex(5));
  EXPECT_EQ(g.num_edges(), 3u);  // 0-5 became a self loop
  EXPECT_EQ(g.edges()[2].from, 2u);
  EXPECT_EQ(g.edges()[2].to, 0u);
  EXPECT_TRUE(g.is_fixed(0));
  EXPECT_EQ(g.pose(0).translation().x(), 0.0);  // the kept vertex keeps its pose
}

TEST(GraphIo, EdgesOnlyFileUsesOdometryChain) {
  const auto g = parse_graph_2d(
      "EDGE2 0 1 1 0 1.5707963267948966 1 0 1 1 0 0\n"
      "EDGE2 1 2 1 0 0 1 0 1 1 0 0\n"
      "EDGE2 2 0 5 5 0 1 0 1 1 0 0\n",
      "test.graph");
  ASSERT_EQ(g.num_vertices(), 3u);
  EXPECT_NEAR(g.pose(1).translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(g.pose(2).translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(g.pose(2).translation().y(), 1.0, 1e-12);
}

TEST(GraphIo, Toro3DEulerAndInformationScaling) {
  const auto g = parse_graph_3d(
      "VERTEX3 0 0 0 0 0 0 0\nVERTEX3 1 1 2 3 0.1 0.2 0.3\n"
      "EDGE3 0 1 1 2 3 0.1 0.2 0.3 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 25\n",
      "test.graph");
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  EXPECT_LT((g.pose(1).rotation_matrix() - R).cwiseAbs().maxCoeff(), 1e-15);
  const auto& I = g.edges()[0].information;
  EXPECT_EQ(I(0, 0), 10.0);
  EXPECT_EQ(I(3, 3), 400.0);  // angle information ×4 on q.xyz ≈ ω/2
  EXPECT_EQ(I(5, 5), 100.0);
  // Writing back gives the file's numbers.
  const auto again = parse_graph_3d(format_graph(g, GraphFileFormat::Toro), "test.graph");
  EXPECT_LT((again.edges()[0].information - I).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_TRUE(again.pose(1).is_approx(g.pose(1), 1e-12));
}

template <class Graph>
void expect_same(const Graph& a, const Graph& b, double tol) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  ASSERT_EQ(a.num_edges(), b.num_edges());
  for (const auto& [id, v] : a.vertices()) {
    ASSERT_TRUE(b.has_vertex(id));
    EXPECT_TRUE(v.pose.is_approx(b.pose(id), tol)) << "vertex " << id;
    EXPECT_EQ(v.fixed, b.is_fixed(id));
  }
  for (std::size_t k = 0; k < a.num_edges(); ++k) {
    EXPECT_EQ(a.edges()[k].from, b.edges()[k].from);
    EXPECT_EQ(a.edges()[k].to, b.edges()[k].to);
    EXPECT_TRUE(a.edges()[k].measurement.is_approx(b.edges()[k].measurement, tol));
    EXPECT_LE((a.edges()[k].information - b.edges()[k].information).cwiseAbs().maxCoeff(),
              tol * (1 + a.edges()[k].information.cwiseAbs().maxCoeff()));
  }
}

PoseGraph3D random_graph_3d(std::mt19937_64& rng, int n) {
  PoseGraph3D g;
  for (int v = 0; v < n; ++v) g.add_vertex(static_cast<VertexId>(v * 3), test::random_se3(rng));
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int k = 0; k < 2 * n; ++k) {
    const int a = k < n - 1 ? k : pick(rng), b = k < n - 1 ? k + 1 : pick(rng);
    if (a == b) continue;
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Random();
    g.add_edge(static_cast<VertexId>(a * 3), static_cast<VertexId>(b * 3), test::random_se3(rng),
               A * A.transpose() + Eigen::Matrix<double, 6, 6>::Identity());
  }
  g.set_fixed(0);
  return g;
}

TEST(GraphIo, TextRoundTrip3D) {
  std::mt19937_64 rng(7);
  const PoseGraph3D g = random_graph_3d(rng, 20);
  expect_same(g, parse_graph_3d(format_graph(g, GraphFileFormat::G2o), "test.graph"), 1e-12);
  expect_same(g, parse_graph_3d(format_graph(g, GraphFileFormat::Toro), "test.graph"), 1e-9);
}

TEST(GraphIo, TextRoundTrip2D) {
  std::mt19937_64 rng(8);
  PoseGraph2D g;
  for (int v = 0; v < 10; ++v) g.add_vertex(static_cast<VertexId>(v), test::random_se2(rng));
  for (int v = 0; v + 1 < 10; ++v) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Random();
    g.add_edge(static_cast<VertexId>(v), static_cast<VertexId>(v + 1), test::random_se2(rng),
               A * A.transpose() + Eigen::Matrix3d::Identity());
  }
  g.set_fixed(3);
  for (auto f : {GraphFileFormat::G2o, GraphFileFormat::Toro}) {
    expect_same(g, parse_graph_2d(format_graph(g, f), "test.graph"), 1e-14);
  }
}

TEST(GraphIo, BinaryRoundTripKeepsLevelsAndKernels) {
  std::mt19937_64 rng(9);
  PoseGraph3D g = random_graph_3d(rng, 12);
  g.set_edge_level(3, 2);
  g.set_edge_kernel(4, RobustKernel(RobustKernelType::Cauchy, 1.5));
  const std::string path =
      (std::filesystem::temp_directory_path() / "rove_graph_io_test.rpg").string();
  write_graph(g, path);
  EXPECT_EQ(detect_graph_dimension(path), GraphDimension::ThreeD);
  const PoseGraph3D back = read_graph_3d(path);
  std::filesystem::remove(path);
  expect_same(g, back, 1e-15);
  EXPECT_EQ(back.edges()[3].level, 2);
  EXPECT_EQ(back.edges()[4].kernel, RobustKernel(RobustKernelType::Cauchy, 1.5));
  // Asking for the wrong dimension is an error naming the field.
  MemoryOutStream out;
  OutArchive ar(out);
  save(ar, g);
  MemoryInStream in(std::span<const std::byte>(out.data()), "graph.rpg");
  InArchive iar(in);
  PoseGraph2D wrong;
  EXPECT_THROW(load(iar, wrong), ParseError);
}

TEST(GraphIo, TruncatedBinaryNamesOffset) {
  std::mt19937_64 rng(10);
  const PoseGraph3D g = random_graph_3d(rng, 5);
  MemoryOutStream out;
  OutArchive ar(out);
  save(ar, g);
  auto bytes = out.data();
  for (std::size_t cut : {std::size_t{3}, std::size_t{20}, bytes.size() / 2, bytes.size() - 1}) {
    std::vector<std::byte> part(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    MemoryInStream in(std::move(part), "cut.rpg");
    InArchive iar(in);
    PoseGraph3D back;
    EXPECT_THROW(load(iar, back), ParseError) << "cut at " << cut;
  }
}

TEST(GraphIo, ErrorsNameFileLineAndField) {
  const std::string v = "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\n";
  auto p2 = [](std::string text) { return [text] { parse_graph_2d(text, "test.graph"); }; };
  auto p3 = [](std::string text) { return [text] { parse_graph_3d(text, "test.graph"); }; };
  expect_parse_error(p2(v + "EDGE2 0 1 1 0 0 1 0 abc 1 0 0\n"), 3, "inf_yy");
  expect_parse_error(p2(v + "EDGE2 0 1 1 0 0 1 0 1 1 0\n"), 3, "inf_yt");
  expect_parse_error(p2(v + "EDGE2 0 1 1 0 nan 1 0 1 1 0 0\n"), 3, "not finite");
  expect_parse_error(p2(v + "LANDMARK 0 1 2\n"), 3, "unknown record tag");
  expect_parse_error(p2(v + "EDGE2 0 7 1 0 0 1 0 1 1 0 0\n"), 3, "vertex 7");
  expect_parse_error(p2(v + "EDGE2 0 1 1 0 0 1 0 1 -1 0 0\n"), 3, "positive definite");
  expect_parse_error(p2(v + "EDGE2 0 1 1 0 0 1 2 1 1 0 0\n"), 3, "positive definite");
  expect_parse_error(p2(v + "EDGE2 1 1 1 0 0 1 0 1 1 0 0\n"), 3, "self loop");
  expect_parse_error(p2(v + "VERTEX2 1 1 0 0\n"), 3, "defined twice");
  expect_parse_error(p2(v + "VERTEX3 2 0 0 0 0 0 0\n"), 3, "3D record");
  expect_parse_error(p2(v + "VERTEX2 -2 0 0 0\n"), 3, "vertex id");
  expect_parse_error(p2(v + "VERTEX2 2 0 0 0 7\n"), 3, "extra field");
  expect_parse_error(p2(v + "FIX 9\n"), 3, "vertex 9");
  expect_parse_error(p3("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 0\n"), 1, "quaternion");
  expect_parse_error(p3("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n"
                        "EDGE_SE3:QUAT 0 1 0 0 0 0 0 0 1 1 0 0\n"),
                     3, "inf_14");
  expect_parse_error(p3("VERTEX2 0 0 0 0\n"), 1, "2D record");
}

TEST(GraphIoDatasets, ReadsEveryDataset) {
  const auto circle = read_graph_2d(test::posegraph_dataset("graph_2d_circle_50nodes.graph"));
  EXPECT_EQ(circle.num_vertices(), 50u);
  EXPECT_EQ(circle.num_edges(), 101u);
  const auto intel = read_graph_2d(test::posegraph_dataset("intel.g2o"));
  EXPECT_EQ(intel.num_vertices(), 1728u);
  EXPECT_EQ(intel.num_edges(), 2512u);
  const auto w100 = read_graph_2d(test::posegraph_dataset("w100.graph"));
  EXPECT_GT(w100.num_edges(), 0u);
  EXPECT_EQ(detect_graph_dimension(test::posegraph_dataset("sphere2500.txt")),
            GraphDimension::ThreeD);
  EXPECT_EQ(detect_graph_dimension(test::posegraph_dataset("M3500.g2o")), GraphDimension::TwoD);
}

}  // namespace
}  // namespace rove
