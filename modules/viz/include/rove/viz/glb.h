#pragma once
/// \file
/// Scenes as glTF 2.0 binary files (.glb, Khronos glTF 2.0 specification,
/// section 4.4 "Binary glTF layout"), which three.js, Blender, and most 3D
/// tools open.
///
/// Layout: a 12-byte header (magic "glTF", version 2, total length), a JSON
/// chunk (padded with spaces to 4 bytes) and a BIN chunk (padded with
/// zeros). Every layer becomes one mesh with one primitive (mode POINTS,
/// LINES, LINE_STRIP or TRIANGLES) under a root node that turns rove's z-up
/// world into glTF's y-up frame (a rotation of −90° about x), so positions
/// keep rove's coordinates. Vertex data: POSITION (float VEC3, with min and
/// max), COLOR_0 (normalized unsigned byte VEC4), TEXCOORD_0 (float VEC2),
/// and the application-specific _TIME and _INTENSITY (float SCALAR); indices
/// are unsigned int. Materials are unlit (KHR_materials_unlit) with the
/// layer colour; a grid's texture is an embedded PNG sampled nearest.
///
/// rove's metadata sits in `extras.rove` of the scene (title, time origin,
/// sources, up axis) and of each layer's node (kind, time mode, point size,
/// source count, permutation step, label text), so the viewer can rebuild
/// its controls from the file alone.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rove/viz/json_value.h"
#include "rove/viz/scene.h"

namespace rove {

/// The bytes of a .glb holding `scene`. Precondition: scene.check() passes
/// (InvalidArgument otherwise); the BIN chunk must stay below 4 GiB
/// (ResourceError).
std::vector<std::uint8_t> write_glb_to_memory(const Scene& scene);

/// Writes `scene` as a .glb at `path`, atomically (rove/core/files.h).
/// Throws IoError if it cannot be written.
void write_glb(const std::string& path, const Scene& scene);

/// A .glb read back: its two chunks.
struct GlbContents {
  std::uint32_t version = 0;           ///< from the header (2)
  std::string json_text;               ///< the JSON chunk, padding removed
  JsonValue json;                      ///< the JSON chunk parsed
  std::vector<std::uint8_t> bin;       ///< the BIN chunk (with its padding)
};

/// Splits and checks a .glb held in memory: the magic, version 2, the total
/// length against the data, chunk lengths and types (JSON first, BIN
/// optional), 4-byte alignment, valid JSON. Throws ParseError naming
/// `source`, the byte offset and the field.
GlbContents parse_glb(std::span<const std::uint8_t> data, std::string_view source);

}  // namespace rove
