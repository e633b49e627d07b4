#include "rove/io/octree_files.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/memory_budget.h"

namespace rove {

namespace {

// The files are little-endian; values are copied as they are in memory.
static_assert(std::endian::native == std::endian::little, "octree files: big-endian hosts are not supported");

constexpr std::string_view kBinaryFirstLine = "# Octomap OcTree binary file";
constexpr std::string_view kFullFirstLine = "# Octomap OcTree file";
constexpr std::string_view kCommentLines =
    "\n# (feel free to add / change comments, but leave the first line as it is!)\n#\n";

[[noreturn]] void fail(const std::string& source, std::uint64_t offset, std::string field, std::string problem) {
  throw ParseError({source, std::nullopt, offset, std::move(field)}, std::move(problem));
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; }

// OctoMap's header reader (AbstractOcTree::readHeader): whitespace-separated
// tokens; `#` starts a comment up to the end of the line; `id`, `size` and
// `res` take the next token; `data` ends the header with its line; other
// words are skipped with their line.
class HeaderScanner {
 public:
  HeaderScanner(std::string_view b, std::size_t pos, const std::string& source) : b_(b), pos_(pos), source_(source) {}

  std::optional<std::string_view> token() {
    while (pos_ < b_.size() && is_space(b_[pos_])) ++pos_;
    if (pos_ == b_.size()) return std::nullopt;
    const std::size_t start = pos_;
    while (pos_ < b_.size() && !is_space(b_[pos_])) ++pos_;
    return b_.substr(start, pos_ - start);
  }
  std::string_view value(const char* field) {
    const auto t = token();
    if (!t) fail(source_, pos_, field, fmt::format("the header ends before the value of '{}'", field));
    return *t;
  }
  void skip_line() {
    while (pos_ < b_.size() && b_[pos_] != '\n') ++pos_;
    if (pos_ < b_.size()) ++pos_;
  }
  std::size_t pos() const noexcept { return pos_; }

 private:
  std::string_view b_;
  std::size_t pos_;
  const std::string& source_;
};

template <typename T>
T parse_number(std::string_view t, const std::string& source, std::size_t offset, const char* field) {
  T v{};
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
    fail(source, offset, field, fmt::format("'{}' is not a valid {}", printable(t), field));
  }
  return v;
}

template <typename T>
T read_le(std::string_view b, std::size_t pos) {
  T v;
  std::memcpy(&v, b.data() + pos, sizeof(T));
  return v;
}

OctreeFileHeader parse_legacy(std::string_view b, const std::string& source) {
  // OctoMap's readBinaryLegacyHeader: int32 tree type 3, f64 resolution, u32 size.
  OctreeFileHeader h;
  h.legacy = true;
  h.id = "OcTree";
  h.resolution = read_le<double>(b, 4);
  h.size = read_le<std::uint32_t>(b, 12);
  h.data_offset = 16;
  if (!octree_resolution_valid(h.resolution)) {
    fail(source, 4, "res", fmt::format("resolution {} is not > 0 or out of range", h.resolution));
  }
  return h;
}

// Appends the nodes of a file in pre-order, checking every byte.
class NodeReader {
 public:
  NodeReader(std::string_view b, const OctreeFileHeader& h, const std::string& source, bool colors, float clamp_min,
             float clamp_max)
      : b_(b), pos_(h.data_offset), header_(h), source_(source), colors_(colors), clamp_min_(clamp_min),
        clamp_max_(clamp_max) {
    nodes_.reserve(static_cast<std::size_t>(h.size));
  }

  std::vector<OctreeNodeRecord> read() {
    if (header_.size > 0) {
      if (header_.format == OctreeFileFormat::Binary) {
        binary_node(0, clamp_max_);  // OctoMap leaves the root at clamping_max
      } else {
        full_node(0);
      }
    }
    if (nodes_.size() != header_.size) {
      fail(source_, pos_, "size", fmt::format("the tree has {} nodes, the header says {}", nodes_.size(), header_.size));
    }
    if (pos_ != b_.size()) fail(source_, pos_, "data", fmt::format("{} bytes after the tree", b_.size() - pos_));
    return std::move(nodes_);
  }

 private:
  void need(std::size_t n, const char* field) {
    if (b_.size() - pos_ < n) {
      fail(source_, pos_, field,
           fmt::format("the file ends inside the tree ({} of {} nodes read)", nodes_.size(), header_.size));
    }
  }
  void push(const OctreeNodeRecord& r, int depth, std::size_t offset) {
    if (nodes_.size() == header_.size) {
      fail(source_, offset, "size", fmt::format("the tree has more nodes than the {} of the header", header_.size));
    }
    if (r.child_mask != 0 && depth >= kOctreeDepth) {
      fail(source_, offset, "node", "a node at depth 16 (a finest cell) has children");
    }
    nodes_.push_back(r);
  }
  void binary_node(int depth, float value) {
    need(2, "node");
    const std::size_t offset = pos_;
    const auto lo = static_cast<unsigned char>(b_[pos_]), hi = static_cast<unsigned char>(b_[pos_ + 1]);
    pos_ += 2;
    unsigned codes[8];
    OctreeNodeRecord r;
    r.log_odds = value;
    for (unsigned i = 0; i < 8; ++i) {
      codes[i] = ((i < 4 ? lo : hi) >> (2 * (i & 3u))) & 3u;
      if (codes[i] != 0) r.child_mask = static_cast<std::uint8_t>(r.child_mask | (1u << i));
    }
    push(r, depth, offset);
    for (unsigned i = 0; i < 8; ++i) {
      if (codes[i] == 1 || codes[i] == 2) {
        OctreeNodeRecord leaf;
        leaf.log_odds = codes[i] == 1 ? clamp_min_ : clamp_max_;
        push(leaf, depth + 1, offset);
      } else if (codes[i] == 3) {
        // An inner node must have children (OctoMap never writes one
        // without); its value is the maximum of theirs.
        need(2, "node");
        if (b_[pos_] == 0 && b_[pos_ + 1] == 0) fail(source_, pos_, "node", "an inner node (code 11) has no children");
        binary_node(depth + 1, std::numeric_limits<float>::quiet_NaN());
      }
    }
  }
  void full_node(int depth) {
    const std::size_t offset = pos_;
    need(colors_ ? 8 : 5, "node");
    OctreeNodeRecord r;
    r.log_odds = read_le<float>(b_, pos_);
    if (!std::isfinite(r.log_odds)) fail(source_, pos_, "log-odds", fmt::format("log-odds {} is not finite", r.log_odds));
    pos_ += 4;
    if (colors_) {
      r.color = Rgb8{static_cast<std::uint8_t>(b_[pos_]), static_cast<std::uint8_t>(b_[pos_ + 1]),
                     static_cast<std::uint8_t>(b_[pos_ + 2])};
      pos_ += 3;
    }
    r.child_mask = static_cast<std::uint8_t>(b_[pos_++]);
    push(r, depth, offset);
    for (unsigned i = 0; i < 8; ++i) {
      if (((r.child_mask >> i) & 1u) != 0) full_node(depth + 1);
    }
  }

  std::string_view b_;
  std::size_t pos_;
  const OctreeFileHeader& header_;
  const std::string& source_;
  bool colors_;
  float clamp_min_, clamp_max_;
  std::vector<OctreeNodeRecord> nodes_;
};

std::string header_text(std::string_view first_line, std::string_view id, std::size_t size, double resolution) {
  // OctoMap writes the resolution with an ostream's default format (%g).
  return fmt::format("{}{}id {}\nsize {}\nres {:g}\ndata\n", first_line, kCommentLines, id, size, resolution);
}

// Index after the subtree of node i, for every node (pre-order list).
std::size_t subtree_ends(const std::vector<OctreeNodeRecord>& n, std::size_t i, std::vector<std::size_t>& end) {
  std::size_t j = i + 1;
  for (unsigned c = 0; c < 8; ++c) {
    if (((n[i].child_mask >> c) & 1u) != 0) j = subtree_ends(n, j, end);
  }
  end[i] = j;
  return j;
}

void write_binary_node(const OccupancyOctree& tree, const std::vector<OctreeNodeRecord>& n,
                       const std::vector<std::size_t>& end, std::size_t i, std::string& out) {
  unsigned char bytes[2] = {0, 0};
  std::size_t children[8];
  std::size_t j = i + 1;
  for (unsigned c = 0; c < 8; ++c) {
    if (((n[i].child_mask >> c) & 1u) == 0) continue;
    children[c] = j;
    const unsigned code = n[j].child_mask != 0 ? 3u : (tree.is_occupied(n[j].log_odds) ? 2u : 1u);
    bytes[c / 4] = static_cast<unsigned char>(bytes[c / 4] | (code << (2 * (c & 3u))));
    j = end[j];
  }
  out.push_back(static_cast<char>(bytes[0]));
  out.push_back(static_cast<char>(bytes[1]));
  for (unsigned c = 0; c < 8; ++c) {
    if (((n[i].child_mask >> c) & 1u) != 0 && n[children[c]].child_mask != 0) {
      write_binary_node(tree, n, end, children[c], out);
    }
  }
}

std::vector<OctreeNodeRecord> records_of(const OccupancyOctree& tree) {
  std::vector<OctreeNodeRecord> n;
  n.reserve(tree.num_nodes());
  tree.for_each_node([&](const OctreeNodeRecord& r) { n.push_back(r); });
  return n;
}

}  // namespace

OctreeFileHeader parse_octree_header(std::string_view b, const std::string& source) {
  OctreeFileHeader h;
  const std::size_t eol = b.find('\n');
  const std::string_view first = b.substr(0, eol == std::string_view::npos ? b.size() : eol);
  if (first.substr(0, kBinaryFirstLine.size()) == kBinaryFirstLine) {
    h.format = OctreeFileFormat::Binary;
  } else if (first.substr(0, kFullFirstLine.size()) == kFullFirstLine) {
    h.format = OctreeFileFormat::Full;
  } else if (b.size() >= 16 && read_le<std::int32_t>(b, 0) == 3) {
    return parse_legacy(b, source);
  } else {
    fail(source, 0, "header",
         fmt::format("not an OctoMap file: the first line must start with '{}' or '{}'", kBinaryFirstLine,
                     kFullFirstLine));
  }
  HeaderScanner s(b, eol == std::string_view::npos ? b.size() : eol + 1, source);
  bool has_res = false;
  while (true) {
    const std::size_t at = s.pos();
    const auto t = s.token();
    if (!t) fail(source, s.pos(), "data", "the header has no 'data' line");
    if (*t == "data") {
      s.skip_line();
      break;
    }
    if ((*t)[0] == '#') {
      s.skip_line();
    } else if (*t == "id") {
      h.id = std::string(s.value("id"));
    } else if (*t == "res") {
      h.resolution = parse_number<double>(s.value("res"), source, at, "res");
      has_res = true;
    } else if (*t == "size") {
      h.size = parse_number<std::uint64_t>(s.value("size"), source, at, "size");
    } else {
      s.skip_line();  // OctoMap skips unknown keywords with their line
    }
  }
  h.data_offset = s.pos();
  if (h.id.empty()) fail(source, h.data_offset, "id", "the header has no tree type ('id')");
  if (h.id == "1") h.id = "OcTree";  // OctoMap's deprecated id
  if (!has_res || !octree_resolution_valid(h.resolution)) {
    fail(source, h.data_offset, "res",
         has_res ? fmt::format("resolution {} is not > 0 or out of range", h.resolution)
                 : std::string("the header has no resolution ('res')"));
  }
  return h;
}

OccupancyOctree parse_octree(std::string_view b, const std::string& source, const OccupancyOctreeParams& params) {
  const OctreeFileHeader h = parse_octree_header(b, source);
  // A ColorOcTree keeps its type also from a .bt (which stores no colours:
  // its leaves are white), so that it writes back as it was read.
  const OctreeChannels channels = h.id == "ColorOcTree" ? OctreeChannels::Color : OctreeChannels::None;
  if (h.format == OctreeFileFormat::Full && h.id != "OcTree" && h.id != "ColorOcTree") {
    fail(source, 0, "id", fmt::format("tree type '{}' is not supported (OcTree, ColorOcTree)", printable(h.id)));
  }
  // Every node takes at least 5 bytes of an .ot; a .bt record of 2 bytes
  // holds up to 8 children.
  const std::uint64_t data = b.size() - std::min<std::uint64_t>(b.size(), h.data_offset);
  const std::uint64_t most = h.format == OctreeFileFormat::Full ? data / 5 : 1 + 4 * data;
  if (h.size > most) {
    fail(source, h.data_offset, "size", fmt::format("{} nodes cannot fit in the {} bytes of data", h.size, data));
  }
  check_memory_budget(checked_bytes(h.size, sizeof(OctreeNodeRecord) + 16),
                      fmt::format("{}: octree of {} nodes", printable(source), h.size));
  OccupancyOctree tree(h.resolution, params, channels);
  NodeReader reader(b, h, source, h.format == OctreeFileFormat::Full && channels == OctreeChannels::Color,
                    tree.clamp_min_log_odds(),
                    tree.clamp_max_log_odds());
  const std::vector<OctreeNodeRecord> nodes = reader.read();
  tree.assign_preorder(nodes);
  return tree;
}

OccupancyOctree read_octree(const std::string& path, const OccupancyOctreeParams& params) {
  const std::string bytes = read_input_file(path, std::numeric_limits<std::uint64_t>::max(), "octree file");
  return parse_octree(bytes, path, params);
}

std::string octree_binary_bytes(const OccupancyOctree& tree, OctreeBinaryContent content) {
  if (content == OctreeBinaryContent::MaxLikelihood) {
    OccupancyOctree ml = tree;
    ml.to_max_likelihood();
    ml.prune();
    return octree_binary_bytes(ml, OctreeBinaryContent::AsIs);
  }
  const std::vector<OctreeNodeRecord> n = records_of(tree);
  const bool colors = has_channels(tree.channels(), OctreeChannels::Color);
  std::string out = header_text(kBinaryFirstLine, colors ? "ColorOcTree" : "OcTree", n.size(), tree.resolution());
  if (!n.empty()) {
    std::vector<std::size_t> end(n.size());
    subtree_ends(n, 0, end);
    write_binary_node(tree, n, end, 0, out);
  }
  return out;
}

std::string octree_full_bytes(const OccupancyOctree& tree) {
  const bool colors = has_channels(tree.channels(), OctreeChannels::Color);
  std::string out =
      header_text(kFullFirstLine, colors ? "ColorOcTree" : "OcTree", tree.num_nodes(), tree.resolution());
  out.reserve(out.size() + tree.num_nodes() * (colors ? 8 : 5));
  tree.for_each_node([&](const OctreeNodeRecord& r) {
    char v[4];
    std::memcpy(v, &r.log_odds, 4);
    out.append(v, 4);
    if (colors) {
      out.push_back(static_cast<char>(r.color.r));
      out.push_back(static_cast<char>(r.color.g));
      out.push_back(static_cast<char>(r.color.b));
    }
    out.push_back(static_cast<char>(r.child_mask));
  });
  return out;
}

void write_octree(const std::string& path, const OccupancyOctree& tree, OctreeFileFormat format,
                  OctreeBinaryContent content) {
  const std::string bytes =
      format == OctreeFileFormat::Binary ? octree_binary_bytes(tree, content) : octree_full_bytes(tree);
  write_text_file_atomically(path, bytes);
}

}  // namespace rove
