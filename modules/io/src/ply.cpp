#include "rove/io/ply.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>

#include <fmt/format.h>

#include "pcd_io_common.h"
#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/io/file_bytes.h"

namespace rove {

namespace {

using detail::ScalarKind;

[[noreturn]] void fail_line(std::string_view src, std::size_t line, std::string field, std::string msg) {
  throw ParseError({std::string(src), line, std::nullopt, std::move(field)}, std::move(msg));
}
[[noreturn]] void fail_offset(std::string_view src, std::uint64_t off, std::string field, std::string msg) {
  throw ParseError({std::string(src), std::nullopt, off, std::move(field)}, std::move(msg));
}

std::optional<ScalarKind> parse_type(std::string_view t) {
  if (t == "char" || t == "int8") return ScalarKind::I8;
  if (t == "uchar" || t == "uint8") return ScalarKind::U8;
  if (t == "short" || t == "int16") return ScalarKind::I16;
  if (t == "ushort" || t == "uint16") return ScalarKind::U16;
  if (t == "int" || t == "int32") return ScalarKind::I32;
  if (t == "uint" || t == "uint32") return ScalarKind::U32;
  if (t == "float" || t == "float32") return ScalarKind::F32;
  if (t == "double" || t == "float64") return ScalarKind::F64;
  return std::nullopt;
}

bool is_float(ScalarKind k) { return k == ScalarKind::F32 || k == ScalarKind::F64; }

struct Property {
  std::string name;
  ScalarKind type = ScalarKind::F32;
  bool is_list = false;
  ScalarKind count_type = ScalarKind::U8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  std::size_t line = 0;
};

enum Slot { kX, kY, kZ, kR, kG, kB, kI, kNx, kNy, kNz, kSlots };

int slot_of(std::string_view n) {
  if (n == "x") return kX;
  if (n == "y") return kY;
  if (n == "z") return kZ;
  if (n == "red" || n == "r") return kR;
  if (n == "green" || n == "g") return kG;
  if (n == "blue" || n == "b") return kB;
  if (n == "intensity" || n == "scalar_intensity") return kI;
  if (n == "nx" || n == "normal_x") return kNx;
  if (n == "ny" || n == "normal_y") return kNy;
  if (n == "nz" || n == "normal_z") return kNz;
  return -1;
}

std::uint8_t to_color(double v, ScalarKind k) {
  if (is_float(k)) v *= 255.0;
  if (!(v >= 0)) return 0;  // also NaN
  if (v >= 255) return 255;
  return static_cast<std::uint8_t>(std::lround(v));
}

/// Where each slot comes from in the vertex element (-1: absent).
struct VertexMap {
  int prop_of[kSlots];
  PointChannels channels = PointChannels::None;
};

VertexMap map_vertex(const Element& e, std::string_view src) {
  VertexMap m;
  std::fill(std::begin(m.prop_of), std::end(m.prop_of), -1);
  for (std::size_t i = 0; i < e.props.size(); ++i) {
    const int s = slot_of(e.props[i].name);
    if (s < 0) continue;
    if (e.props[i].is_list) fail_line(src, e.line, e.props[i].name, "must be a scalar property, not a list");
    if (m.prop_of[s] >= 0) fail_line(src, e.line, e.props[i].name, "property appears twice");
    m.prop_of[s] = static_cast<int>(i);
  }
  for (int s : {kX, kY, kZ})
    if (m.prop_of[s] < 0)
      fail_line(src, e.line, s == kX ? "x" : s == kY ? "y" : "z", "the vertex element has no such property");
  if (m.prop_of[kR] >= 0 && m.prop_of[kG] >= 0 && m.prop_of[kB] >= 0) m.channels = m.channels | PointChannels::Color;
  if (m.prop_of[kI] >= 0) m.channels = m.channels | PointChannels::Intensity;
  if (m.prop_of[kNx] >= 0 && m.prop_of[kNy] >= 0 && m.prop_of[kNz] >= 0)
    m.channels = m.channels | PointChannels::Normal;
  return m;
}

void store_vertex(PointCloud& c, const VertexMap& m, const Element& e, const double* v) {
  (void)e;
  const std::size_t i = c.push_back(Eigen::Vector3f(static_cast<float>(v[m.prop_of[kX]]),
                                                    static_cast<float>(v[m.prop_of[kY]]),
                                                    static_cast<float>(v[m.prop_of[kZ]])));
  if (c.has_colors())
    c.colors_mut()[i] = Rgb8{to_color(v[m.prop_of[kR]], e.props[static_cast<std::size_t>(m.prop_of[kR])].type),
                             to_color(v[m.prop_of[kG]], e.props[static_cast<std::size_t>(m.prop_of[kG])].type),
                             to_color(v[m.prop_of[kB]], e.props[static_cast<std::size_t>(m.prop_of[kB])].type)};
  if (c.has_intensity()) c.intensities_mut()[i] = static_cast<float>(v[m.prop_of[kI]]);
  if (c.has_normals())
    c.normals_mut()[i] = Eigen::Vector3f(static_cast<float>(v[m.prop_of[kNx]]), static_cast<float>(v[m.prop_of[kNy]]),
                                         static_cast<float>(v[m.prop_of[kNz]]));
}

/// Reads one ascii token as a number of the property's type.
double ascii_value(std::string_view t, ScalarKind k, std::string_view src, std::size_t line, const std::string& name) {
  if (is_float(k)) {
    const char* b = t.data();
    if (!t.empty() && *b == '+') ++b;
    double v;
    const auto r = std::from_chars(b, t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail_line(src, line, name, fmt::format("'{}' is not a number", t));
    // Out of range only if it rounds to infinity: |v| >= FLT_MAX + half an ulp
    // (2^128 - 2^103). "3.4028235e+38", the shortest text of FLT_MAX, is above
    // FLT_MAX itself (fuzz finding, test Ply.AsciiFltMaxReadsBack).
    if (k == ScalarKind::F32 && std::isfinite(v) && std::fabs(v) >= 3.4028235677973366e38)
      fail_line(src, line, name, fmt::format("'{}' is out of the float range", t));
    if (k == ScalarKind::F32) {
      // Parse as float directly so the value is correctly rounded once.
      float f;
      const auto rf = std::from_chars(b, t.data() + t.size(), f);
      if (rf.ec == std::errc()) return f;
    }
    return v;
  }
  const bool is_signed = k == ScalarKind::I8 || k == ScalarKind::I16 || k == ScalarKind::I32;
  const int bits = static_cast<int>(detail::scalar_size(k)) * 8;
  if (is_signed) {
    std::int64_t v;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || v < -(std::int64_t{1} << (bits - 1)) ||
        v >= (std::int64_t{1} << (bits - 1)))
      fail_line(src, line, name, fmt::format("'{}' is not a {}-bit integer", t, bits));
    return static_cast<double>(v);
  }
  std::uint64_t v;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size() || v >= (std::uint64_t{1} << bits))
    fail_line(src, line, name, fmt::format("'{}' is not a {}-bit unsigned integer", t, bits));
  return static_cast<double>(v);
}

}  // namespace

PointCloud read_ply_from_memory(std::span<const std::uint8_t> bytes, std::string_view src) {
  ROVE_TRACE_BEGIN
  const std::string_view all(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::size_t pos = 0, line_no = 0;
  std::vector<std::string_view> tok;
  auto next_line = [&]() -> std::optional<std::string_view> {
    if (pos >= all.size()) return std::nullopt;
    ++line_no;
    std::size_t eol = all.find('\n', pos);
    const std::size_t next = eol == std::string_view::npos ? all.size() : eol + 1;
    if (eol == std::string_view::npos) eol = all.size();
    const std::string_view l = all.substr(pos, eol - pos);
    pos = next;
    return l;
  };
  auto first = next_line();
  detail::split_tokens(first.value_or(""), tok);
  if (tok.size() != 1 || tok[0] != "ply") fail_line(src, 1, "ply", "not a PLY file (first line must be 'ply')");

  std::optional<PlyFormat> format;
  std::vector<Element> elements;
  bool ended = false;
  while (!ended) {
    auto l = next_line();
    if (!l) fail_line(src, line_no + 1, "end_header", "the header ends without end_header");
    detail::split_tokens(*l, tok);
    if (tok.empty()) continue;
    const std::string_view key = tok[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (tok.size() != 3) fail_line(src, line_no, "format", "expects: format <encoding> <version>");
      if (tok[1] == "ascii") format = PlyFormat::Ascii;
      else if (tok[1] == "binary_little_endian") format = PlyFormat::BinaryLittleEndian;
      else if (tok[1] == "binary_big_endian") format = PlyFormat::BinaryBigEndian;
      else fail_line(src, line_no, "format", fmt::format("unknown encoding '{}'", tok[1]));
      if (tok[2] != "1.0") fail_line(src, line_no, "format", fmt::format("unsupported version '{}'", tok[2]));
    } else if (key == "element") {
      if (tok.size() != 3) fail_line(src, line_no, "element", "expects: element <name> <count>");
      Element e;
      e.name = std::string(tok[1]);
      e.line = line_no;
      const auto r = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
      if (r.ec != std::errc() || r.ptr != tok[2].data() + tok[2].size())
        fail_line(src, line_no, e.name, fmt::format("count '{}' is not an unsigned integer", tok[2]));
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty()) fail_line(src, line_no, "property", "property before any element");
      Property p;
      if (tok.size() == 5 && tok[1] == "list") {
        const auto ct = parse_type(tok[2]);
        const auto it = parse_type(tok[3]);
        if (!ct || is_float(*ct)) fail_line(src, line_no, std::string(tok[4]), fmt::format("bad list count type '{}'", tok[2]));
        if (!it) fail_line(src, line_no, std::string(tok[4]), fmt::format("unknown type '{}'", tok[3]));
        p.is_list = true;
        p.count_type = *ct;
        p.type = *it;
        p.name = std::string(tok[4]);
      } else if (tok.size() == 3) {
        const auto t = parse_type(tok[1]);
        if (!t) fail_line(src, line_no, std::string(tok[2]), fmt::format("unknown type '{}'", tok[1]));
        p.type = *t;
        p.name = std::string(tok[2]);
      } else {
        fail_line(src, line_no, "property", "expects: property <type> <name> or property list <type> <type> <name>");
      }
      elements.back().props.push_back(std::move(p));
    } else if (key == "end_header") {
      ended = true;
    } else {
      fail_line(src, line_no, std::string(key), "unknown header line");
    }
  }
  if (!format) fail_line(src, line_no, "format", "the header has no format line");
  const Element* vertex = nullptr;
  for (const auto& e : elements)
    if (e.name == "vertex") {
      if (vertex) fail_line(src, e.line, "vertex", "two vertex elements");
      vertex = &e;
    }
  if (!vertex) fail_line(src, line_no, "vertex", "the file has no vertex element");
  const VertexMap vm = map_vertex(*vertex, src);

  PointCloud cloud;
  cloud.set_channels(vm.channels);
  const std::size_t data_start = pos;
  std::vector<double> values;

  if (*format == PlyFormat::Ascii) {
    // Elements are read as a stream of tokens, one instance after the other.
    std::size_t tpos = 0;
    std::vector<std::string_view> line_tok;
    auto next_token = [&](const std::string& what) -> std::string_view {
      while (tpos >= line_tok.size()) {
        auto l = next_line();
        if (!l) fail_line(src, line_no + 1, what, "the data ends early");
        detail::split_tokens(*l, line_tok);
        tpos = 0;
      }
      return line_tok[tpos++];
    };
    for (const auto& e : elements) {
      const bool is_vertex = &e == vertex;
      if (is_vertex) cloud.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(e.count, (all.size() - data_start) / 2)));
      if (e.props.empty()) continue;
      for (std::uint64_t n = 0; n < e.count; ++n) {
        values.assign(e.props.size(), 0.0);
        for (std::size_t k = 0; k < e.props.size(); ++k) {
          const Property& p = e.props[k];
          if (p.is_list) {
            const double len = ascii_value(next_token(p.name), p.count_type, src, line_no, p.name);
            if (!(len >= 0)) fail_line(src, line_no, p.name, fmt::format("negative list length {}", len));
            for (std::uint64_t j = 0; j < static_cast<std::uint64_t>(len); ++j)
              (void)ascii_value(next_token(p.name), p.type, src, line_no, p.name);
          } else {
            values[k] = ascii_value(next_token(p.name), p.type, src, line_no, p.name);
          }
        }
        if (is_vertex) store_vertex(cloud, vm, e, values.data());
      }
    }
  } else {
    const bool swap = (*format == PlyFormat::BinaryBigEndian) != (std::endian::native == std::endian::big);
    std::size_t off = data_start;
    auto need = [&](std::uint64_t n, const std::string& what) {
      if (n > bytes.size() - off)
        fail_offset(src, off, what, fmt::format("needs {} bytes, {} left in the file", n, bytes.size() - off));
    };
    for (const auto& e : elements) {
      const bool is_vertex = &e == vertex;
      if (e.props.empty()) continue;
      std::uint64_t min_size = 0;
      for (const auto& p : e.props) min_size += detail::scalar_size(p.is_list ? p.count_type : p.type);
      std::uint64_t total = 0;
      if (__builtin_mul_overflow(e.count, min_size, &total)) total = UINT64_MAX;
      need(total, e.name);  // a lying count is refused before looping or allocating
      if (is_vertex) cloud.reserve(static_cast<std::size_t>(e.count));
      for (std::uint64_t n = 0; n < e.count; ++n) {
        values.assign(e.props.size(), 0.0);
        for (std::size_t k = 0; k < e.props.size(); ++k) {
          const Property& p = e.props[k];
          if (p.is_list) {
            const std::size_t cs = detail::scalar_size(p.count_type);
            need(cs, p.name);
            const double len = detail::load_scalar(bytes.data() + off, p.count_type, swap);
            if (!(len >= 0)) fail_offset(src, off, p.name, fmt::format("negative list length {}", len));
            off += cs;
            const std::uint64_t skip = static_cast<std::uint64_t>(len) * detail::scalar_size(p.type);
            need(skip, p.name);
            off += static_cast<std::size_t>(skip);
          } else {
            const std::size_t s = detail::scalar_size(p.type);
            need(s, p.name);
            values[k] = detail::load_scalar(bytes.data() + off, p.type, swap);
            off += s;
          }
        }
        if (is_vertex) store_vertex(cloud, vm, e, values.data());
      }
    }
  }
  return cloud;
  ROVE_TRACE_END
}

PointCloud read_ply(const std::string& path) {
  const std::vector<std::uint8_t> bytes = read_file_bytes(path, 0, "point cloud");
  return read_ply_from_memory(bytes, path);
}

std::vector<std::uint8_t> write_ply_to_memory(const PointCloud& cloud, const PlyWriteOptions& o) {
  const bool rgb = o.write_colors && cloud.has_colors();
  const bool inten = o.write_intensity && cloud.has_intensity();
  const bool nrm = o.write_normals && cloud.has_normals();
  std::string head = fmt::format("ply\nformat {} 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
                                 o.format == PlyFormat::Ascii                ? "ascii"
                                 : o.format == PlyFormat::BinaryLittleEndian ? "binary_little_endian"
                                                                              : "binary_big_endian",
                                 cloud.size());
  if (rgb) head += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (inten) head += "property float intensity\n";
  if (nrm) head += "property float nx\nproperty float ny\nproperty float nz\n";
  head += "end_header\n";
  std::vector<std::uint8_t> out(head.begin(), head.end());
  if (o.format == PlyFormat::Ascii) {
    std::string body;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        if (k) body += ' ';
        detail::append_float(body, cloud[i][k]);
      }
      if (rgb) body += fmt::format(" {} {} {}", cloud.colors()[i].r, cloud.colors()[i].g, cloud.colors()[i].b);
      if (inten) {
        body += ' ';
        detail::append_float(body, cloud.intensities()[i]);
      }
      if (nrm)
        for (int k = 0; k < 3; ++k) {
          body += ' ';
          detail::append_float(body, cloud.normals()[i][k]);
        }
      body += '\n';
    }
    out.insert(out.end(), body.begin(), body.end());
  } else {
    const bool swap = (o.format == PlyFormat::BinaryBigEndian) != (std::endian::native == std::endian::big);
    auto put_f = [&](float v) {
      std::uint32_t b = std::bit_cast<std::uint32_t>(v);
      if (swap) b = __builtin_bswap32(b);
      const auto* p = reinterpret_cast<const std::uint8_t*>(&b);
      out.insert(out.end(), p, p + 4);
    };
    out.reserve(out.size() + cloud.size() * (12 + (rgb ? 3 : 0) + (inten ? 4 : 0) + (nrm ? 12 : 0)));
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      for (int k = 0; k < 3; ++k) put_f(cloud[i][k]);
      if (rgb) out.insert(out.end(), {cloud.colors()[i].r, cloud.colors()[i].g, cloud.colors()[i].b});
      if (inten) put_f(cloud.intensities()[i]);
      if (nrm)
        for (int k = 0; k < 3; ++k) put_f(cloud.normals()[i][k]);
    }
  }
  return out;
}

void write_ply(const std::string& path, const PointCloud& cloud, const PlyWriteOptions& options) {
  write_file_bytes(path, write_ply_to_memory(cloud, options));
}

}  // namespace rove
