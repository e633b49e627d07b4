// `rove graph-slam`: optimize, inspect and plot pose graphs.
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <string>

#include "commands.h"
#include "graph_plot.h"
#include "rove/core/error.h"
#include "rove/core/timer.h"
#include "rove/graph/evaluation.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/initialization.h"
#include "rove/graph/optimizer.h"

namespace rove::cli {
namespace {

struct GraphSlamArgs {
  std::string input, output, plot, ground_truth;
  bool two_d = false, three_d = false, info = false, json = false;
  std::string solver = "dogleg", init = "as-is", robust, linear_solver = "auto";
  int max_iters = 100, threads = 1, level = 0;
  double function_tolerance = GraphOptimizerOptions{}.function_tolerance;
};

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

template <class Graph>
void print_info(const Graph& g, const GraphSlamArgs& a, int dim) {
  // Components over all edges, degrees, levels, odometry vs. loop closures.
  std::map<VertexId, std::size_t> index;
  for (const auto& kv : g.vertices()) index.emplace(kv.first, index.size());
  std::vector<std::size_t> parent(index.size()), degree(index.size(), 0);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::map<int, std::size_t> levels;
  std::size_t odometry = 0;
  for (const auto& e : g.edges()) {
    const std::size_t i = index.at(e.from), j = index.at(e.to);
    parent[find(i)] = find(j);
    ++degree[i];
    ++degree[j];
    ++levels[e.level];
    if (e.to == e.from + 1 || e.from == e.to + 1) ++odometry;
  }
  std::size_t components = 0, isolated = 0;
  for (std::size_t v = 0; v < parent.size(); ++v) {
    if (find(v) == v) ++components;
    if (degree[v] == 0) ++isolated;
  }
  const std::size_t max_degree = degree.empty() ? 0 : *std::max_element(degree.begin(), degree.end());
  const double chi2 = compute_chi2(g, a.level);
  if (a.json) {
    std::string lv;
    for (const auto& [l, n] : levels) lv += fmt::format("{}\"{}\": {}", lv.empty() ? "" : ", ", l, n);
    fmt::print(
        "{{\"input\": {}, \"dimension\": {}, \"vertices\": {}, \"edges\": {}, \"fixed\": {}, "
        "\"odometry_edges\": {}, \"loop_closures\": {}, \"components\": {}, \"isolated\": {}, "
        "\"max_degree\": {}, \"levels\": {{{}}}, \"chi2\": {}}}\n",
        json_string(a.input), dim, g.num_vertices(), g.num_edges(), g.num_fixed(), odometry,
        g.num_edges() - odometry, components, isolated, max_degree, lv, chi2);
    return;
  }
  fmt::print("input          {} ({}D)\n", a.input, dim);
  fmt::print("vertices       {} ({} fixed, {} isolated)\n", g.num_vertices(), g.num_fixed(),
             isolated);
  fmt::print("edges          {} ({} odometry, {} loop closures)\n", g.num_edges(), odometry,
             g.num_edges() - odometry);
  for (const auto& [l, n] : levels) fmt::print("  level {:<6}  {} edges\n", l, n);
  fmt::print("connectivity   {} connected component{}, max degree {}, mean degree {:.2f}\n",
             components, components == 1 ? "" : "s", max_degree,
             index.empty() ? 0.0 : 2.0 * static_cast<double>(g.num_edges()) / index.size());
  fmt::print("chi2           {:.10g} (poses as stored, level {})\n", chi2, a.level);
}

template <class Graph>
int run(Graph g, const GraphSlamArgs& a, int dim, double load_s) {
  if (a.info) {
    print_info(g, a, dim);
    return 0;
  }
  GraphOptimizerOptions o;
  o.solver = parse_graph_solver(a.solver);
  o.max_iterations = a.max_iters;
  o.num_threads = a.threads;
  o.level = a.level;
  o.function_tolerance = a.function_tolerance;
  if (a.linear_solver == "eigen") {
    o.linear_solver = LinearSolverType::Eigen;
  } else if (a.linear_solver == "cholmod") {
    o.linear_solver = LinearSolverType::Cholmod;
  } else if (a.linear_solver == "block") {
    o.linear_solver = LinearSolverType::Block;
  }
  if (!a.robust.empty()) o.robust_kernel = parse_robust_kernel(a.robust, "--robust");
  const InitialGuess init = parse_initial_guess(a.init);
  Stopwatch sw;
  initialize(g, init, a.level);
  const double init_s = sw.lap();
  // The initial guess is kept only for the plot (a copy of the whole graph).
  std::optional<Graph> initial;
  if (!a.plot.empty()) initial = g;
  const GraphOptimizerResult r = optimize(g, o);
  sw.lap();
  double write_s = 0.0;
  if (!a.output.empty() && r.ok()) {
    write_graph(g, a.output);
    write_s = sw.lap();
  }
  if constexpr (std::is_same_v<Graph, PoseGraph2D>) {
    if (initial) write_graph_plot(*initial, g, a.plot);
  }
  std::optional<AlignedPositionError> gt;
  if (!a.ground_truth.empty()) {
    if constexpr (std::is_same_v<Graph, PoseGraph2D>) {
      gt = aligned_position_error(g, read_graph_2d(a.ground_truth));
    } else {
      gt = aligned_position_error(g, read_graph_3d(a.ground_truth));
    }
  }
  if (a.json) {
    std::string issues;
    for (const auto& is : r.issues) {
      issues += fmt::format("{}{{\"edge\": {}, \"vertex\": {}, \"message\": {}}}",
                            issues.empty() ? "" : ", ",
                            is.edge == static_cast<std::size_t>(-1) ? std::string("null")
                                                                    : std::to_string(is.edge),
                            is.vertex, json_string(is.message));
    }
    fmt::print(
        "{{\"input\": {}, \"dimension\": {}, \"vertices\": {}, \"edges_used\": {}, "
        "\"vertices_optimized\": {}, \"vertices_fixed\": {}, \"gauge_anchor\": {}, "
        "\"init\": \"{}\", \"solver\": \"{}\", \"linear_solver\": \"{}\", \"threads\": {}, "
        "\"initial_chi2\": {}, \"final_chi2\": {}, \"iterations\": {}, \"accepted_steps\": {}, "
        "\"factorizations\": {}, \"reused_factorizations\": {}, \"cg_iterations\": {}, "
        "\"termination\": \"{}\", \"message\": {}, \"time_s\": {{\"load\": {}, \"init\": {}, "
        "\"setup\": {}, \"linearize\": {}, \"factorize\": {}, \"evaluate\": {}, \"optimize\": {}, "
        "\"write\": {}}}, \"hessian_nonzeros\": {}, \"factor_nonzeros\": {}, \"ground_truth_rmse\": {}, \"issues\": [{}]}}\n",
        json_string(a.input), dim, g.num_vertices(), r.num_edges_used, r.num_vertices_optimized,
        r.num_vertices_fixed, r.gauge_anchor ? std::to_string(*r.gauge_anchor) : "null",
        to_string(init), to_string(o.solver), to_string(r.linear_solver), o.num_threads,
        r.initial_chi2, r.final_chi2, r.iterations, r.accepted_steps, r.factorizations,
        r.reused_factorizations, r.cg_iterations, to_string(r.termination),
        json_string(r.message), load_s, init_s, r.timing.setup, r.timing.linearize,
        r.timing.factorize, r.timing.evaluate, r.timing.total, write_s, r.hessian_nonzeros,
        r.factor_nonzeros, gt ? fmt::format("{}", gt->rmse) : std::string("null"), issues);
  } else {
    fmt::print("input          {} ({}D, {} vertices, {} edges used at level {})\n", a.input, dim,
               g.num_vertices(), r.num_edges_used, o.level);
    fmt::print("anchors        {} fixed{}\n", r.num_vertices_fixed,
               r.gauge_anchor ? fmt::format(" (vertex {} held for the gauge)", *r.gauge_anchor)
                              : std::string());
    fmt::print("initial guess  {} ({:.3f} s)\n", to_string(init), init_s);
    fmt::print("solver         {}, {} Cholesky, {} thread{}{}\n", to_string(o.solver),
               to_string(r.linear_solver), o.num_threads, o.num_threads == 1 ? "" : "s",
               o.robust_kernel ? ", robust " + o.robust_kernel->to_string() : std::string());
    fmt::print("chi2           {:.10g} -> {:.10g}\n", r.initial_chi2, r.final_chi2);
    fmt::print("iterations     {} ({} accepted, {} factorizations{})\n", r.iterations,
               r.accepted_steps, r.factorizations,
               r.reused_factorizations == 0
                   ? std::string()
                   : fmt::format(", {} steps on a reused factorization, {} CG iterations",
                                 r.reused_factorizations, r.cg_iterations));
    fmt::print("termination    {}: {}\n", to_string(r.termination), r.message);
    fmt::print("time (s)       load {:.3f} | init {:.3f} | setup {:.3f} | linearize {:.3f} | "
               "factorize {:.3f} | evaluate {:.3f} | optimize {:.3f}\n",
               load_s, init_s, r.timing.setup, r.timing.linearize, r.timing.factorize,
               r.timing.evaluate, r.timing.total);
    fmt::print("sparsity       {} nonzeros in JᵀWJ (upper), {} in the factor\n",
               r.hessian_nonzeros, r.factor_nonzeros);
    if (gt) {
      fmt::print("ground truth   position RMSE {:.6g} m, max {:.6g} m after alignment ({} vertices)\n",
                 gt->rmse, gt->max, gt->matched);
    }
    if (!a.output.empty() && r.ok()) fmt::print("output         {}\n", a.output);
    if (!a.plot.empty() && dim == 2) fmt::print("plot           {}\n", a.plot);
  }
  if (!r.ok()) {
    fmt::print(stderr, "rove: graph-slam failed ({}): {}\n", to_string(r.termination), r.message);
    for (const auto& is : r.issues) fmt::print(stderr, "  {}\n", is.message);
    return 1;
  }
  return 0;
}

}  // namespace

void add_graph_slam_command(CLI::App& app) {
  auto a = std::make_shared<GraphSlamArgs>();
  auto* cmd = app.add_subcommand(
      "graph-slam", "Optimize a 2D/3D pose graph (TORO .graph, g2o, rove binary), or inspect it");
  cmd->add_option("-i,--input", a->input, "Input graph file")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a->output,
                  "Output graph (.g2o → g2o, .rpg → rove binary, else TORO .graph)");
  auto* d2 = cmd->add_flag("--2d", a->two_d, "The file holds a 2D graph (default: detected)");
  cmd->add_flag("--3d", a->three_d, "The file holds a 3D graph (default: detected)")->excludes(d2);
  cmd->add_option("--solver", a->solver, "gn | lm | dogleg (default dogleg)")
      ->check(CLI::IsMember({"gn", "lm", "dogleg"}));
  cmd->add_option("--init", a->init, "Initial guess: as-is | odometry | spanning-tree | chordal")
      ->check(CLI::IsMember({"as-is", "odometry", "spanning-tree", "chordal"}));
  cmd->add_option("--robust", a->robust, "Robust kernel for every edge, e.g. huber:1.0, cauchy:2");
  cmd->add_option("--max-iters", a->max_iters, "Maximum iterations (default 100)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", a->threads, "Threads for linearization (default 1)")
      ->check(CLI::Range(1, 256));
  cmd->add_option("--level", a->level, "Optimize the edges of this level (default 0)");
  cmd->add_option("--linear-solver", a->linear_solver, "auto | block | eigen | cholmod")
      ->check(CLI::IsMember({"auto", "block", "eigen", "cholmod"}));
  cmd->add_option("--function-tolerance", a->function_tolerance,
                  "Stop when χ² decreases by less than this fraction")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--plot", a->plot, "PNG of a 2D graph: initial guess (left), result (right)");
  cmd->add_option("--ground-truth", a->ground_truth,
                  "Graph file with the true poses: print the position RMSE after alignment")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--info", a->info, "Print vertices, edges, levels and connectivity; no optimization");
  cmd->add_flag("--json", a->json, "Print the summary as one JSON object");
  cmd->callback([a] {
    Stopwatch sw;
    int dim = a->two_d ? 2 : a->three_d ? 3 : 0;
    if (dim == 0) {
      const auto d = detect_graph_dimension(a->input);
      if (d == GraphDimension::Unknown) {
        throw ParseError({a->input, std::nullopt, std::nullopt, "tag"},
                         "no vertex or edge record found; cannot tell 2D from 3D (use --2d/--3d)");
      }
      dim = d == GraphDimension::TwoD ? 2 : 3;
    }
    if (dim == 3 && !a->plot.empty()) {
      throw InvalidArgument("--plot draws 2D graphs only");
    }
    int rc = 0;
    if (dim == 2) {
      auto g = read_graph_2d(a->input);
      rc = run(std::move(g), *a, 2, sw.elapsed());
    } else {
      auto g = read_graph_3d(a->input);
      rc = run(std::move(g), *a, 3, sw.elapsed());
    }
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace rove::cli
