// libFuzzer target for rove::parse_octree (OctoMap's .bt and .ot files).
// Any bytes must either read or be rejected with a ParseError (malformed
// file) or a ResourceError (over the memory budget); nothing else may be
// thrown. A tree that reads must be consistent (its leaves finite, as many
// nodes as its listing), and what rove writes of it must read back to a tree
// that writes the same bytes again, in both formats.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "rove/core/error.h"
#include "rove/io/octree_files.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "octree_fuzz: %s\n", what);
  std::abort();
}

void check_consistent(const rove::OccupancyOctree& t) {
  std::size_t nodes = 0, leaves = 0;
  t.for_each_node([&](const rove::OctreeNodeRecord& r) {
    ++nodes;
    if (r.child_mask == 0) ++leaves;
    if (!std::isfinite(r.log_odds)) die("a node's log-odds is not finite");
  });
  if (nodes != t.num_nodes()) die("the node listing disagrees with num_nodes()");
  if (leaves != t.num_leaves()) die("the leaf count disagrees with num_leaves()");
}

// write(read(write(t))) == write(t) in one format.
void check_round_trip(const std::string& written, bool binary) {
  const char* what = binary ? "binary (.bt) round trip changed the bytes" : "full (.ot) round trip changed the bytes";
  rove::OccupancyOctree again(1.0);
  try {
    again = rove::parse_octree(written, "again");
  } catch (const rove::Error& e) {
    std::fprintf(stderr, "octree_fuzz: %s written by rove does not read back: %s\n", what, e.what());
    std::abort();
  }
  check_consistent(again);
  const std::string rewritten = binary ? rove::octree_binary_bytes(again) : rove::octree_full_bytes(again);
  if (rewritten != written) die(what);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  rove::OccupancyOctree tree(1.0);
  try {
    tree = rove::parse_octree(bytes, "fuzz.bt");
  } catch (const rove::ParseError&) {
    return 0;
  } catch (const rove::ResourceError&) {
    return 0;
  } catch (const rove::Error& e) {
    std::fprintf(stderr, "octree_fuzz: malformed input gave an error other than ParseError: %s\n", e.what());
    std::abort();
  }
  check_consistent(tree);
  check_round_trip(rove::octree_binary_bytes(tree), true);
  check_round_trip(rove::octree_full_bytes(tree), false);
  return 0;
}
