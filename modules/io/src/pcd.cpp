#include "rove/io/pcd.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "pcd_io_common.h"
#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/io/file_bytes.h"
#include "rove/io/lzf.h"

static_assert(std::endian::native == std::endian::little,
              "the PCD reader and writer assume a little-endian host");

namespace rove {

namespace {

using detail::ScalarKind;

constexpr std::uint32_t kMaxFieldCount = 1u << 20;  // elements per field
constexpr std::size_t kMaxFields = 4096;

[[noreturn]] void fail_line(std::string_view src, std::size_t line, std::string field, std::string msg) {
  throw ParseError({std::string(src), line, std::nullopt, std::move(field)}, std::move(msg));
}
[[noreturn]] void fail_offset(std::string_view src, std::uint64_t off, std::string field, std::string msg) {
  throw ParseError({std::string(src), std::nullopt, off, std::move(field)}, std::move(msg));
}

template <typename T>
bool parse_number(std::string_view tok, T& out) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if constexpr (std::is_floating_point_v<T>) {
    // from_chars rejects a leading '+', which some writers emit.
    if (b != e && *b == '+') ++b;
  }
  auto r = std::from_chars(b, e, out);
  return r.ec == std::errc() && r.ptr == e;
}

ScalarKind kind_of(char type, std::uint32_t size) {
  switch (type) {
    case 'F': return size == 4 ? ScalarKind::F32 : ScalarKind::F64;
    case 'I': return size == 1 ? ScalarKind::I8 : size == 2 ? ScalarKind::I16 : size == 4 ? ScalarKind::I32 : ScalarKind::I64;
    default: return size == 1 ? ScalarKind::U8 : size == 2 ? ScalarKind::U16 : size == 4 ? ScalarKind::U32 : ScalarKind::U64;
  }
}

/// Which field feeds which channel, and where each field lives.
struct Layout {
  int x = -1, y = -1, z = -1, rgb = -1, intensity = -1, nx = -1, ny = -1, nz = -1;
  std::vector<std::size_t> record_offset;  // byte offset within a binary record
  std::vector<std::size_t> packed_offset;  // per-point byte offset among non-padding fields
  std::vector<std::size_t> token_index;    // first ascii token of the field
  std::vector<ScalarKind> kind;
  std::size_t record_size = 0;   // bytes per point, binary
  std::size_t packed_size = 0;   // bytes per point without '_' fields, compressed
  std::size_t tokens = 0;        // ascii tokens per point (padding included)
};

struct HeaderParse {
  PcdHeader header;
  std::size_t data_offset = 0;  // first byte after the DATA line
  std::size_t data_line = 0;    // line number of the first data line
};

HeaderParse parse_header(std::span<const std::uint8_t> bytes, std::string_view src) {
  HeaderParse out;
  PcdHeader& h = out.header;
  std::vector<std::string> names;
  std::vector<std::uint32_t> sizes, counts;
  std::vector<char> types;
  bool have_fields = false, have_size = false, have_type = false, have_count = false, have_width = false,
       have_height = false, have_points = false, have_data = false;
  std::size_t line_fields = 0, line_size = 0, line_type = 0, line_count = 0, line_points = 0;
  std::size_t pos = 0, line_no = 0;
  std::vector<std::string_view> tok;
  const std::string_view all(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  while (!have_data) {
    if (pos >= all.size()) fail_line(src, line_no + 1, "DATA", "the header ends without a DATA line");
    ++line_no;
    std::size_t eol = all.find('\n', pos);
    const std::size_t next = eol == std::string_view::npos ? all.size() : eol + 1;
    if (eol == std::string_view::npos) eol = all.size();
    std::string_view line = all.substr(pos, eol - pos);
    pos = next;
    detail::split_tokens(line, tok);
    if (tok.empty() || tok[0][0] == '#') continue;
    const std::string_view key = tok[0];
    const std::size_t nargs = tok.size() - 1;
    auto need_args = [&](std::size_t n) {
      if (nargs != n)
        fail_line(src, line_no, std::string(key), fmt::format("expects {} value(s), found {}", n, nargs));
    };
    auto parse_u32 = [&](std::string_view t, const char* what) {
      std::uint32_t v = 0;
      if (!parse_number(t, v))
        fail_line(src, line_no, what, fmt::format("'{}' is not an unsigned 32-bit integer", t));
      return v;
    };
    if (key == "VERSION") {
      need_args(1);
      h.version = std::string(tok[1]);
    } else if (key == "FIELDS" || key == "COLUMNS") {
      if (nargs == 0) fail_line(src, line_no, "FIELDS", "no field names");
      if (nargs > kMaxFields) fail_line(src, line_no, "FIELDS", fmt::format("more than {} fields", kMaxFields));
      names.assign(tok.begin() + 1, tok.end());
      have_fields = true;
      line_fields = line_no;
    } else if (key == "SIZE") {
      sizes.clear();
      for (std::size_t i = 1; i < tok.size() && i <= kMaxFields; ++i) {
        const std::uint32_t s = parse_u32(tok[i], "SIZE");
        if (s != 1 && s != 2 && s != 4 && s != 8)
          fail_line(src, line_no, "SIZE", fmt::format("field size {} is not 1, 2, 4 or 8", s));
        sizes.push_back(s);
      }
      have_size = true;
      line_size = line_no;
    } else if (key == "TYPE") {
      types.clear();
      for (std::size_t i = 1; i < tok.size() && i <= kMaxFields; ++i) {
        if (tok[i].size() != 1 || (tok[i][0] != 'F' && tok[i][0] != 'I' && tok[i][0] != 'U'))
          fail_line(src, line_no, "TYPE", fmt::format("type '{}' is not F, I or U", tok[i]));
        types.push_back(tok[i][0]);
      }
      have_type = true;
      line_type = line_no;
    } else if (key == "COUNT") {
      counts.clear();
      for (std::size_t i = 1; i < tok.size() && i <= kMaxFields; ++i) {
        const std::uint32_t c = parse_u32(tok[i], "COUNT");
        if (c == 0 || c > kMaxFieldCount)
          fail_line(src, line_no, "COUNT", fmt::format("count {} is not in [1, {}]", c, kMaxFieldCount));
        counts.push_back(c);
      }
      have_count = true;
      line_count = line_no;
    } else if (key == "WIDTH") {
      need_args(1);
      h.width = parse_u32(tok[1], "WIDTH");
      have_width = true;
    } else if (key == "HEIGHT") {
      need_args(1);
      h.height = parse_u32(tok[1], "HEIGHT");
      have_height = true;
    } else if (key == "VIEWPOINT") {
      need_args(7);
      for (int i = 0; i < 7; ++i)
        if (!parse_number(tok[static_cast<std::size_t>(i) + 1], h.viewpoint[static_cast<std::size_t>(i)]) ||
            !std::isfinite(h.viewpoint[static_cast<std::size_t>(i)]))
          fail_line(src, line_no, "VIEWPOINT", fmt::format("'{}' is not a finite number", tok[static_cast<std::size_t>(i) + 1]));
    } else if (key == "POINTS") {
      need_args(1);
      if (!parse_number(tok[1], h.points))
        fail_line(src, line_no, "POINTS", fmt::format("'{}' is not an unsigned integer", tok[1]));
      have_points = true;
      line_points = line_no;
    } else if (key == "DATA") {
      need_args(1);
      if (tok[1] == "ascii") h.format = PcdFormat::Ascii;
      else if (tok[1] == "binary") h.format = PcdFormat::Binary;
      else if (tok[1] == "binary_compressed") h.format = PcdFormat::BinaryCompressed;
      else fail_line(src, line_no, "DATA", fmt::format("unknown data encoding '{}'", tok[1]));
      have_data = true;
    } else {
      fail_line(src, line_no, std::string(key), "unknown header line");
    }
  }
  out.data_offset = pos;
  out.data_line = line_no + 1;

  if (!have_fields) fail_line(src, line_no, "FIELDS", "the header has no FIELDS line");
  if (!have_size) fail_line(src, line_no, "SIZE", "the header has no SIZE line");
  if (!have_type) fail_line(src, line_no, "TYPE", "the header has no TYPE line");
  if (!have_count) counts.assign(names.size(), 1);  // PCD 0.5 has no COUNT
  if (sizes.size() != names.size())
    fail_line(src, line_size, "SIZE", fmt::format("{} sizes for {} fields", sizes.size(), names.size()));
  if (types.size() != names.size())
    fail_line(src, line_type, "TYPE", fmt::format("{} types for {} fields", types.size(), names.size()));
  if (counts.size() != names.size())
    fail_line(src, line_count, "COUNT", fmt::format("{} counts for {} fields", counts.size(), names.size()));
  if (!have_width) fail_line(src, line_no, "WIDTH", "the header has no WIDTH line");
  if (!have_height) h.height = 1;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (types[i] == 'F' && sizes[i] != 4 && sizes[i] != 8)
      fail_line(src, line_size, names[i], fmt::format("a float field of {} bytes", sizes[i]));
    h.fields.push_back(PcdField{names[i], sizes[i], types[i], counts[i]});
  }
  const std::uint64_t wh = std::uint64_t{h.width} * h.height;
  if (!have_points) {
    h.points = wh;
  } else if (h.points != wh) {
    fail_line(src, line_points, "POINTS",
              fmt::format("POINTS {} differs from WIDTH * HEIGHT = {} * {}", h.points, h.width, h.height));
  }
  (void)line_fields;
  return out;
}

Layout make_layout(const PcdHeader& h, std::string_view src) {
  Layout l;
  const std::size_t n = h.fields.size();
  l.record_offset.resize(n);
  l.packed_offset.resize(n);
  l.token_index.resize(n);
  l.kind.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const PcdField& f = h.fields[i];
    l.kind[i] = kind_of(f.type, f.size);
    l.record_offset[i] = l.record_size;
    l.packed_offset[i] = l.packed_size;
    l.token_index[i] = l.tokens;
    const std::size_t bytes = std::size_t{f.size} * f.count;
    l.record_size += bytes;
    if (f.name != "_") l.packed_size += bytes;
    l.tokens += f.count;
    auto bind = [&](int& slot) {
      if (slot >= 0) fail_offset(src, 0, f.name, "field appears twice");
      if (f.count != 1) fail_offset(src, 0, f.name, fmt::format("field has COUNT {}, expected 1", f.count));
      slot = static_cast<int>(i);
    };
    if (f.name == "x") bind(l.x);
    else if (f.name == "y") bind(l.y);
    else if (f.name == "z") bind(l.z);
    else if (f.name == "rgb" || f.name == "rgba") {
      bind(l.rgb);
      if (f.size != 4) fail_offset(src, 0, f.name, fmt::format("color field of {} bytes, expected 4", f.size));
    } else if (f.name == "intensity") bind(l.intensity);
    else if (f.name == "normal_x") bind(l.nx);
    else if (f.name == "normal_y") bind(l.ny);
    else if (f.name == "normal_z") bind(l.nz);
  }
  if (l.x < 0 || l.y < 0 || l.z < 0)
    fail_offset(src, 0, l.x < 0 ? "x" : l.y < 0 ? "y" : "z", "the file has no such field; x, y and z are required");
  const bool all_normals = l.nx >= 0 && l.ny >= 0 && l.nz >= 0;
  if (!all_normals) l.nx = l.ny = l.nz = -1;  // partial normals: skipped
  return l;
}

PointCloud make_cloud(const Layout& l, std::size_t reserve) {
  PointCloud c;
  PointChannels ch = PointChannels::None;
  if (l.rgb >= 0) ch = ch | PointChannels::Color;
  if (l.intensity >= 0) ch = ch | PointChannels::Intensity;
  if (l.nx >= 0) ch = ch | PointChannels::Normal;
  c.set_channels(ch);
  c.reserve(reserve);
  return c;
}

Rgb8 unpack_rgb(std::uint32_t v) {
  return Rgb8{static_cast<std::uint8_t>((v >> 16) & 0xffu), static_cast<std::uint8_t>((v >> 8) & 0xffu),
              static_cast<std::uint8_t>(v & 0xffu)};
}

/// Binary and decompressed data: element e of field f for point i sits at
/// base + offset(f) + i * stride(f).
template <typename At>
void fill_binary(PointCloud& c, const Layout& l, std::size_t n, At at) {
  c.resize(n);
  auto pts = c.points_mut();
  const auto fx = static_cast<std::size_t>(l.x), fy = static_cast<std::size_t>(l.y), fz = static_cast<std::size_t>(l.z);
  for (std::size_t i = 0; i < n; ++i) {
    pts[i] = Eigen::Vector3f(static_cast<float>(detail::load_scalar(at(fx, i), l.kind[fx], false)),
                             static_cast<float>(detail::load_scalar(at(fy, i), l.kind[fy], false)),
                             static_cast<float>(detail::load_scalar(at(fz, i), l.kind[fz], false)));
  }
  if (l.rgb >= 0) {
    auto col = c.colors_mut();
    for (std::size_t i = 0; i < n; ++i) col[i] = unpack_rgb(detail::load_u32(at(static_cast<std::size_t>(l.rgb), i), false));
  }
  if (l.intensity >= 0) {
    auto in = c.intensities_mut();
    const auto fi = static_cast<std::size_t>(l.intensity);
    for (std::size_t i = 0; i < n; ++i) in[i] = static_cast<float>(detail::load_scalar(at(fi, i), l.kind[fi], false));
  }
  if (l.nx >= 0) {
    auto nm = c.normals_mut();
    const auto a = static_cast<std::size_t>(l.nx), b = static_cast<std::size_t>(l.ny), d = static_cast<std::size_t>(l.nz);
    for (std::size_t i = 0; i < n; ++i)
      nm[i] = Eigen::Vector3f(static_cast<float>(detail::load_scalar(at(a, i), l.kind[a], false)),
                              static_cast<float>(detail::load_scalar(at(b, i), l.kind[b], false)),
                              static_cast<float>(detail::load_scalar(at(d, i), l.kind[d], false)));
  }
}

void read_ascii(PointCloud& c, const PcdHeader& h, const Layout& l, std::span<const std::uint8_t> bytes,
                std::size_t offset, std::size_t line_no, std::string_view src) {
  const std::string_view all(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::vector<std::string_view> tok;
  std::uint64_t got = 0;
  std::size_t pos = offset;
  --line_no;
  auto value = [&](std::size_t f, std::string_view t) -> double {
    const PcdField& fd = h.fields[f];
    if (fd.type == 'F') {
      if (fd.size == 4) {
        float v;
        if (!parse_number(t, v)) fail_line(src, line_no, fd.name, fmt::format("'{}' is not a float", t));
        return v;
      }
      double v;
      if (!parse_number(t, v)) fail_line(src, line_no, fd.name, fmt::format("'{}' is not a number", t));
      return v;
    }
    if (fd.type == 'I') {
      std::int64_t v;
      if (!parse_number(t, v)) fail_line(src, line_no, fd.name, fmt::format("'{}' is not an integer", t));
      return static_cast<double>(v);
    }
    std::uint64_t v;
    if (!parse_number(t, v)) fail_line(src, line_no, fd.name, fmt::format("'{}' is not an unsigned integer", t));
    return static_cast<double>(v);
  };
  while (pos < all.size()) {
    ++line_no;
    std::size_t eol = all.find('\n', pos);
    const std::size_t next = eol == std::string_view::npos ? all.size() : eol + 1;
    if (eol == std::string_view::npos) eol = all.size();
    const std::string_view line = all.substr(pos, eol - pos);
    pos = next;
    detail::split_tokens(line, tok);
    if (tok.empty()) continue;
    if (got == h.points)
      fail_line(src, line_no, "POINTS", fmt::format("more data lines than the {} points declared", h.points));
    if (tok.size() != l.tokens)
      fail_line(src, line_no, "DATA", fmt::format("{} values on the line, {} expected", tok.size(), l.tokens));
    Eigen::Vector3f p(static_cast<float>(value(static_cast<std::size_t>(l.x), tok[l.token_index[static_cast<std::size_t>(l.x)]])),
                      static_cast<float>(value(static_cast<std::size_t>(l.y), tok[l.token_index[static_cast<std::size_t>(l.y)]])),
                      static_cast<float>(value(static_cast<std::size_t>(l.z), tok[l.token_index[static_cast<std::size_t>(l.z)]])));
    const std::size_t i = c.push_back(p);
    if (l.rgb >= 0) {
      const auto f = static_cast<std::size_t>(l.rgb);
      const std::string_view t = tok[l.token_index[f]];
      std::uint32_t bits = 0;
      if (h.fields[f].type == 'F') {
        float v;
        if (!parse_number(t, v)) fail_line(src, line_no, h.fields[f].name, fmt::format("'{}' is not a float", t));
        bits = std::bit_cast<std::uint32_t>(v);
      } else if (h.fields[f].type == 'U') {
        if (!parse_number(t, bits)) fail_line(src, line_no, h.fields[f].name, fmt::format("'{}' is not a 32-bit unsigned integer", t));
      } else {
        std::int32_t s;
        if (!parse_number(t, s)) fail_line(src, line_no, h.fields[f].name, fmt::format("'{}' is not a 32-bit integer", t));
        bits = static_cast<std::uint32_t>(s);
      }
      c.colors_mut()[i] = unpack_rgb(bits);
    }
    if (l.intensity >= 0) {
      const auto f = static_cast<std::size_t>(l.intensity);
      c.intensities_mut()[i] = static_cast<float>(value(f, tok[l.token_index[f]]));
    }
    if (l.nx >= 0) {
      const auto a = static_cast<std::size_t>(l.nx), b = static_cast<std::size_t>(l.ny), d = static_cast<std::size_t>(l.nz);
      c.normals_mut()[i] = Eigen::Vector3f(static_cast<float>(value(a, tok[l.token_index[a]])),
                                           static_cast<float>(value(b, tok[l.token_index[b]])),
                                           static_cast<float>(value(d, tok[l.token_index[d]])));
    }
    // Skipped fields are still checked to be numbers of their type.
    for (std::size_t f = 0; f < h.fields.size(); ++f) {
      if (static_cast<int>(f) == l.x || static_cast<int>(f) == l.y || static_cast<int>(f) == l.z ||
          static_cast<int>(f) == l.rgb)
        continue;
      for (std::size_t e = 0; e < h.fields[f].count; ++e) (void)value(f, tok[l.token_index[f] + e]);
    }
    ++got;
  }
  if (got != h.points)
    fail_line(src, line_no + 1, "POINTS", fmt::format("the file has {} data lines, {} points declared", got, h.points));
}

}  // namespace

PointCloud read_pcd_from_memory(std::span<const std::uint8_t> bytes, std::string_view src, PcdHeader* header_out) {
  ROVE_TRACE_BEGIN
  HeaderParse hp = parse_header(bytes, src);
  const PcdHeader& h = hp.header;
  const Layout l = make_layout(h, src);
  const std::size_t off = hp.data_offset;
  const std::size_t remaining = bytes.size() - off;
  PointCloud cloud;

  if (h.format == PcdFormat::Ascii) {
    // Every point needs at least two characters per value: never reserve more.
    const std::uint64_t cap = remaining / (2 * std::max<std::size_t>(l.tokens, 1));
    cloud = make_cloud(l, static_cast<std::size_t>(std::min<std::uint64_t>(h.points, cap)));
    read_ascii(cloud, h, l, bytes, off, hp.data_line, src);
  } else if (h.format == PcdFormat::Binary) {
    std::uint64_t need = 0;
    if (__builtin_mul_overflow(h.points, static_cast<std::uint64_t>(l.record_size), &need) || need > remaining)
      fail_offset(src, off, "DATA",
                  fmt::format("{} points of {} bytes need {} bytes, the file has {} after the header", h.points,
                              l.record_size, need, remaining));
    // Bytes after the declared points are ignored, as PCL does.
    const std::uint8_t* base = bytes.data() + off;
    const std::size_t rec = l.record_size;
    cloud = make_cloud(l, 0);
    fill_binary(cloud, l, static_cast<std::size_t>(h.points),
                [&](std::size_t f, std::size_t i) { return base + i * rec + l.record_offset[f]; });
  } else {
    if (h.points == 0 && remaining == 0) {
      cloud = make_cloud(l, 0);
    } else {
      if (remaining < 8)
        fail_offset(src, off, "DATA", "binary_compressed data is cut off before its two size words");
      const std::uint32_t csize = detail::load_u32(bytes.data() + off, false);
      const std::uint32_t usize = detail::load_u32(bytes.data() + off + 4, false);
      std::uint64_t expect = 0;
      if (__builtin_mul_overflow(h.points, static_cast<std::uint64_t>(l.packed_size), &expect) || expect != usize)
        fail_offset(src, off + 4, "uncompressed_size",
                    fmt::format("uncompressed size {} differs from {} points of {} bytes", usize, h.points,
                                l.packed_size));
      if (csize > remaining - 8)
        fail_offset(src, off, "compressed_size",
                    fmt::format("compressed size {} exceeds the {} bytes left in the file", csize, remaining - 8));
      // LZF produces at most 88 bytes per input byte (a 3-byte reference of
      // 264 bytes): a larger claim is a lie, refused before allocating.
      if (std::uint64_t{usize} > std::uint64_t{csize} * 88)
        fail_offset(src, off + 4, "uncompressed_size",
                    fmt::format("uncompressed size {} is impossible for {} compressed bytes", usize, csize));
      // PCL's writer leaves bytes after the compressed block (its file is
      // sized before compressing); they are ignored, as PCL does.
      std::vector<std::uint8_t> raw(usize);
      lzf_decompress(bytes.subspan(off + 8, csize), raw, src, off + 8);
      const std::uint8_t* base = raw.data();
      const std::size_t np = static_cast<std::size_t>(h.points);
      cloud = make_cloud(l, 0);
      fill_binary(cloud, l, np, [&](std::size_t f, std::size_t i) {
        const std::size_t elem = std::size_t{h.fields[f].size} * h.fields[f].count;
        return base + l.packed_offset[f] * np + i * elem;
      });
    }
  }
  if (header_out) *header_out = h;
  return cloud;
  ROVE_TRACE_END
}

PointCloud read_pcd(const std::string& path, PcdHeader* header) {
  const std::vector<std::uint8_t> bytes = read_file_bytes(path, 0, "point cloud");
  return read_pcd_from_memory(bytes, path, header);
}

std::vector<std::uint8_t> write_pcd_to_memory(const PointCloud& cloud, const PcdWriteOptions& o) {
  const std::size_t n = cloud.size();
  std::uint32_t width = o.width, height = o.height;
  if (width == 0 && height == 0) {
    ROVE_CHECK_LE(n, std::size_t{std::numeric_limits<std::uint32_t>::max()});
    width = static_cast<std::uint32_t>(n);
    height = 1;
  }
  ROVE_CHECK_MSG(std::uint64_t{width} * height == n, "width {} * height {} must equal the cloud size {}", width,
                 height, n);
  const bool rgb = o.write_colors && cloud.has_colors();
  const bool inten = o.write_intensity && cloud.has_intensity();
  const bool nrm = o.write_normals && cloud.has_normals();
  std::vector<std::string> names{"x", "y", "z"};
  if (rgb) names.emplace_back("rgb");
  if (inten) names.emplace_back("intensity");
  if (nrm) names.insert(names.end(), {"normal_x", "normal_y", "normal_z"});
  const std::size_t nf = names.size();

  std::string head = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
  for (auto& s : names) head += " " + s;
  head += "\nSIZE";
  for (std::size_t i = 0; i < nf; ++i) head += " 4";
  head += "\nTYPE";
  for (std::size_t i = 0; i < nf; ++i) head += " F";
  head += "\nCOUNT";
  for (std::size_t i = 0; i < nf; ++i) head += " 1";
  head += fmt::format("\nWIDTH {}\nHEIGHT {}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {}\nDATA {}\n", width, height, n,
                      o.format == PcdFormat::Ascii    ? "ascii"
                      : o.format == PcdFormat::Binary ? "binary"
                                                       : "binary_compressed");

  // Value of field k of point i, as a float.
  auto field = [&](std::size_t i, std::size_t k) -> float {
    if (k < 3) return cloud[i][static_cast<Eigen::Index>(k)];
    k -= 3;
    if (rgb) {
      if (k == 0) {
        const Rgb8 c = cloud.colors()[i];
        return std::bit_cast<float>((std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | c.b);
      }
      --k;
    }
    if (inten) {
      if (k == 0) return cloud.intensities()[i];
      --k;
    }
    return cloud.normals()[i][static_cast<Eigen::Index>(k)];
  };

  std::vector<std::uint8_t> out(head.begin(), head.end());
  if (o.format == PcdFormat::Ascii) {
    std::string body;
    body.reserve(n * nf * 10);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < nf; ++k) {
        if (k) body += ' ';
        detail::append_float(body, field(i, k));
      }
      body += '\n';
    }
    out.insert(out.end(), body.begin(), body.end());
  } else if (o.format == PcdFormat::Binary) {
    std::vector<std::uint8_t> body(n * nf * 4);
    std::uint8_t* p = body.data();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < nf; ++k, p += 4) {
        const float v = field(i, k);
        std::memcpy(p, &v, 4);
      }
    out.insert(out.end(), body.begin(), body.end());
  } else {
    const std::uint64_t usize = std::uint64_t{n} * nf * 4;
    ROVE_CHECK_MSG(usize <= std::numeric_limits<std::uint32_t>::max(),
                   "{} points are too many for binary_compressed (sizes are 32-bit)", n);
    std::vector<std::uint8_t> raw(static_cast<std::size_t>(usize));
    std::uint8_t* p = raw.data();
    for (std::size_t k = 0; k < nf; ++k)
      for (std::size_t i = 0; i < n; ++i, p += 4) {
        const float v = field(i, k);
        std::memcpy(p, &v, 4);
      }
    const std::vector<std::uint8_t> packed = lzf_compress(raw);
    ROVE_CHECK_LE(packed.size(), std::size_t{std::numeric_limits<std::uint32_t>::max()});
    const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(packed.size()), static_cast<std::uint32_t>(usize)};
    const auto* sb = reinterpret_cast<const std::uint8_t*>(sizes);
    out.insert(out.end(), sb, sb + 8);
    out.insert(out.end(), packed.begin(), packed.end());
  }
  return out;
}

void write_pcd(const std::string& path, const PointCloud& cloud, const PcdWriteOptions& options) {
  write_file_bytes(path, write_pcd_to_memory(cloud, options));
}

}  // namespace rove
