// TORO/MRPT .graph, g2o and binary pose-graph files.
#include "rove/graph/graph_io.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/memory_budget.h"
#include "rove/graph/initialization.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/file_stream.h"
#include "rove/serialization/gzip_stream.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/memory_stream.h"
#include "rove/serialization/version.h"

namespace rove {
namespace {

constexpr char kBinaryMagic[8] = {'r', 'o', 'v', 'e', '-', 'p', 'g', '\0'};
constexpr std::uint8_t kBinaryVersion = 1;

// ---------------------------------------------------------------------------
// Text lexing

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits one line into whitespace-separated tokens.
void split_tokens(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'a' && x <= 'z') x = static_cast<char>(x - 'a' + 'A');
    if (y >= 'a' && y <= 'z') y = static_cast<char>(y - 'a' + 'A');
    if (x != y) return false;
  }
  return true;
}

enum class Tag { Vertex2, Edge2Toro, Edge2G2o, Vertex3, Vertex3Quat, Edge3Toro, Edge3Quat, Equiv, Fix };

bool tag_from_text(std::string_view t, Tag& tag) {
  static const std::pair<const char*, Tag> kTags[] = {
      {"VERTEX2", Tag::Vertex2},          {"VERTEX", Tag::Vertex2},
      {"VERTEX_SE2", Tag::Vertex2},       {"EDGE2", Tag::Edge2Toro},
      {"EDGE", Tag::Edge2Toro},           {"ODOMETRY", Tag::Edge2Toro},
      {"EDGE_SE2", Tag::Edge2G2o},        {"VERTEX3", Tag::Vertex3},
      {"VERTEX_SE3:QUAT", Tag::Vertex3Quat}, {"EDGE3", Tag::Edge3Toro},
      {"EDGE_SE3:QUAT", Tag::Edge3Quat},  {"EQUIV", Tag::Equiv},
      {"FIX", Tag::Fix}};
  for (const auto& [name, value] : kTags) {
    if (iequals(t, name)) {
      tag = value;
      return true;
    }
  }
  return false;
}

bool is_3d_tag(Tag t) {
  return t == Tag::Vertex3 || t == Tag::Vertex3Quat || t == Tag::Edge3Toro || t == Tag::Edge3Quat;
}
bool is_2d_tag(Tag t) { return t == Tag::Vertex2 || t == Tag::Edge2Toro || t == Tag::Edge2G2o; }

// Reads the tokens of one record with errors that name the file, line and field.
class LineReader {
 public:
  LineReader(std::string_view source, std::size_t line, const std::vector<std::string_view>& tokens)
      : source_(source), line_(line), tokens_(tokens) {}

  [[noreturn]] void fail(std::string_view field, const std::string& problem) const {
    throw ParseError({std::string(source_), line_, std::nullopt, std::string(field)}, problem);
  }

  bool at_end() const { return next_ >= tokens_.size(); }
  std::size_t remaining() const { return tokens_.size() - next_; }

  double number(std::string_view field) {
    if (at_end()) fail(field, fmt::format("line ends before field '{}'", field));
    const std::string_view t = tokens_[next_++];
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || ptr != t.data() + t.size()) {
      fail(field, fmt::format("expected a number for field '{}', got '{}'", field, t));
    }
    if (!std::isfinite(v)) fail(field, fmt::format("field '{}' is not finite ({})", field, t));
    return v;
  }

  VertexId id(std::string_view field) {
    if (at_end()) fail(field, fmt::format("line ends before field '{}'", field));
    const std::string_view t = tokens_[next_++];
    VertexId v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || ptr != t.data() + t.size()) {
      fail(field, fmt::format("expected a non-negative integer vertex id for field '{}', got '{}'",
                              field, t));
    }
    return v;
  }

  void expect_end() const {
    if (!at_end()) {
      fail("", fmt::format("unexpected extra field '{}' (record has {} fields, expected {})",
                           tokens_[next_], tokens_.size() - 1, next_ - 1));
    }
  }

  std::size_t line() const { return line_; }

 private:
  std::string_view source_;
  std::size_t line_;
  const std::vector<std::string_view>& tokens_;
  std::size_t next_ = 1;  // token 0 is the tag
};

// Rotation from TORO/MRPT Euler angles: R = Rz(yaw)·Ry(pitch)·Rx(roll).
Eigen::Quaterniond quaternion_from_rpy(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

// (roll, pitch, yaw) of a rotation matrix, MRPT's formula.
Eigen::Vector3d rpy_from_matrix(const Eigen::Matrix3d& R) {
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  double yaw = 0.0, roll = 0.0;
  if (std::abs(std::abs(pitch) - M_PI / 2) < 1e-9) {
    // Gimbal lock: only yaw ∓ roll is defined; put it all in yaw.
    yaw = std::atan2(-R(0, 1), R(1, 1));
  } else {
    yaw = std::atan2(R(1, 0), R(0, 0));
    roll = std::atan2(R(2, 1), R(2, 2));
  }
  return {roll, pitch, yaw};
}

SE3d se3_from_quaternion(LineReader& r, double x, double y, double z, double qx, double qy,
                         double qz, double qw) {
  const double norm = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
  if (!(norm > 0.0) || std::abs(norm - 1.0) > 1e-3) {
    r.fail("quaternion", fmt::format("quaternion (qx qy qz qw) = ({} {} {} {}) has norm {}, "
                                     "not a rotation",
                                     qx, qy, qz, qw, norm));
  }
  Eigen::Quaterniond q(qw / norm, qx / norm, qy / norm, qz / norm);
  return SE3d(SO3d::from_unnormalized(q), Eigen::Vector3d(x, y, z));
}

const char* const kInfo2Toro[6] = {"inf_xx", "inf_xy", "inf_yy", "inf_tt", "inf_xt", "inf_yt"};
const char* const kInfo2G2o[6] = {"inf_xx", "inf_xy", "inf_xt", "inf_yy", "inf_yt", "inf_tt"};

// Field names "inf_ij" (1-based) of an upper triangle up to 6 × 6, made
// once: naming each field per number read was a third of the parse time.
const std::string& info_field_name(int i, int j) {
  static const auto names = [] {
    std::array<std::string, 36> n;
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) n[static_cast<std::size_t>(6 * a + b)] = fmt::format("inf_{}{}", a + 1, b + 1);
    return n;
  }();
  return names[static_cast<std::size_t>(6 * i + j)];
}

template <int N>
void read_upper_triangle(LineReader& r, Eigen::Matrix<double, N, N>& m) {
  static_assert(N <= 6);
  for (int i = 0; i < N; ++i) {
    for (int j = i; j < N; ++j) m(i, j) = m(j, i) = r.number(info_field_name(i, j));
  }
}

struct VertexRecord {
  VertexId id;
  std::size_t line;
};

template <class PoseT>
struct EdgeRecord {
  PoseGraphEdge<PoseT> edge;
  std::size_t line;
};

// Smallest id of the EQUIV class of `id` (union-find by smallest id).
VertexId find_root(std::map<VertexId, VertexId>& parent, VertexId id) {
  VertexId root = id;
  for (auto it = parent.find(root); it != parent.end() && it->second != root;
       it = parent.find(root)) {
    root = it->second;
  }
  // Path compression.
  while (id != root) {
    auto it = parent.find(id);
    const VertexId next = it->second;
    it->second = root;
    id = next;
  }
  return root;
}

void add_equiv(std::map<VertexId, VertexId>& parent, VertexId a, VertexId b) {
  parent.try_emplace(a, a);
  parent.try_emplace(b, b);
  const VertexId ra = find_root(parent, a);
  const VertexId rb = find_root(parent, b);
  if (ra == rb) return;
  parent[std::max(ra, rb)] = std::min(ra, rb);
}

template <class PoseT>
PoseGraph<PoseT> parse_text(std::string_view text, std::string_view source,
                            const GraphReadOptions& options, GraphReadReport* report_out) {
  constexpr bool k3d = PoseT::kDof == 6;
  GraphReadReport report;
  // Edges whose information matrix is not positive definite: counted over
  // the whole file, so the error can say how many there are.
  std::size_t bad_information = 0;
  std::optional<std::pair<std::size_t, std::string>> first_bad_information;
  PoseGraph<PoseT> graph;
  std::vector<std::pair<VertexId, PoseT>> vertex_poses;
  std::vector<VertexRecord> vertex_records;
  std::vector<EdgeRecord<PoseT>> edge_records;
  std::vector<std::pair<VertexId, std::size_t>> fix_records;
  std::map<VertexId, VertexId> equiv;
  std::vector<std::string_view> tokens;

  std::size_t line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    split_tokens(line, tokens);
    if (tokens.empty() || tokens[0][0] == '#') continue;
    LineReader r(source, line_no, tokens);
    Tag tag;
    if (!tag_from_text(tokens[0], tag)) {
      r.fail("tag", fmt::format("unknown record tag '{}'", tokens[0]));
    }
    if (!k3d && is_3d_tag(tag)) {
      r.fail("tag", fmt::format("3D record '{}' in a 2D graph", tokens[0]));
    }
    if (k3d && is_2d_tag(tag)) {
      r.fail("tag", fmt::format("2D record '{}' in a 3D graph", tokens[0]));
    }
    switch (tag) {
      case Tag::Equiv: {
        const VertexId a = r.id("id1");
        const VertexId b = r.id("id2");
        r.expect_end();
        if (a != b) add_equiv(equiv, a, b);
        break;
      }
      case Tag::Fix: {
        fix_records.emplace_back(r.id("id"), line_no);
        while (!r.at_end()) fix_records.emplace_back(r.id("id"), line_no);
        break;
      }
      case Tag::Vertex2:
      case Tag::Vertex3:
      case Tag::Vertex3Quat: {
        const VertexId id = r.id("id");
        if constexpr (!k3d) {
          const double x = r.number("x"), y = r.number("y"), th = r.number("theta");
          r.expect_end();
          vertex_poses.emplace_back(id, SE2d(SO2d::from_angle(th), Eigen::Vector2d(x, y)));
        } else if (tag == Tag::Vertex3) {
          const double x = r.number("x"), y = r.number("y"), z = r.number("z");
          const double roll = r.number("roll"), pitch = r.number("pitch"), yaw = r.number("yaw");
          r.expect_end();
          vertex_poses.emplace_back(
              id, SE3d(SO3d::from_unnormalized(quaternion_from_rpy(roll, pitch, yaw)),
                       Eigen::Vector3d(x, y, z)));
        } else {
          const double x = r.number("x"), y = r.number("y"), z = r.number("z");
          const double qx = r.number("qx"), qy = r.number("qy"), qz = r.number("qz"),
                       qw = r.number("qw");
          r.expect_end();
          vertex_poses.emplace_back(id, se3_from_quaternion(r, x, y, z, qx, qy, qz, qw));
        }
        vertex_records.push_back({id, line_no});
        break;
      }
      case Tag::Edge2Toro:
      case Tag::Edge2G2o:
      case Tag::Edge3Toro:
      case Tag::Edge3Quat: {
        EdgeRecord<PoseT> rec;
        rec.line = line_no;
        rec.edge.from = r.id("from");
        rec.edge.to = r.id("to");
        if (rec.edge.from == rec.edge.to) {
          r.fail("to", fmt::format("edge {} -> {} is a self loop", rec.edge.from, rec.edge.to));
        }
        auto& info = rec.edge.information;
        if constexpr (!k3d) {
          const double x = r.number("dx"), y = r.number("dy"), th = r.number("dtheta");
          rec.edge.measurement = SE2d(SO2d::from_angle(th), Eigen::Vector2d(x, y));
          const char* const* names = tag == Tag::Edge2Toro ? kInfo2Toro : kInfo2G2o;
          double v[6];
          for (int k = 0; k < 6; ++k) v[k] = r.number(names[k]);
          if (tag == Tag::Edge2Toro) {
            info << v[0], v[1], v[4], v[1], v[2], v[5], v[4], v[5], v[3];
          } else {
            info << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
          }
          r.expect_end();
        } else {
          const double x = r.number("dx"), y = r.number("dy"), z = r.number("dz");
          if (tag == Tag::Edge3Toro) {
            const double roll = r.number("roll"), pitch = r.number("pitch"),
                         yaw = r.number("yaw");
            rec.edge.measurement =
                SE3d(SO3d::from_unnormalized(quaternion_from_rpy(roll, pitch, yaw)),
                     Eigen::Vector3d(x, y, z));
          } else {
            const double qx = r.number("qx"), qy = r.number("qy"), qz = r.number("qz"),
                         qw = r.number("qw");
            rec.edge.measurement = se3_from_quaternion(r, x, y, z, qx, qy, qz, qw);
          }
          if (r.at_end()) {
            info.setIdentity();
          } else {
            read_upper_triangle<6>(r, info);
            r.expect_end();
            if (tag == Tag::Edge3Toro) {
              // Euler-angle information → information on q.xyz ≈ ω/2.
              Eigen::Matrix<double, 6, 1> s;
              s << 1, 1, 1, 2, 2, 2;
              info = s.asDiagonal() * info * s.asDiagonal();
            }
          }
        }
        ++report.edges;
        if (auto problem = information_problem<PoseT::kDof>(info)) {
          ++bad_information;
          if (!first_bad_information) {
            first_bad_information.emplace(
                line_no, fmt::format("edge {} -> {}: {}", rec.edge.from, rec.edge.to, *problem));
          }
          if (options.repair_information == InformationRepair::None) break;
          info = nearest_positive_definite<PoseT::kDof>(info, options.repair_floor);
          if (auto still = information_problem<PoseT::kDof>(info)) {
            r.fail("information", fmt::format("{} even after the nearest-psd repair", *still));
          }
          ++report.repaired_edges;
          if (!report.first_repaired_line) report.first_repaired_line = line_no;
        }
        edge_records.push_back(std::move(rec));
        break;
      }
    }
  }

  auto fail_at = [&](std::size_t line, std::string_view field, const std::string& problem) {
    throw ParseError({std::string(source), line, std::nullopt, std::string(field)}, problem);
  };
  if (bad_information > 0 && options.repair_information == InformationRepair::None) {
    fail_at(first_bad_information->first, "information",
            fmt::format("{}; {} of {} edges have an information matrix that is not positive "
                        "definite (the repair option GraphReadOptions::repair_information, "
                        "--repair-information nearest-psd on the command line, replaces each "
                        "by the nearest positive definite matrix)",
                        first_bad_information->second, bad_information, report.edges));
  }
  auto mapped = [&](VertexId id) { return equiv.empty() ? id : find_root(equiv, id); };

  // Vertices (a duplicated id is an error even when EQUIV maps it elsewhere).
  {
    std::map<VertexId, std::size_t> seen;
    for (std::size_t k = 0; k < vertex_records.size(); ++k) {
      const auto [it, inserted] = seen.emplace(vertex_records[k].id, vertex_records[k].line);
      if (!inserted) {
        fail_at(vertex_records[k].line, "id",
                fmt::format("vertex {} defined twice (first on line {})", vertex_records[k].id,
                            it->second));
      }
      const VertexId id = mapped(vertex_poses[k].first);
      if (!graph.has_vertex(id)) graph.add_vertex(id, vertex_poses[k].second);
    }
  }
  const bool from_odometry = vertex_records.empty();
  for (auto& rec : edge_records) {
    const VertexId raw_from = rec.edge.from, raw_to = rec.edge.to;
    rec.edge.from = mapped(raw_from);
    rec.edge.to = mapped(raw_to);
    if (rec.edge.from == rec.edge.to) {
      ++report.merged_edges_dropped;  // merged by EQUIV
      continue;
    }
    for (const VertexId id : {rec.edge.from, rec.edge.to}) {
      if (!graph.has_vertex(id)) {
        if (from_odometry) {
          graph.add_vertex(id, PoseT());
        } else {
          fail_at(rec.line, id == rec.edge.from ? "from" : "to",
                  fmt::format("edge {} -> {} refers to vertex {}, which the file does not define",
                              raw_from, raw_to, id));
        }
      }
    }
    graph.add_edge(rec.edge);
  }
  for (const auto& [raw, line] : fix_records) {
    const VertexId id = mapped(raw);
    if (!graph.has_vertex(id)) {
      fail_at(line, "id", fmt::format("FIX names vertex {}, which does not exist", raw));
    }
    graph.set_fixed(id, true);
  }
  if (from_odometry && graph.num_edges() > 0) {
    initialize_odometry(graph);
    report.built_from_odometry = true;
  }
  if (report_out) *report_out = report;
  return graph;
}

// ---------------------------------------------------------------------------
// Text writing

// Numbers are written in their shortest form that reads back exactly
// (std::to_chars), straight into the output.
void put(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out += ' ';
  out.append(buf, r.ptr);
}
void put_id(std::string& out, VertexId v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out += ' ';
  out.append(buf, r.ptr);
}

void append_info_upper(std::string& out, const Eigen::Matrix<double, 6, 6>& m) {
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) put(out, m(i, j));
}

void append_fixed(std::string& out, const auto& graph) {
  for (const auto& [id, v] : graph.vertices()) {
    if (!v.fixed) continue;
    out += "FIX";
    put_id(out, id);
    out += '\n';
  }
}

std::string format_2d(const PoseGraph2D& graph, GraphFileFormat format) {
  ROVE_CHECK_MSG(format == GraphFileFormat::Toro || format == GraphFileFormat::G2o,
                 "format_graph writes only the text formats (Toro or G2o)");
  const bool toro = format == GraphFileFormat::Toro;
  std::string out;
  out.reserve(64 * (graph.num_vertices() + 2 * graph.num_edges()));
  for (const auto& [id, v] : graph.vertices()) {
    const auto& t = v.pose.translation();
    out += toro ? "VERTEX2" : "VERTEX_SE2";
    put_id(out, id);
    put(out, t.x());
    put(out, t.y());
    put(out, v.pose.angle());
    out += '\n';
  }
  for (const auto& e : graph.edges()) {
    const auto& t = e.measurement.translation();
    const auto& I = e.information;
    out += toro ? "EDGE2" : "EDGE_SE2";
    put_id(out, e.from);
    put_id(out, e.to);
    put(out, t.x());
    put(out, t.y());
    put(out, e.measurement.angle());
    if (toro) {  // inf_xx inf_xy inf_yy inf_pp inf_xp inf_yp
      for (const auto& [i, j] : {std::pair{0, 0}, {0, 1}, {1, 1}, {2, 2}, {0, 2}, {1, 2}})
        put(out, I(i, j));
    } else {  // upper triangle, row by row
      for (const auto& [i, j] : {std::pair{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}})
        put(out, I(i, j));
    }
    out += '\n';
  }
  append_fixed(out, graph);
  return out;
}

std::string format_3d(const PoseGraph3D& graph, GraphFileFormat format) {
  ROVE_CHECK_MSG(format == GraphFileFormat::Toro || format == GraphFileFormat::G2o,
                 "format_graph writes only the text formats (Toro or G2o)");
  const bool toro = format == GraphFileFormat::Toro;
  std::string out;
  out.reserve(128 * (graph.num_vertices() + 3 * graph.num_edges()));
  auto pose_fields = [&](const SE3d& p) {
    const auto& t = p.translation();
    put(out, t.x());
    put(out, t.y());
    put(out, t.z());
    if (toro) {
      const Eigen::Vector3d rpy = rpy_from_matrix(p.rotation_matrix());
      for (int k = 0; k < 3; ++k) put(out, rpy(k));
    } else {
      const auto& q = p.quaternion();
      put(out, q.x());
      put(out, q.y());
      put(out, q.z());
      put(out, q.w());
    }
  };
  for (const auto& [id, v] : graph.vertices()) {
    out += toro ? "VERTEX3" : "VERTEX_SE3:QUAT";
    put_id(out, id);
    pose_fields(v.pose);
    out += '\n';
  }
  Eigen::Matrix<double, 6, 1> s_inv;
  s_inv << 1, 1, 1, 0.5, 0.5, 0.5;
  for (const auto& e : graph.edges()) {
    out += toro ? "EDGE3" : "EDGE_SE3:QUAT";
    put_id(out, e.from);
    put_id(out, e.to);
    pose_fields(e.measurement);
    if (toro) {
      append_info_upper(out, s_inv.asDiagonal() * e.information * s_inv.asDiagonal());
    } else {
      append_info_upper(out, e.information);
    }
    out += '\n';
  }
  append_fixed(out, graph);
  return out;
}

// ---------------------------------------------------------------------------
// Binary

// The whole (decompressed) file, refusing what is not a regular file and
// stopping at max_bytes: /dev/zero or a gzip bomb must not grow without end.
std::vector<std::byte> read_all(const std::string& path, std::uint64_t max_bytes) {
  check_regular_input(path, "graph");
  auto in = open_input_file(path);
  std::vector<std::byte> data;
  std::byte buf[1 << 16];
  for (;;) {
    const std::size_t n = in->read_some(buf);
    if (n == 0) break;
    if (data.size() + n > max_bytes) {
      throw IoError(path, fmt::format("the graph is larger than the {} limit of the reader "
                                      "(GraphReadOptions::max_bytes)",
                                      format_bytes(max_bytes)));
    }
    if (data.size() + n > data.capacity()) {
      const std::uint64_t next = std::max<std::uint64_t>(2 * data.capacity(), data.size() + n);
      check_memory_budget(next, fmt::format("graph file {}", printable(path)));
      data.reserve(static_cast<std::size_t>(next));
    }
    data.insert(data.end(), buf, buf + n);
  }
  return data;
}

bool has_binary_magic(const std::vector<std::byte>& data) {
  return data.size() >= sizeof(kBinaryMagic) &&
         std::memcmp(data.data(), kBinaryMagic, sizeof(kBinaryMagic)) == 0;
}

template <class PoseT>
void write_pose(OutArchive& ar, const PoseT& p) {
  if constexpr (PoseT::kDof == 3) {
    ar.write_scalar(p.translation().x());
    ar.write_scalar(p.translation().y());
    ar.write_scalar(p.angle());
  } else {
    for (int k = 0; k < 3; ++k) ar.write_scalar(p.translation()(k));
    const auto& q = p.quaternion();
    ar.write_scalar(q.w());
    ar.write_scalar(q.x());
    ar.write_scalar(q.y());
    ar.write_scalar(q.z());
  }
}

template <class PoseT>
PoseT read_pose(InArchive& ar, std::string_view field) {
  const std::uint64_t at = ar.offset();
  auto fail = [&](const std::string& what) -> PoseT {
    throw ParseError({ar.source_name(), std::nullopt, at, std::string(field)}, what);
  };
  if constexpr (PoseT::kDof == 3) {
    double v[3];
    ar.read_scalars(std::span<double>(v, 3), field);
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      return fail("pose has a non-finite value");
    }
    return SE2d(SO2d::from_angle(v[2]), Eigen::Vector2d(v[0], v[1]));
  } else {
    double v[7];
    ar.read_scalars(std::span<double>(v, 7), field);
    for (double x : v)
      if (!std::isfinite(x)) return fail("pose has a non-finite value");
    const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
    if (std::abs(norm - 1.0) > 1e-6) return fail(fmt::format("quaternion norm {} is not 1", norm));
    return SE3d(SO3d::from_unnormalized(Eigen::Quaterniond(v[3], v[4], v[5], v[6])),
                Eigen::Vector3d(v[0], v[1], v[2]));
  }
}

template <class PoseT>
void save_graph(OutArchive& ar, const PoseGraph<PoseT>& graph) {
  constexpr int N = PoseT::kDof;
  ar.write_bytes(std::as_bytes(std::span<const char>(kBinaryMagic, sizeof(kBinaryMagic))));
  write_version(ar, kBinaryVersion);
  ar.write_scalar(static_cast<std::uint8_t>(N == 3 ? 2 : 3));
  ar.write_length(graph.num_vertices(), "vertices");
  for (const auto& [id, v] : graph.vertices()) {
    ar.write_scalar(static_cast<std::uint64_t>(id));
    ar.write_scalar(v.fixed);
    write_pose(ar, v.pose);
  }
  ar.write_length(graph.num_edges(), "edges");
  for (const auto& e : graph.edges()) {
    ar.write_scalar(static_cast<std::uint64_t>(e.from));
    ar.write_scalar(static_cast<std::uint64_t>(e.to));
    write_pose(ar, e.measurement);
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j) ar.write_scalar(e.information(i, j));
    ar.write_scalar(static_cast<std::int32_t>(e.level));
    ar.write_scalar(static_cast<std::uint8_t>(e.kernel.type()));
    ar.write_scalar(e.kernel.parameter());
  }
}

template <class PoseT>
void load_graph(InArchive& ar, PoseGraph<PoseT>& graph) {
  constexpr int N = PoseT::kDof;
  auto fail = [&](std::uint64_t at, std::string_view field, const std::string& what) {
    throw ParseError({ar.source_name(), std::nullopt, at, std::string(field)}, what);
  };
  char magic[sizeof(kBinaryMagic)];
  ar.read_bytes(std::as_writable_bytes(std::span<char>(magic, sizeof(magic))), "magic");
  if (std::memcmp(magic, kBinaryMagic, sizeof(magic)) != 0) {
    fail(0, "magic", "not a rove pose-graph file (bad magic bytes)");
  }
  read_version(ar, "PoseGraph", kBinaryVersion);
  const std::uint64_t dim_at = ar.offset();
  const auto dim = ar.read_scalar<std::uint8_t>("dimension");
  if (dim != (N == 3 ? 2 : 3)) {
    fail(dim_at, "dimension",
         fmt::format("file holds a {}D graph, a {}D graph was asked for", dim, N == 3 ? 2 : 3));
  }
  PoseGraph<PoseT> out;
  constexpr std::uint64_t pose_bytes = N == 3 ? 24 : 56;
  const std::uint32_t nv = ar.read_length("vertices", 9 + pose_bytes);
  for (std::uint32_t k = 0; k < nv; ++k) {
    const std::uint64_t at = ar.offset();
    const auto id = ar.read_scalar<std::uint64_t>("vertex id");
    const bool fixed = ar.read_scalar<bool>("fixed");
    const PoseT pose = read_pose<PoseT>(ar, "vertex pose");
    if (out.has_vertex(id)) fail(at, "vertex id", fmt::format("vertex {} defined twice", id));
    out.add_vertex(id, pose, fixed);
  }
  const std::uint32_t ne = ar.read_length("edges", 16 + pose_bytes + 8 * (N * (N + 1) / 2) + 13);
  for (std::uint32_t k = 0; k < ne; ++k) {
    const std::uint64_t at = ar.offset();
    PoseGraphEdge<PoseT> e;
    e.from = ar.read_scalar<std::uint64_t>("edge from");
    e.to = ar.read_scalar<std::uint64_t>("edge to");
    e.measurement = read_pose<PoseT>(ar, "edge measurement");
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j) e.information(i, j) = e.information(j, i) =
          ar.read_scalar<double>("information");
    e.level = ar.read_scalar<std::int32_t>("level");
    const std::uint64_t kernel_at = ar.offset();
    const auto type = ar.read_scalar<std::uint8_t>("kernel type");
    const double param = ar.read_scalar<double>("kernel parameter");
    if (type > static_cast<std::uint8_t>(RobustKernelType::Dcs)) {
      fail(kernel_at, "kernel type", fmt::format("unknown robust kernel type {}", type));
    }
    const auto kt = static_cast<RobustKernelType>(type);
    if (kt != RobustKernelType::Trivial) {
      if (!(std::isfinite(param) && param > 0.0)) {
        fail(kernel_at, "kernel parameter",
             fmt::format("robust kernel parameter {} is not finite and > 0", param));
      }
      e.kernel = RobustKernel(kt, param);
    }
    if (!out.has_vertex(e.from) || !out.has_vertex(e.to)) {
      fail(at, "edge", fmt::format("edge {} -> {} refers to a missing vertex", e.from, e.to));
    }
    if (e.from == e.to) fail(at, "edge", fmt::format("edge {} -> {} is a self loop", e.from, e.to));
    if (auto problem = information_problem<N>(e.information)) fail(at, "information", *problem);
    out.add_edge(e);
  }
  graph = std::move(out);
}

template <class PoseT>
PoseGraph<PoseT> read_graph(const std::string& path, const GraphReadOptions& options,
                            GraphReadReport* report) {
  const std::vector<std::byte> data = read_all(path, options.max_bytes);
  if (has_binary_magic(data)) {
    MemoryInStream stream(std::span<const std::byte>(data), path);
    InArchive ar(stream);
    PoseGraph<PoseT> graph;
    load_graph(ar, graph);
    if (report) {
      *report = GraphReadReport{};
      report->edges = graph.num_edges();
    }
    return graph;
  }
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  return parse_text<PoseT>(text, path, options, report);
}

GraphFileFormat format_for_path(const std::string& path, GraphFileFormat format) {
  if (format != GraphFileFormat::Auto) return format;
  auto ends_with = [&](std::string_view suffix) {
    return path.size() >= suffix.size() &&
           iequals(std::string_view(path).substr(path.size() - suffix.size()), suffix);
  };
  if (ends_with(".g2o")) return GraphFileFormat::G2o;
  if (ends_with(".rpg") || ends_with(".rpg.gz") || ends_with(".bin")) return GraphFileFormat::Binary;
  return GraphFileFormat::Toro;
}

template <class PoseT>
void write_graph_impl(const PoseGraph<PoseT>& graph, const std::string& path,
                      GraphFileFormat format) {
  format = format_for_path(path, format);
  if (format == GraphFileFormat::Binary) {
    write_file_atomically(path, [&](const std::filesystem::path& tmp) {
      GzipFileOutStream out(tmp.string());
      OutArchive ar(out);
      save_graph(ar, graph);
      out.close();
    });
    return;
  }
  write_text_file_atomically(path, format_graph(graph, format));
}

}  // namespace

GraphDimension detect_graph_dimension(const std::string& path, std::uint64_t max_bytes) {
  const std::vector<std::byte> data = read_all(path, max_bytes);
  if (has_binary_magic(data)) {
    const std::size_t at = sizeof(kBinaryMagic) + 1;
    if (data.size() <= at) return GraphDimension::Unknown;
    const auto dim = std::to_integer<unsigned>(data[at]);
    return dim == 2 ? GraphDimension::TwoD : dim == 3 ? GraphDimension::ThreeD
                                                      : GraphDimension::Unknown;
  }
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  std::vector<std::string_view> tokens;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    split_tokens(text.substr(pos, end - pos), tokens);
    pos = end + 1;
    Tag tag;
    if (tokens.empty() || !tag_from_text(tokens[0], tag)) continue;
    if (is_2d_tag(tag)) return GraphDimension::TwoD;
    if (is_3d_tag(tag)) return GraphDimension::ThreeD;
  }
  return GraphDimension::Unknown;
}

PoseGraph2D read_graph_2d(const std::string& path, const GraphReadOptions& options,
                          GraphReadReport* report) {
  return read_graph<SE2d>(path, options, report);
}
PoseGraph3D read_graph_3d(const std::string& path, const GraphReadOptions& options,
                          GraphReadReport* report) {
  return read_graph<SE3d>(path, options, report);
}

PoseGraph2D parse_graph_2d(std::string_view text, std::string_view source,
                           const GraphReadOptions& options, GraphReadReport* report) {
  return parse_text<SE2d>(text, source, options, report);
}
PoseGraph3D parse_graph_3d(std::string_view text, std::string_view source,
                           const GraphReadOptions& options, GraphReadReport* report) {
  return parse_text<SE3d>(text, source, options, report);
}

std::string_view to_string(InformationRepair repair) {
  switch (repair) {
    case InformationRepair::None: return "none";
    case InformationRepair::NearestPsd: return "nearest-psd";
  }
  return "?";
}

std::optional<InformationRepair> parse_information_repair(std::string_view text) {
  if (text == "none") return InformationRepair::None;
  if (text == "nearest-psd") return InformationRepair::NearestPsd;
  return std::nullopt;
}

std::string format_graph(const PoseGraph2D& graph, GraphFileFormat format) {
  return format_2d(graph, format);
}
std::string format_graph(const PoseGraph3D& graph, GraphFileFormat format) {
  return format_3d(graph, format);
}

void write_graph(const PoseGraph2D& graph, const std::string& path, GraphFileFormat format) {
  write_graph_impl(graph, path, format);
}
void write_graph(const PoseGraph3D& graph, const std::string& path, GraphFileFormat format) {
  write_graph_impl(graph, path, format);
}

void save(OutArchive& ar, const PoseGraph2D& graph) { save_graph(ar, graph); }
void load(InArchive& ar, PoseGraph2D& graph) { load_graph(ar, graph); }
void save(OutArchive& ar, const PoseGraph3D& graph) { save_graph(ar, graph); }
void load(InArchive& ar, PoseGraph3D& graph) { load_graph(ar, graph); }

}  // namespace rove
