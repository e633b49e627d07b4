// libFuzzer target for rove::graph's readers (TORO/MRPT .graph and g2o text,
// as 2D and as 3D, and the binary form). Any bytes must either load or be
// rejected with a rove::Error; a graph that loads must be consistent, write
// back to text that reads again to the same size, and optimize (a few
// iterations) without crashing.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string_view>

#include "rove/core/error.h"
#include "rove/graph/graph_io.h"
#include "rove/graph/optimizer.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/memory_stream.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "graph_fuzz: %s\n", what);
  std::abort();
}

template <class Graph, class Parse>
void exercise(std::string_view text, Parse parse) {
  Graph g;
  try {
    g = parse(text, "fuzz.graph");
  } catch (const rove::Error&) {
    return;
  }
  for (const auto& e : g.edges()) {
    if (!g.has_vertex(e.from) || !g.has_vertex(e.to) || e.from == e.to) die("dangling edge");
    if (rove::information_problem<Graph::kDof>(e.information)) die("bad information accepted");
  }
  for (auto format : {rove::GraphFileFormat::G2o, rove::GraphFileFormat::Toro}) {
    const std::string out = rove::format_graph(g, format);
    const Graph back = parse(out, "fuzz-roundtrip.graph");
    if (back.num_vertices() != g.num_vertices() || back.num_edges() != g.num_edges()) {
      die("text round trip changed the graph size");
    }
  }
  if (g.num_vertices() <= 64) {
    rove::GraphOptimizerOptions o;
    o.max_iterations = 5;
    const auto r = rove::optimize(g, o);
    if (r.ok() && std::isnan(r.final_chi2) && r.num_edges_used > 0) die("ok result with NaN chi2");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  exercise<rove::PoseGraph2D>(text, [](std::string_view t, std::string_view s) {
    return rove::parse_graph_2d(t, s);
  });
  exercise<rove::PoseGraph3D>(text, [](std::string_view t, std::string_view s) {
    return rove::parse_graph_3d(t, s);
  });
  // With the nearest-psd repair every edge that loads must be acceptable.
  rove::GraphReadOptions repair;
  repair.repair_information = rove::InformationRepair::NearestPsd;
  exercise<rove::PoseGraph2D>(text, [&](std::string_view t, std::string_view s) {
    return rove::parse_graph_2d(t, s, repair);
  });
  exercise<rove::PoseGraph3D>(text, [&](std::string_view t, std::string_view s) {
    return rove::parse_graph_3d(t, s, repair);
  });
  for (int dim = 2; dim <= 3; ++dim) {
    rove::MemoryInStream in(std::span<const std::byte>(reinterpret_cast<const std::byte*>(data), size),
                            "fuzz.rpg");
    rove::InArchive ar(in);
    try {
      if (dim == 2) {
        rove::PoseGraph2D g;
        rove::load(ar, g);
      } else {
        rove::PoseGraph3D g;
        rove::load(ar, g);
      }
    } catch (const rove::Error&) {
    }
  }
  return 0;
}
