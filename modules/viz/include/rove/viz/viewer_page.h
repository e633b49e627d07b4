#pragma once
/// \file
/// The web page that shows a scene: three.js (Debian's libjs-three, read
/// from its folder at run time, never from the network), its glTF loader
/// and orbit controls, and rove's viewer script (layer toggles, point
/// size, colour modes, time slider, picking, a level of detail for large
/// clouds). The page publishes what it loaded as JSON in
/// `<pre id="rove-stats">` (status, layers, objects, vertices per kind,
/// load time) and titles itself "rove view: <title>" when ready or
/// "rove view: error" when not, for scripts and tests.

#include <array>
#include <cstddef>
#include <optional>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rove {

/// Where Debian's libjs-three installs three.js.
inline constexpr std::string_view kDefaultThreeDir = "/usr/share/javascript/three";

/// The three.js scripts the page loads, relative to the three.js folder, in
/// loading order: three.min.js, the GLTFLoader and the OrbitControls of
/// examples/js.
std::span<const std::string_view> three_script_files() noexcept;

/// rove's viewer script (served as /viewer.js).
std::string_view viewer_script() noexcept;

/// Options of the pages.
struct ViewerPageOptions {
  std::string three_dir = std::string(kDefaultThreeDir);  ///< folder of three.js
  /// Points of a large cloud drawn while the camera moves (all of them when
  /// it rests), > 0.
  std::size_t lod_budget = 1'000'000;
  /// Measure frames per second after loading (stats fps_full, fps_moving).
  bool bench = false;
  /// Show the control panel (layers, point size, colours, time); false
  /// leaves only the title, for pictures.
  bool panel = true;
  /// When set, the page clicks at these normalized device coordinates
  /// (−1..1, y up; (0, 0) is the centre) once loaded and publishes what it
  /// picked in the stats ("pick": layer, kind, index in the source, x, y, z;
  /// for a grid cell also "cell": [cx, cy] and "occupancy": p(occupied) read
  /// from the texture, with index cy·size_x + cx and x, y the cell's centre).
  std::optional<std::array<double, 2>> pick_at;
};

/// Reads one of three_script_files() from `three_dir`. Throws IoError naming
/// the file and the Debian package (libjs-three) when it is missing.
std::string read_three_script(const std::string& three_dir, std::string_view relative);

/// The page the viewer server sends: it loads `three/<file>` for each of
/// three_script_files(), `viewer.js` and `scene.glb` relative to itself.
std::string served_page(const ViewerPageOptions& options = {});

/// One self-contained page: three.js, the viewer and the scene (base64)
/// inlined, to open from disk or send to someone. Throws IoError if a
/// three.js script cannot be read.
std::string standalone_page(std::span<const std::uint8_t> glb, const ViewerPageOptions& options = {});

/// The JSON the page published in `<pre id="rove-stats">` of a dumped DOM
/// (headless_dump_dom), entities such as &quot; decoded; empty when absent.
std::string page_stats_json(std::string_view dom);

/// Standard base64 (RFC 4648, with padding).
std::string base64_encode(std::span<const std::uint8_t> bytes);

}  // namespace rove
