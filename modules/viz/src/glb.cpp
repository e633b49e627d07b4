#include "rove/viz/glb.h"

#include <fmt/format.h>

#include <cstring>
#include <limits>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/json.h"

namespace rove {

namespace {

constexpr std::uint32_t kMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kNearest = 9728, kClampToEdge = 33071;

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint32_t get_u32(std::span<const std::uint8_t> d, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(d[at + i]) << (8 * i);
  return v;
}

int gltf_mode(Primitive p) {
  switch (p) {
    case Primitive::Points: return 0;
    case Primitive::Lines: return 1;
    case Primitive::LineStrip: return 3;
    case Primitive::Triangles: return 4;
  }
  return 0;
}

const char* to_string(TimeMode m) {
  switch (m) {
    case TimeMode::None: return "none";
    case TimeMode::Cumulative: return "cumulative";
    case TimeMode::Snapshot: return "snapshot";
  }
  return "none";
}

// The BIN chunk and the JSON arrays that describe it, built together.
class GltfBuilder {
 public:
  // Appends raw bytes as a buffer view (4-byte aligned); returns its index.
  std::size_t view(const void* data, std::size_t bytes, int target) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    const std::size_t offset = bin_.size();
    const auto* p = static_cast<const std::uint8_t*>(data);
    bin_.insert(bin_.end(), p, p + bytes);
    JsonWriter j(0);
    j.begin_object().key("buffer").value(0).key("byteOffset").value(std::uint64_t{offset});
    j.key("byteLength").value(std::uint64_t{bytes});
    if (target != 0) j.key("target").value(target);
    j.end_object();
    views_.push_back(j.str());
    return views_.size() - 1;
  }

  // A buffer view plus an accessor over it; returns the accessor index.
  std::size_t accessor(const void* data, std::size_t count, int component, const char* type, std::size_t bytes,
                       int target, bool normalized = false, std::string_view bounds = {}) {
    const std::size_t v = view(data, bytes, target);
    std::string s = fmt::format("{{\"bufferView\":{},\"componentType\":{},{}\"count\":{},\"type\":\"{}\"{}{}}}", v,
                                component, normalized ? "\"normalized\":true," : "", count, type,
                                bounds.empty() ? "" : ",", bounds);
    accessors_.push_back(std::move(s));
    return accessors_.size() - 1;
  }

  std::vector<std::string> views_, accessors_;
  std::vector<std::uint8_t> bin_;
};

std::string float_list(std::initializer_list<float> v) {
  std::string s = "[";
  for (float x : v) {
    if (s.size() > 1) s += ',';
    s += fmt::format("{}", static_cast<double>(x));
  }
  return s + "]";
}

// "min": [...], "max": [...] of the positions (exact: floats print exactly).
std::string position_bounds(const std::vector<Eigen::Vector3f>& p) {
  Eigen::Vector3f lo = p.front(), hi = p.front();
  for (const auto& x : p) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return fmt::format("\"min\":{},\"max\":{}", float_list({lo.x(), lo.y(), lo.z()}),
                     float_list({hi.x(), hi.y(), hi.z()}));
}

// Attributes (and indices) of one layer's primitive.
std::string primitive_json(GltfBuilder& b, const Layer& l, std::size_t material) {
  const std::size_t n = l.positions.size();
  JsonWriter j(0);
  j.begin_object().key("attributes").begin_object();
  j.key("POSITION").value(std::uint64_t{b.accessor(l.positions.data(), n, kFloat, "VEC3", n * 12, kArrayBuffer, false,
                                                   position_bounds(l.positions))});
  if (!l.colors.empty()) {
    j.key("COLOR_0").value(std::uint64_t{
        b.accessor(l.colors.data(), n, kUnsignedByte, "VEC4", n * 4, kArrayBuffer, true)});
  }
  if (!l.uvs.empty()) {
    j.key("TEXCOORD_0").value(std::uint64_t{b.accessor(l.uvs.data(), n, kFloat, "VEC2", n * 8, kArrayBuffer)});
  }
  if (!l.times.empty()) {
    j.key("_TIME").value(std::uint64_t{b.accessor(l.times.data(), n, kFloat, "SCALAR", n * 4, kArrayBuffer)});
  }
  if (!l.intensities.empty()) {
    j.key("_INTENSITY").value(
        std::uint64_t{b.accessor(l.intensities.data(), n, kFloat, "SCALAR", n * 4, kArrayBuffer)});
  }
  j.end_object();
  if (!l.indices.empty()) {
    j.key("indices").value(std::uint64_t{b.accessor(l.indices.data(), l.indices.size(), kUnsignedInt, "SCALAR",
                                                    l.indices.size() * 4, kElementArrayBuffer)});
  }
  j.key("mode").value(gltf_mode(l.primitive)).key("material").value(std::uint64_t{material});
  j.end_object();
  return j.str();
}

std::string layer_extras(const Layer& l, std::size_t index) {
  JsonWriter j(0);
  j.begin_object().key("rove").begin_object();
  j.key("index").value(std::uint64_t{index});
  j.key("kind").value(to_string(l.kind)).key("name").value(l.name);
  j.key("time_mode").value(to_string(l.time_mode)).key("point_size").value(l.point_size);
  j.key("vertex_count").value(std::uint64_t{l.positions.size()});
  j.key("source_count").value(std::uint64_t{l.source_count});
  j.key("permutation_step").value(std::uint64_t{l.permutation_step});
  j.key("color").begin_array().value(l.color.r).value(l.color.g).value(l.color.b).value(l.color.a).end_array();
  if (!l.text.empty()) j.key("text").value(l.text);
  if (!l.shown) j.key("shown").value(false);
  if (l.grid) {
    j.key("grid").begin_object();
    j.key("x_min").value(l.grid->x_min).key("y_min").value(l.grid->y_min).key("resolution").value(l.grid->resolution);
    j.key("size_x").value(std::uint64_t{l.grid->size_x}).key("size_y").value(std::uint64_t{l.grid->size_y});
    j.key("cells_per_texel").value(std::uint64_t{l.grid->cells_per_texel});
    j.end_object();
  }
  j.end_object().end_object();
  return j.str();
}

std::string material_json(const Layer& l, std::optional<std::size_t> texture) {
  JsonWriter j(0);
  j.begin_object().key("name").value(l.name).key("pbrMetallicRoughness").begin_object();
  j.key("baseColorFactor").raw(float_list({l.color.r / 255.0f, l.color.g / 255.0f, l.color.b / 255.0f,
                                           l.color.a / 255.0f}));
  j.key("metallicFactor").value(0).key("roughnessFactor").value(1);
  if (texture) j.key("baseColorTexture").begin_object().key("index").value(std::uint64_t{*texture}).end_object();
  j.end_object();
  j.key("doubleSided").value(true);
  if (l.color.a < 255) j.key("alphaMode").value("BLEND");
  j.key("extensions").begin_object().key("KHR_materials_unlit").begin_object().end_object().end_object();
  j.end_object();
  return j.str();
}

void raw_array(JsonWriter& j, const char* key, const std::vector<std::string>& items) {
  j.key(key).begin_array();
  for (const auto& s : items) j.raw(s);
  j.end_array();
}

std::string scene_extras(const Scene& scene) {
  JsonWriter j(0);
  j.begin_object().key("rove").begin_object();
  j.key("title").value(scene.title).key("up").value(to_string(scene.up));
  j.key("time_origin").value(scene.time_origin);  // null when unset
  j.key("sources").value(scene.sources);
  j.key("layers").value(std::uint64_t{scene.layers.size()});
  j.key("vertices").value(std::uint64_t{scene.vertex_count()});
  j.end_object().end_object();
  return j.str();
}

}  // namespace

std::vector<std::uint8_t> write_glb_to_memory(const Scene& scene) {
  scene.check();
  GltfBuilder b;
  std::vector<std::string> nodes, meshes, materials, textures, images;
  std::string children;
  for (std::size_t i = 0; i < scene.layers.size(); ++i) {
    const Layer& l = scene.layers[i];
    std::optional<std::size_t> texture;
    if (l.texture) {
      const std::size_t v = b.view(l.texture->png.data(), l.texture->png.size(), 0);
      images.push_back(fmt::format("{{\"bufferView\":{},\"mimeType\":\"image/png\"}}", v));
      textures.push_back(fmt::format("{{\"sampler\":0,\"source\":{}}}", images.size() - 1));
      texture = textures.size() - 1;
    }
    materials.push_back(material_json(l, texture));
    meshes.push_back(fmt::format("{{\"name\":{},\"primitives\":[{}]}}", json_quote(l.name),
                                 primitive_json(b, l, materials.size() - 1)));
    nodes.push_back(fmt::format("{{\"name\":{},\"mesh\":{},\"extras\":{}}}", json_quote(l.name), i, layer_extras(l, i)));
    children += (i == 0 ? "" : ",") + std::to_string(i + 1);
  }
  if (b.bin_.size() > std::numeric_limits<std::uint32_t>::max() - 64) {
    throw ResourceError(fmt::format("scene of {} bytes does not fit a .glb (at most 4 GiB)", b.bin_.size()));
  }
  while (b.bin_.size() % 4 != 0) b.bin_.push_back(0);
  // The root turns the scene's up into glTF's y up: z up by a rotation of
  // −90° about x; −y up (a camera's optical frame) by 180° about x, which
  // also turns the camera's forward z into glTF's −z, the view direction
  // of a viewer standing behind it.
  const bool optical = scene.up == SceneUp::MinusY;
  const std::string root = fmt::format("{{\"name\":\"rove world ({} up)\",\"rotation\":[{}],\"children\":[{}]}}",
                                       to_string(scene.up),
                                       optical ? "1,0,0,0" : "-0.7071067811865476,0,0,0.7071067811865476", children);
  nodes.insert(nodes.begin(), root);
  JsonWriter j(0);
  j.begin_object();
  j.key("asset").begin_object().key("version").value("2.0").key("generator").value("rove").end_object();
  j.key("extensionsUsed").begin_array().value("KHR_materials_unlit").end_array();
  j.key("scene").value(0);
  j.key("scenes").begin_array().begin_object().key("name").value(scene.title);
  j.key("nodes").begin_array().value(0).end_array().key("extras").raw(scene_extras(scene)).end_object().end_array();
  raw_array(j, "nodes", nodes);
  raw_array(j, "meshes", meshes);
  raw_array(j, "materials", materials);
  if (!textures.empty()) {
    j.key("samplers").begin_array().raw(fmt::format("{{\"magFilter\":{0},\"minFilter\":{0},\"wrapS\":{1},\"wrapT\":{1}}}",
                                                    kNearest, kClampToEdge)).end_array();
    raw_array(j, "textures", textures);
    raw_array(j, "images", images);
  }
  raw_array(j, "accessors", b.accessors_);
  raw_array(j, "bufferViews", b.views_);
  j.key("buffers").begin_array().begin_object().key("byteLength").value(std::uint64_t{b.bin_.size()});
  j.end_object().end_array().end_object();
  std::string json = j.str();
  while (json.size() % 4 != 0) json += ' ';

  std::vector<std::uint8_t> out;
  const std::size_t total = 12 + 8 + json.size() + 8 + b.bin_.size();
  out.reserve(total);
  put_u32(out, kMagic);
  put_u32(out, 2);
  put_u32(out, static_cast<std::uint32_t>(total));
  put_u32(out, static_cast<std::uint32_t>(json.size()));
  put_u32(out, kChunkJson);
  out.insert(out.end(), json.begin(), json.end());
  put_u32(out, static_cast<std::uint32_t>(b.bin_.size()));
  put_u32(out, kChunkBin);
  out.insert(out.end(), b.bin_.begin(), b.bin_.end());
  return out;
}

void write_glb(const std::string& path, const Scene& scene) {
  const std::vector<std::uint8_t> bytes = write_glb_to_memory(scene);
  write_text_file_atomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

GlbContents parse_glb(std::span<const std::uint8_t> data, std::string_view source) {
  const auto fail = [&](std::uint64_t offset, const char* field, const std::string& problem) {
    throw ParseError({std::string(source), std::nullopt, offset, field}, problem);
  };
  if (data.size() < 12) fail(0, "header", fmt::format("{} bytes, shorter than a glb header", data.size()));
  if (get_u32(data, 0) != kMagic) fail(0, "magic", "not a binary glTF file (no \"glTF\" magic)");
  GlbContents c;
  c.version = get_u32(data, 4);
  if (c.version != 2) fail(4, "version", fmt::format("glTF version {}, expected 2", c.version));
  const std::uint32_t length = get_u32(data, 8);
  if (length != data.size()) fail(8, "length", fmt::format("header says {} bytes, the data has {}", length, data.size()));
  std::size_t at = 12;
  int chunk = 0;
  while (at < data.size()) {
    if (data.size() - at < 8) fail(at, "chunk", "truncated chunk header");
    const std::uint32_t size = get_u32(data, at), type = get_u32(data, at + 4);
    if (size % 4 != 0) fail(at, "chunkLength", fmt::format("chunk length {} is not a multiple of 4", size));
    if (size > data.size() - at - 8) fail(at, "chunkLength", fmt::format("chunk of {} bytes runs past the end", size));
    const auto body = data.subspan(at + 8, size);
    if (chunk == 0) {
      if (type != kChunkJson) fail(at + 4, "chunkType", "the first chunk is not JSON");
      c.json_text.assign(body.begin(), body.end());
      while (!c.json_text.empty() && (c.json_text.back() == ' ' || c.json_text.back() == '\0')) c.json_text.pop_back();
      c.json = parse_json(c.json_text, fmt::format("{} (JSON chunk)", source));
    } else if (chunk == 1 && type == kChunkBin) {
      c.bin.assign(body.begin(), body.end());
    } else if (type == kChunkJson || type == kChunkBin) {
      fail(at + 4, "chunkType", fmt::format("unexpected chunk type 0x{:08x} as chunk {}", type, chunk));
    }
    at += 8 + size;
    ++chunk;
  }
  if (chunk == 0) fail(12, "chunk", "no JSON chunk");
  return c;
}

}  // namespace rove
