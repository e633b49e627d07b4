#pragma once
/// \file
/// The YAML half of a ROS map_server map (`map.yaml`): which image holds the
/// cells, where it lies, and how its gray values are read.
///
/// Keys (ROS map_server / nav2_map_server): `image` (path, relative to the
/// YAML file's folder unless absolute), `resolution` (meters per pixel),
/// `origin` [x, y, yaw] (meters, radians: the pose of the lower-left pixel's
/// corner), `negate` (0/1 or true/false), `occupied_thresh`, `free_thresh`,
/// `mode` (trinary, scale or raw). `image`, `resolution` and `origin` are
/// required; the others default to negate 0, 0.65, 0.196 and trinary
/// (map_server requires negate and the thresholds; rove is lenient there).
///
/// The parser reads the subset of YAML such files use: one `key: value` per
/// line, flow lists `[a, b, c]`, plain or quoted ('...' / "...") scalars,
/// `#` comments, blank lines and a leading `---`. Nested blocks, anchors and
/// multi-line values are rejected. Errors are rove::ParseError naming the
/// source, line and key. Keys it does not know are kept in `unknown_keys`
/// (map_server ignores them too), never silently applied.

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace rove {

/// How gray values become cells (map_server's `mode`).
enum class RosMapMode : unsigned char {
  Trinary,  ///< occupied / free / unknown by the thresholds
  Scale,    ///< between the thresholds: an occupancy of 1 + 98·ratio percent
  Raw,      ///< the gray value is the occupancy in percent (0–100), above 100 unknown
};

/// The contents of a map.yaml.
struct RosMapYaml {
  std::string image;                    ///< image path as written in the file
  double resolution = 0.05;             ///< meters per pixel, > 0
  std::array<double, 3> origin{0, 0, 0};///< x, y (meters), yaw (radians) of the lower-left corner
  bool negate = false;                  ///< white = occupied instead of black
  double occupied_thresh = 0.65;        ///< occupancy above this: occupied
  double free_thresh = 0.196;           ///< occupancy below this: free
  RosMapMode mode = RosMapMode::Trinary;
  std::vector<std::string> unknown_keys;///< keys read but not known (ignored)
};

/// Parses map.yaml text; `source` names it in errors. Checks: required keys
/// present, no duplicate key, resolution > 0 and finite, origin three finite
/// numbers, 0 ≤ free_thresh ≤ occupied_thresh ≤ 1, mode known, negate 0/1.
/// Throws ParseError (source, line, key).
RosMapYaml parse_ros_map_yaml(std::string_view text, std::string_view source);

/// Reads and parses the file at `path`. Throws IoError / ParseError.
RosMapYaml read_ros_map_yaml(const std::string& path);

/// The text of a map.yaml in map_saver's layout: image, resolution, origin,
/// negate, occupied_thresh, free_thresh, then `mode` only when not trinary.
/// Numbers are written in the shortest form that reads back to the same
/// value (as float when the value is a float, the grid's precision).
std::string format_ros_map_yaml(const RosMapYaml& yaml);

/// The image path of `yaml` resolved against the folder of `yaml_path`
/// (unchanged when absolute).
std::string resolve_image_path(const RosMapYaml& yaml, const std::string& yaml_path);

/// Name of a mode as written in the file: "trinary", "scale", "raw".
std::string_view to_string(RosMapMode mode);

}  // namespace rove
