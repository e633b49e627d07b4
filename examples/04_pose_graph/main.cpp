// 04_pose_graph: optimize a 2D pose graph with rove::graph. MRPT's circle of
// 50 poses (noisy odometry and loop closures) is read, optimized with the
// default solver (dog-leg), and compared with its ground truth after the
// best rigid alignment. Exits non-zero unless the optimizer converged, χ²
// fell below 0.01 and every position is within 5 cm of the truth.
#include <cstdio>
#include <string>

#include "rove/graph/evaluation.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/optimizer.h"

int main(int argc, char** argv) {
  const std::string path = argc > 2 ? argv[1] : ROVE_EXAMPLE_GRAPH;
  const std::string truth_path = argc > 2 ? argv[2] : ROVE_EXAMPLE_TRUTH;
  rove::PoseGraph2D graph = rove::read_graph_2d(path);
  const rove::PoseGraph2D truth = rove::read_graph_2d(truth_path);

  const rove::AlignedPositionError before = rove::aligned_position_error(graph, truth);
  const rove::GraphOptimizerResult r = rove::optimize(graph);  // in place
  const rove::AlignedPositionError after = rove::aligned_position_error(graph, truth);

  std::printf("%s: chi2 %.6g -> %.6g in %d iterations (%s: %s)\n", path.c_str(), r.initial_chi2,
              r.final_chi2, r.iterations, std::string(rove::to_string(r.termination)).c_str(),
              r.message.c_str());
  std::printf("position error against the truth: max %.3f m before, %.4f m after (RMSE %.4f m)\n",
              before.max, after.max, after.rmse);
  const bool ok = r.termination == rove::GraphTermination::Converged && r.final_chi2 < 0.01 && after.max < 0.05;
  std::printf("%s\n", ok ? "reached the ground truth" : "DID NOT REACH THE GROUND TRUTH");
  return ok ? 0 : 1;
}
