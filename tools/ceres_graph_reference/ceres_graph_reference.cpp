// Ceres reference for rove::graph: the same cost, from the same initial
// guess, minimized by Ceres 2.1 (LM or Powell's dog-leg, sparse normal
// Cholesky on SuiteSparse).
//
//   ceres_graph_reference -i GRAPH [--init as-is|odometry|spanning-tree|chordal]
//                         [--solver lm|dogleg] [--threads N] [--max-iters N]
//                         [--function-tolerance X] [-o OUT.g2o]
//
// Tolerances as rove's defaults: function 1e-8 (relative), gradient and
// parameter 1e-12.
//
// Prints one line: "chi2_initial <x> chi2_final <y> iterations <n> solve_s <t>".
// χ² = Σ eᵀ Ω e with e = [t, θ] (2D) or [t, q.xyz] (3D, w ≥ 0) of
// Z⁻¹·(Xi⁻¹·Xj), i.e. twice Ceres' cost.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/Cholesky>

#include "rove/core/timer.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/initialization.h"
#include "rove/graph/optimizer.h"

namespace {

// 2D: parameters [x, y, θ] per vertex; residual √Ω·[t_E; wrap(θ_E)].
struct Edge2Cost {
  Edge2Cost(const rove::SE2d& z, const Eigen::Matrix3d& sqrt_info)
      : zx(z.translation().x()), zy(z.translation().y()), zt(z.angle()), L(sqrt_info) {}
  template <class T>
  bool operator()(const T* a, const T* b, T* r) const {
    using std::cos;
    using std::sin;
    // Xi⁻¹ Xj
    const T ca = cos(a[2]), sa = sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    const T rx = ca * dx + sa * dy, ry = -sa * dx + ca * dy;
    const T rt = b[2] - a[2];
    // Z⁻¹ (Xi⁻¹ Xj)
    const double cz = std::cos(zt), sz = std::sin(zt);
    const T ex = cz * (rx - zx) + sz * (ry - zy);
    const T ey = -sz * (rx - zx) + cz * (ry - zy);
    T et = rt - zt;
    // Wrap to (−π, π] through atan2 of the angle's sine and cosine.
    et = atan2(sin(et), cos(et));
    const T e[3] = {ex, ey, et};
    for (int i = 0; i < 3; ++i) r[i] = L(i, 0) * e[0] + L(i, 1) * e[1] + L(i, 2) * e[2];
    return true;
  }
  double zx, zy, zt;
  Eigen::Matrix3d L;
};

// 3D: parameters p (3) and q (4, Eigen order x y z w) per vertex.
struct Edge3Cost {
  Edge3Cost(const rove::SE3d& z, const Eigen::Matrix<double, 6, 6>& sqrt_info)
      : tz(z.translation()), qz(z.quaternion()), L(sqrt_info) {}
  template <class T>
  bool operator()(const T* pa, const T* qa, const T* pb, const T* qb, T* r) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(pa), tb(pb);
    Eigen::Map<const Eigen::Quaternion<T>> Qa(qa), Qb(qb);
    const Eigen::Quaternion<T> qa_inv = Qa.conjugate();
    const Eigen::Matrix<T, 3, 1> t_ab = qa_inv * (tb - ta);
    const Eigen::Quaternion<T> q_ab = qa_inv * Qb;
    const Eigen::Quaternion<T> qz_inv = qz.conjugate().template cast<T>();
    const Eigen::Matrix<T, 3, 1> t_e = qz_inv * (t_ab - tz.template cast<T>());
    Eigen::Quaternion<T> q_e = qz_inv * q_ab;
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = t_e;
    e.template tail<3>() = q_e.w() < T(0) ? Eigen::Matrix<T, 3, 1>(-q_e.vec()) : q_e.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res = L.template cast<T>() * e;
    return true;
  }
  Eigen::Vector3d tz;
  Eigen::Quaterniond qz;
  Eigen::Matrix<double, 6, 6> L;
};

template <int N>
Eigen::Matrix<double, N, N> sqrt_information(const Eigen::Matrix<double, N, N>& info) {
  return Eigen::LLT<Eigen::Matrix<double, N, N>>(info).matrixU();  // Uᵀ U = Ω
}

double g_function_tolerance = 1e-8;
ceres::TrustRegionStrategyType g_strategy = ceres::LEVENBERG_MARQUARDT;

ceres::Solver::Options solver_options(int threads, int max_iters) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  o.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  o.minimizer_type = ceres::TRUST_REGION;
  o.trust_region_strategy_type = g_strategy;
  o.dogleg_type = ceres::TRADITIONAL_DOGLEG;  // Powell's, as rove's
  o.max_num_iterations = max_iters;
  o.function_tolerance = g_function_tolerance;
  o.gradient_tolerance = 1e-12;
  o.parameter_tolerance = 1e-12;
  o.num_threads = threads;
  o.logging_type = ceres::SILENT;
  return o;
}

// Vertices held constant: the fixed ones, or the lowest id (rove's gauge rule).
template <class Graph>
std::vector<rove::VertexId> anchors(const Graph& g) {
  std::vector<rove::VertexId> out;
  for (const auto& [id, v] : g.vertices())
    if (v.fixed) out.push_back(id);
  if (out.empty() && !g.vertices().empty()) {
    // Lowest id among vertices touched by an edge of level 0.
    rove::VertexId best = 0;
    bool found = false;
    for (const auto& e : g.edges()) {
      if (e.level != 0) continue;
      for (auto id : {e.from, e.to})
        if (!found || id < best) best = id, found = true;
    }
    if (found) out.push_back(best);
  }
  return out;
}

struct Outcome {
  double chi2_initial, chi2_final;
  int iterations;
  double seconds;
};

Outcome solve_2d(rove::PoseGraph2D& g, int threads, int max_iters) {
  std::map<rove::VertexId, std::array<double, 3>> x;
  for (const auto& [id, v] : g.vertices())
    x[id] = {v.pose.translation().x(), v.pose.translation().y(), v.pose.angle()};
  ceres::Problem problem;
  for (const auto& e : g.edges()) {
    if (e.level != 0) continue;
    auto* cost = new ceres::AutoDiffCostFunction<Edge2Cost, 3, 3, 3>(
        new Edge2Cost(e.measurement, sqrt_information<3>(e.information)));
    problem.AddResidualBlock(cost, nullptr, x[e.from].data(), x[e.to].data());
  }
  for (auto id : anchors(g)) problem.SetParameterBlockConstant(x[id].data());
  ceres::Solver::Summary summary;
  rove::Stopwatch sw;
  ceres::Solve(solver_options(threads, max_iters), &problem, &summary);
  const double t = sw.elapsed();
  for (auto& [id, p] : x)
    g.set_pose(id, rove::SE2d(rove::SO2d::from_angle(p[2]), Eigen::Vector2d(p[0], p[1])));
  return {2 * summary.initial_cost, 2 * summary.final_cost,
          static_cast<int>(summary.iterations.size()) - 1, t};
}

Outcome solve_3d(rove::PoseGraph3D& g, int threads, int max_iters) {
  struct Block {
    std::array<double, 3> p;
    std::array<double, 4> q;  // x y z w
  };
  std::map<rove::VertexId, Block> x;
  for (const auto& [id, v] : g.vertices()) {
    const auto& t = v.pose.translation();
    const auto& q = v.pose.quaternion();
    x[id] = {{t.x(), t.y(), t.z()}, {q.x(), q.y(), q.z(), q.w()}};
  }
  ceres::Problem problem;
  auto* manifold = new ceres::EigenQuaternionManifold;
  for (const auto& e : g.edges()) {
    if (e.level != 0) continue;
    auto* cost = new ceres::AutoDiffCostFunction<Edge3Cost, 6, 3, 4, 3, 4>(
        new Edge3Cost(e.measurement, sqrt_information<6>(e.information)));
    problem.AddResidualBlock(cost, nullptr, x[e.from].p.data(), x[e.from].q.data(),
                             x[e.to].p.data(), x[e.to].q.data());
  }
  for (auto& [id, b] : x)
    if (problem.HasParameterBlock(b.q.data())) problem.SetManifold(b.q.data(), manifold);
  for (auto id : anchors(g)) {
    problem.SetParameterBlockConstant(x[id].p.data());
    problem.SetParameterBlockConstant(x[id].q.data());
  }
  ceres::Solver::Summary summary;
  rove::Stopwatch sw;
  ceres::Solve(solver_options(threads, max_iters), &problem, &summary);
  const double t = sw.elapsed();
  for (auto& [id, b] : x) {
    const Eigen::Quaterniond q(b.q[3], b.q[0], b.q[1], b.q[2]);
    g.set_pose(id, rove::SE3d(rove::SO3d::from_unnormalized(q),
                              Eigen::Vector3d(b.p[0], b.p[1], b.p[2])));
  }
  return {2 * summary.initial_cost, 2 * summary.final_cost,
          static_cast<int>(summary.iterations.size()) - 1, t};
}

[[noreturn]] void usage() {
  std::fprintf(stderr,
               "usage: ceres_graph_reference -i GRAPH [--init as-is|odometry|spanning-tree|"
               "chordal] [--solver lm|dogleg] [--threads N] [--max-iters N] [--function-tolerance X] [-o OUT]\n");
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  std::string in, out;
  rove::InitialGuess init = rove::InitialGuess::AsIs;
  int threads = 1, max_iters = 100;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    auto next = [&]() -> std::string {
      if (k + 1 >= argc) usage();
      return argv[++k];
    };
    if (a == "-i") in = next();
    else if (a == "-o") out = next();
    else if (a == "--init") init = rove::parse_initial_guess(next());
    else if (a == "--solver") {
      const std::string v = next();
      if (v == "lm") g_strategy = ceres::LEVENBERG_MARQUARDT;
      else if (v == "dogleg") g_strategy = ceres::DOGLEG;
      else usage();
    }
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--max-iters") max_iters = std::atoi(next().c_str());
    else if (a == "--function-tolerance") g_function_tolerance = std::atof(next().c_str());
    else usage();
  }
  if (in.empty()) usage();
  try {
    Outcome r{};
    if (rove::detect_graph_dimension(in) == rove::GraphDimension::ThreeD) {
      auto g = rove::read_graph_3d(in);
      rove::initialize(g, init);
      r = solve_3d(g, threads, max_iters);
      r.chi2_final = rove::compute_chi2(g);
      if (!out.empty()) rove::write_graph(g, out);
    } else {
      auto g = rove::read_graph_2d(in);
      rove::initialize(g, init);
      r = solve_2d(g, threads, max_iters);
      r.chi2_final = rove::compute_chi2(g);
      if (!out.empty()) rove::write_graph(g, out);
    }
    std::printf("chi2_initial %.10g chi2_final %.10g iterations %d solve_s %.4f\n", r.chi2_initial,
                r.chi2_final, r.iterations, r.seconds);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ceres_graph_reference: %s\n", e.what());
    return 1;
  }
  return 0;
}
