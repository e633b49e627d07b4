#pragma once
/// \file
/// Camera intrinsics files in the formats RGB-D users have:
///  - the RGB-D SLAM tutorial's `parameters.txt`: `key=value` lines,
///    `camera.fx=518.0;` (trailing `;` allowed), `camera.scale` the depth
///    scale, `#` comments;
///  - TUM / ORB-SLAM YAML (OpenCV FileStorage, `%YAML:1.0`): `Camera.fx:`,
///    `Camera.fy:`, `Camera.cx:`, `Camera.cy:`, `Camera.k1:` … `Camera.k3:`,
///    `Camera.p1:`, `Camera.p2:`, `Camera.width:`, `Camera.height:`,
///    `DepthMapFactor:` (ORB-SLAM3's `Camera1.` prefix is read alike);
///  - MRPT's camera config (TCamera::loadFromConfigFile): an INI section with
///    `resolution = [w h]`, `cx`, `cy`, `fx`, `fy`, `dist = [k1 k2 p1 p2 k3]`.
/// The format is told by the keys present.

#include <optional>
#include <string>
#include <string_view>

#include "rove/obs/pinhole_camera.h"

namespace rove {

/// Which format a camera file was read as.
enum class CameraFileFormat {
  TutorialParameters,  ///< `camera.fx=…` lines
  OrbSlamYaml,         ///< `Camera.fx: …` (TUM / ORB-SLAM)
  MrptConfig,          ///< an INI section with `fx`, `fy`, `cx`, `cy`
};

/// Name of a format ("parameters.txt", "ORB-SLAM YAML", "MRPT camera config").
std::string_view to_string(CameraFileFormat format);

/// What a camera file holds.
struct CameraFile {
  /// The intrinsics; width and height are 0 when the file does not give them.
  PinholeCamera camera;
  /// Stored depth units per meter (`camera.scale`, `DepthMapFactor`), when given.
  std::optional<double> depth_scale;
  /// The format the file was read as.
  CameraFileFormat format = CameraFileFormat::TutorialParameters;
};

/// Parses camera-file text; `source` names it in errors. Throws ParseError
/// naming the source, line and key for a malformed number, a missing focal
/// length or principal point, a zero or non-finite focal length, a negative
/// or zero depth scale, or text that is none of the three formats.
CameraFile parse_camera_file(std::string_view text, std::string_view source);

/// Reads a camera file (see parse_camera_file). Throws IoError if it cannot
/// be read.
CameraFile read_camera_file(const std::string& path);

}  // namespace rove
