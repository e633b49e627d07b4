// `rove graph-slam`: optimize, inspect and plot pose graphs. A thin layer over
// rove::graph (graph_io.h, initialization.h, optimizer.h, statistics.h).
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "graph_plot.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/json.h"
#include "rove/core/parallel.h"
#include "rove/core/timer.h"
#include "rove/graph/blas_tuning.h"
#include "rove/graph/evaluation.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/initialization.h"
#include "rove/graph/optimizer.h"
#include "rove/graph/statistics.h"

namespace rove::cli {
namespace {

struct GraphSlamArgs {
  std::string input, output, plot, ground_truth;
  bool two_d = false, three_d = false, info = false, json = false;
  std::string solver = "dogleg", init = "auto", robust, linear_solver = "auto";
  std::string repair_information = "none";
  int max_iters = 100, threads = 1, level = 0;
  double function_tolerance = GraphOptimizerOptions{}.function_tolerance;
};

// Everything the command learnt before optimizing.
struct Loaded {
  int dim = 2;
  GraphReadOptions read_options;
  GraphReadReport read;
  GraphStatistics stats;
  double load_s = 0.0;
};

std::string levels_present(const GraphStatistics& s) {
  std::string out;
  for (const auto& [level, n] : s.edges_per_level) {
    out += fmt::format("{}{} ({} edges)", out.empty() ? "" : ", ", level, n);
  }
  return out.empty() ? std::string("none: the graph has no edges") : out;
}

// A level nobody has: an empty problem is not a result.
void check_level(const GraphSlamArgs& a, const GraphStatistics& s) {
  if (s.edges_per_level.count(a.level) == 0) {
    throw InvalidArgument(fmt::format("--level {}: {} has no edge of that level; levels present: {}",
                                      a.level, printable(a.input), levels_present(s)));
  }
}

void write_statistics(JsonWriter& j, const GraphStatistics& s) {
  j.key("vertices").value(static_cast<std::uint64_t>(s.vertices));
  j.key("edges").value(static_cast<std::uint64_t>(s.edges));
  j.key("fixed").value(static_cast<std::uint64_t>(s.fixed));
  j.key("odometry_edges").value(static_cast<std::uint64_t>(s.odometry_edges));
  j.key("loop_closures").value(static_cast<std::uint64_t>(s.loop_closures));
  j.key("components").value(static_cast<std::uint64_t>(s.components));
  j.key("isolated").value(static_cast<std::uint64_t>(s.isolated));
  j.key("max_degree").value(static_cast<std::uint64_t>(s.max_degree));
  j.key("mean_degree").value(s.mean_degree);
  j.key("levels").begin_object();
  for (const auto& [level, n] : s.edges_per_level) {
    j.key(std::to_string(level)).value(static_cast<std::uint64_t>(n));
  }
  j.end_object();
}

void write_read_report(JsonWriter& j, const GraphSlamArgs& a, const GraphReadReport& r) {
  j.key("vertices_from").value(r.built_from_odometry ? "odometry" : "file");
  j.key("repair_information").value(a.repair_information);
  j.key("repaired_information_edges").value(static_cast<std::uint64_t>(r.repaired_edges));
}

void print_read_report(const GraphReadReport& r) {
  if (r.built_from_odometry) {
    fmt::print("poses          built from odometry (the file has edges only, no vertex)\n");
  }
  if (r.repaired_edges > 0) {
    fmt::print("information    {} of {} edges repaired to the nearest positive definite matrix "
               "(first on line {})\n",
               r.repaired_edges, r.edges, r.first_repaired_line.value_or(0));
  }
}

template <class Graph>
void print_info(const Graph& g, const GraphSlamArgs& a, const Loaded& l) {
  const GraphStatistics& s = l.stats;
  const double chi2 = compute_chi2(g, a.level);
  if (a.json) {
    JsonWriter j;
    j.begin_object();
    j.key("input").value(a.input);
    j.key("dimension").value(l.dim);
    write_statistics(j, s);
    write_read_report(j, a, l.read);
    j.key("level").value(a.level);
    j.key("chi2").value(chi2);
    write_issues(j, {});
    j.end_object();
    fmt::print("{}\n", j.str());
    return;
  }
  fmt::print("input          {} ({}D)\n", printable(a.input), l.dim);
  print_read_report(l.read);
  fmt::print("vertices       {} ({} fixed, {} isolated)\n", s.vertices, s.fixed, s.isolated);
  fmt::print("edges          {} ({} odometry, {} loop closures)\n", s.edges, s.odometry_edges,
             s.loop_closures);
  for (const auto& [level, n] : s.edges_per_level) fmt::print("  level {:<6}  {} edges\n", level, n);
  fmt::print("connectivity   {} connected component{}, max degree {}, mean degree {:.2f}\n",
             s.components, s.components == 1 ? "" : "s", s.max_degree, s.mean_degree);
  fmt::print("chi2           {:.10g} (poses as stored, level {})\n", chi2, a.level);
}

GraphOptimizerOptions optimizer_options(const GraphSlamArgs& a, int threads) {
  GraphOptimizerOptions o;
  o.solver = parse_graph_solver(a.solver);
  o.max_iterations = a.max_iters;
  o.num_threads = threads;
  o.level = a.level;
  o.function_tolerance = a.function_tolerance;
  if (a.linear_solver == "eigen") {
    o.linear_solver = LinearSolverType::Eigen;
  } else if (a.linear_solver == "cholmod") {
    if (!cholmod_available()) {
      throw InvalidArgument("--linear-solver cholmod: this build of rove has no SuiteSparse "
                            "CHOLMOD (use auto, block or eigen)");
    }
    o.linear_solver = LinearSolverType::Cholmod;
  } else if (a.linear_solver == "block") {
    o.linear_solver = LinearSolverType::Block;
  }
  if (!a.robust.empty()) o.robust_kernel = parse_robust_kernel(a.robust, "--robust");
  return o;
}

std::string init_description(const InitialGuessChoice& c) {
  if (c.requested != InitialGuess::Auto) return std::string(to_string(c.used));
  return fmt::format("{} (auto: {})", to_string(c.used), c.note);
}

/// Everything a graph-slam run reports, for its JSON and its text.
struct GraphSlamReport {
  const GraphSlamArgs& a;
  const Loaded& l;
  const GraphOptimizerOptions& o;
  const GraphOptimizerResult& r;
  const InitialGuessChoice& choice;
  std::size_t num_vertices;
  int threads;
  double init_s, write_s;
  bool plotted;
  std::optional<AlignedPositionError> gt;
  std::vector<Issue> issues;
};

void print_json(const GraphSlamReport& rep) {
  const auto& [a, l, o, r, choice, num_vertices, threads, init_s, write_s, plotted, gt, issues] =
      rep;
  JsonWriter j;
  j.begin_object();
  j.key("input").value(a.input);
  j.key("dimension").value(l.dim);
  j.key("vertices").value(static_cast<std::uint64_t>(num_vertices));
  write_read_report(j, a, l.read);
  j.key("level").value(a.level);
  j.key("edges_used").value(static_cast<std::uint64_t>(r.num_edges_used));
  j.key("vertices_optimized").value(static_cast<std::uint64_t>(r.num_vertices_optimized));
  j.key("vertices_fixed").value(static_cast<std::uint64_t>(r.num_vertices_fixed));
  if (r.gauge_anchor) {
    j.key("gauge_anchor").value(static_cast<std::uint64_t>(*r.gauge_anchor));
  } else {
    j.key("gauge_anchor").null();
  }
  j.key("init_requested").value(to_string(choice.requested));
  j.key("init").value(to_string(choice.used));
  j.key("init_note").value(choice.note);
  j.key("init_chi2_as_is");
  if (choice.as_is_chi2) j.value(*choice.as_is_chi2); else j.null();
  j.key("init_chi2_chordal");
  if (choice.chordal_chi2) j.value(*choice.chordal_chi2); else j.null();
  j.key("solver").value(to_string(o.solver));
  j.key("linear_solver").value(to_string(r.linear_solver));
  j.key("threads").value(threads);
  j.key("initial_chi2").value(r.initial_chi2);
  j.key("final_chi2").value(r.final_chi2);
  j.key("iterations").value(r.iterations);
  j.key("accepted_steps").value(r.accepted_steps);
  j.key("factorizations").value(r.factorizations);
  j.key("reused_factorizations").value(r.reused_factorizations);
  j.key("cg_iterations").value(r.cg_iterations);
  j.key("termination").value(to_string(r.termination));
  j.key("converged").value(r.termination == GraphTermination::Converged);
  j.key("message").value(r.message);
  j.key("time_s").begin_object();
  j.key("load").value(l.load_s).key("init").value(init_s);
  j.key("setup").value(r.timing.setup).key("linearize").value(r.timing.linearize);
  j.key("factorize").value(r.timing.factorize).key("evaluate").value(r.timing.evaluate);
  j.key("optimize").value(r.timing.total).key("write").value(write_s);
  j.end_object();
  j.key("hessian_nonzeros").value(static_cast<std::uint64_t>(r.hessian_nonzeros));
  j.key("factor_nonzeros").value(static_cast<std::uint64_t>(r.factor_nonzeros));
  j.key("ground_truth_rmse");
  if (gt) j.value(gt->rmse); else j.null();
  j.key("output");
  if (r.improved() && !a.output.empty()) j.value(a.output); else j.null();
  j.key("plot");
  if (plotted) j.value(a.plot); else j.null();
  j.key("problems").begin_array();
  for (const auto& is : r.issues) {
    j.begin_object();
    j.key("edge");
    if (is.edge == static_cast<std::size_t>(-1)) j.null(); else j.value(static_cast<std::uint64_t>(is.edge));
    j.key("vertex").value(static_cast<std::uint64_t>(is.vertex));
    j.key("message").value(is.message);
    j.end_object();
  }
  j.end_array();
  write_issues(j, issues);
  j.end_object();
  fmt::print("{}\n", j.str());
}

void print_text(const GraphSlamReport& rep) {
  const auto& [a, l, o, r, choice, num_vertices, threads, init_s, write_s, plotted, gt, issues] =
      rep;
  fmt::print("input          {} ({}D, {} vertices, {} edges used at level {})\n",
             printable(a.input), l.dim, num_vertices, r.num_edges_used, o.level);
  print_read_report(l.read);
  fmt::print("anchors        {} fixed{}\n", r.num_vertices_fixed,
             r.gauge_anchor ? fmt::format(" (vertex {} held for the gauge)", *r.gauge_anchor)
                            : std::string());
  fmt::print("initial guess  {} ({:.3f} s)\n", init_description(choice), init_s);
  fmt::print("solver         {}, {} Cholesky, {} thread{}{}\n", to_string(o.solver),
             to_string(r.linear_solver), threads, threads == 1 ? "" : "s",
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
             l.load_s, init_s, r.timing.setup, r.timing.linearize, r.timing.factorize,
             r.timing.evaluate, r.timing.total);
  fmt::print("sparsity       {} nonzeros in JᵀWJ (upper), {} in the factor\n",
             r.hessian_nonzeros, r.factor_nonzeros);
  if (gt) {
    fmt::print("ground truth   position RMSE {:.6g} m, max {:.6g} m after alignment ({} vertices)\n",
               gt->rmse, gt->max, gt->matched);
  }
  if (r.improved() && !a.output.empty()) fmt::print("output         {}\n", printable(a.output));
  if (plotted) fmt::print("plot           {}\n", printable(a.plot));
  if (issues.empty()) fmt::print("issues         none\n");
  for (std::size_t k = 0; k < issues.size(); ++k) {
    fmt::print("{}{}: {}\n", k == 0 ? "issues         " : "               ", issues[k].code,
               issues[k].message);
  }
}

template <class Graph>
int run(Graph g, const GraphSlamArgs& a, const Loaded& l, int threads) {
  if (a.info) {
    print_info(g, a, l);
    return kExitOk;
  }
  const GraphOptimizerOptions o = optimizer_options(a, threads);
  const InitialGuess init = parse_initial_guess(a.init);
  Stopwatch sw;
  const InitialGuessChoice choice = initialize_best(g, init, a.level);
  const double init_s = sw.lap();
  // The initial guess is kept only for the plot (a copy of the whole graph).
  std::optional<Graph> initial;
  if (!a.plot.empty()) initial = g;
  const GraphOptimizerResult r = optimize(g, o);
  sw.lap();

  std::vector<Issue> issues;
  if (r.termination == GraphTermination::MaxIterations) {
    issues.push_back({"max-iterations",
                      fmt::format("stopped at the iteration limit ({}, --max-iters) before "
                                  "converging; χ² {:.10g} may not be a minimum",
                                  o.max_iterations, r.final_chi2)});
  } else if (r.termination == GraphTermination::NoProgress) {
    issues.push_back({"no-progress", fmt::format("stopped without converging: {}", r.message)});
  } else if (!r.improved()) {
    issues.push_back({std::string(to_string(r.termination)), r.message});
    for (const auto& is : r.issues) issues.push_back({"graph", is.message});
  }

  double write_s = 0.0;
  if (r.improved() && !a.output.empty()) {
    write_graph(g, a.output);
    write_s = sw.lap();
  }
  bool plotted = false;
  if constexpr (std::is_same_v<Graph, PoseGraph2D>) {
    if (r.improved() && initial) {
      write_graph_plot(*initial, g, a.plot);
      plotted = true;
    }
  }
  std::optional<AlignedPositionError> gt;
  if (!a.ground_truth.empty() && r.improved()) {
    Graph truth;
    if constexpr (std::is_same_v<Graph, PoseGraph2D>) {
      truth = read_graph_2d(a.ground_truth, l.read_options);
    } else {
      truth = read_graph_3d(a.ground_truth, l.read_options);
    }
    std::size_t common = 0;
    for (const auto& kv : truth.vertices()) common += g.has_vertex(kv.first) ? 1 : 0;
    if (common < 3) {
      throw InvalidArgument(fmt::format(
          "--ground-truth {}: only {} of its vertex ids are in the graph; the alignment needs 3",
          printable(a.ground_truth), common));
    }
    gt = aligned_position_error(g, truth);
  }

  const GraphSlamReport report{a,      l,       o,       r,       choice, g.num_vertices(),
                               threads, init_s, write_s, plotted, gt,     issues};
  if (a.json) {
    print_json(report);
  } else {
    print_text(report);
  }
  if (!r.improved()) {
    fmt::print(stderr, "rove: graph-slam failed ({}): {}\n", to_string(r.termination), r.message);
    for (const auto& is : r.issues) fmt::print(stderr, "  {}\n", is.message);
    fmt::print(stderr, "rove: nothing was written\n");
    return kExitError;
  }
  finish(issues);
  return kExitOk;
}

}  // namespace

void add_graph_slam_command(CLI::App& app) {
  auto a = std::make_shared<GraphSlamArgs>();
  auto* cmd = app.add_subcommand(
      "graph-slam", "Optimize a 2D/3D pose graph (TORO .graph, g2o, rove binary), or inspect it");
  cmd->add_option("-i,--input", a->input, "Input graph file")->required();
  cmd->add_option("-o,--output", a->output,
                  "Output graph (.g2o → g2o, .rpg → rove binary, else TORO .graph); written "
                  "only when the optimization succeeds, never over the input");
  auto* d2 = cmd->add_flag("--2d", a->two_d, "The file holds a 2D graph (default: detected)");
  cmd->add_flag("--3d", a->three_d, "The file holds a 3D graph (default: detected)")->excludes(d2);
  cmd->add_option("--solver", a->solver, "gn | lm | dogleg")
      ->check(CLI::IsMember({"gn", "lm", "dogleg"}))
      ->capture_default_str();
  cmd->add_option("--init", a->init,
                  "Initial guess: auto (the better of as-is and chordal by χ² at the start) | "
                  "as-is | odometry | spanning-tree | chordal")
      ->check(CLI::IsMember({"auto", "as-is", "odometry", "spanning-tree", "chordal"}))
      ->capture_default_str();
  cmd->add_option("--robust", a->robust,
                  "Robust kernel for every edge, e.g. huber:1.0, cauchy:2 (default: none)");
  cmd->add_option("--max-iters", a->max_iters,
                  "Maximum iterations; reaching it is reported as the issue max-iterations")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--threads", a->threads,
                  fmt::format("Threads for linearization and χ² (0 = all hardware threads, at "
                              "most {})", kMaxThreads))
      ->capture_default_str();
  cmd->add_option("--level", a->level, "Optimize the edges of this level (it must exist)")
      ->capture_default_str();
  cmd->add_option("--linear-solver", a->linear_solver, "auto | block | eigen | cholmod")
      ->check(CLI::IsMember({"auto", "block", "eigen", "cholmod"}))
      ->capture_default_str();
  cmd->add_option("--function-tolerance", a->function_tolerance,
                  "Stop when χ² decreases by less than this fraction")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--repair-information", a->repair_information,
                  "Edges whose information matrix is not positive definite: none (refuse the "
                  "file) | nearest-psd (clamp its eigenvalues to 1e-6 of the largest, and say "
                  "how many edges changed)")
      ->check(CLI::IsMember({"none", "nearest-psd"}))
      ->capture_default_str();
  cmd->add_option("--plot", a->plot,
                  "PNG of a 2D graph: initial guess (left), result (right); never over an input");
  cmd->add_option("--ground-truth", a->ground_truth,
                  "Graph file with the true poses: print the position RMSE after alignment");
  cmd->add_flag("--info", a->info, "Print vertices, edges, levels and connectivity; no optimization");
  cmd->add_flag("--json", a->json, "Print the summary as one JSON object");
  cmd->callback([a] {
    const int threads = resolve_thread_count(a->threads, "--threads");
    // Process-wide BLAS settings: the command line opts in, once, here.
    configure_blas_for_this_cpu();
    tune_blas_threads(threads);
    std::vector<std::filesystem::path> inputs = {a->input}, outputs;
    check_regular_input(a->input, "graph (-i)");
    if (!a->ground_truth.empty()) {
      check_regular_input(a->ground_truth, "ground truth (--ground-truth)");
      inputs.emplace_back(a->ground_truth);
    }
    if (!a->output.empty()) outputs.emplace_back(a->output);
    if (!a->plot.empty()) outputs.emplace_back(a->plot);
    check_outputs_distinct(inputs, outputs);
    // A missing folder is found now, not after a long optimization.
    for (const auto& out : outputs) {
      const std::filesystem::path folder = out.parent_path();
      std::error_code ec;
      if (!folder.empty() && !std::filesystem::is_directory(folder, ec)) {
        throw IoError(out.string(), fmt::format("cannot write: folder '{}' does not exist",
                                                printable(folder.string())));
      }
    }

    Stopwatch sw;
    Loaded l;
    l.dim = a->two_d ? 2 : a->three_d ? 3 : 0;
    if (l.dim == 0) {
      const auto d = detect_graph_dimension(a->input);
      if (d == GraphDimension::Unknown) {
        throw ParseError({a->input, std::nullopt, std::nullopt, "tag"},
                         "no vertex or edge record found; cannot tell 2D from 3D (use --2d/--3d)");
      }
      l.dim = d == GraphDimension::TwoD ? 2 : 3;
    }
    if (l.dim == 3 && !a->plot.empty()) {
      throw InvalidArgument("--plot draws 2D graphs only; this graph is 3D");
    }
    GraphReadOptions& ro = l.read_options;
    ro.repair_information = *parse_information_repair(a->repair_information);
    int rc = 0;
    if (l.dim == 2) {
      auto g = read_graph_2d(a->input, ro, &l.read);
      l.load_s = sw.elapsed();
      l.stats = graph_statistics(g);
      if (!a->info || a->level != 0) check_level(*a, l.stats);
      rc = run(std::move(g), *a, l, threads);
    } else {
      auto g = read_graph_3d(a->input, ro, &l.read);
      l.load_s = sw.elapsed();
      l.stats = graph_statistics(g);
      if (!a->info || a->level != 0) check_level(*a, l.stats);
      rc = run(std::move(g), *a, l, threads);
    }
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace rove::cli
