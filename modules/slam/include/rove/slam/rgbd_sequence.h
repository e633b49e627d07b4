#pragma once
/// \file
/// RGB-D sequence folders: the list of (color, depth) image pairs with their
/// times, the camera, the depth scale and the reference trajectory when the
/// folder has one. Three layouts are recognized:
///  - TUM RGB-D (Sturm et al., IROS 2012): `associations.txt` (`t_rgb
///    rgb/… t_depth depth/…` per line), else `rgb.txt` and `depth.txt`
///    associated by nearest time (one-to-one, closest pairs first, as TUM's
///    associate.py); `groundtruth.txt` is the reference; depth 5000 per meter;
///  - ICL-NUIM as TUM-less numbered frames: `color/` (or `rgb/`) and
///    `depth/` holding `1.png`, `2.png`, … and `pose.txt` (`x y z qx qy qz
///    qw` per frame, T_world_camera): the reference; depth 5000 per meter;
///  - numbered frames with a camera file: the same folders, the camera from
///    a camera file in the folder (`camera.yaml`, `camera.txt`,
///    `parameters.txt`, `camera.ini`) or given.
/// Numbered frames get their number as time (seconds). Only file names are
/// listed here; images are read by the pipeline.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/trajectory_files.h"
#include "rove/obs/pinhole_camera.h"

namespace rove {

/// Which layout a sequence folder has.
enum class RgbdSequenceFormat {
  Tum,             ///< TUM RGB-D benchmark folder
  NumberedFrames,  ///< color/ and depth/ with numbered images
};

/// "tum" or "numbered-frames".
std::string_view to_string(RgbdSequenceFormat format);

/// One color image and its registered depth image.
struct RgbdSequenceFrame {
  double time = 0.0;        ///< seconds (the color image's)
  std::string color_path;   ///< color image file
  std::string depth_path;   ///< depth image file
  double depth_time = 0.0;  ///< seconds (the depth image's; equal to time for numbered frames)
};

/// The intrinsics and depth scale of a named camera: "tum-fr1", "tum-fr2",
/// "tum-fr3" (TUM's published calibrations of the RGB cameras; depth 5000
/// per meter), "tum" (TUM's default for registered depth: f 525, c (319.5,
/// 239.5)), "icl-nuim" (fx 481.2, fy −480, c (319.5, 239.5), 5000 per
/// meter), "kinect" (the RGB-D SLAM tutorial's: fx 518, fy 519, c (325.5,
/// 253.5), 1000 per meter). std::nullopt for another name.
struct NamedCamera {
  PinholeCamera camera;  ///< intrinsics (640×480)
  double depth_scale = 5000.0;  ///< depth image units per meter
};
/// See NamedCamera.
std::optional<NamedCamera> named_camera(std::string_view name);

/// Options of read_rgbd_sequence.
struct RgbdSequenceOptions {
  /// Camera: empty to decide from the folder (a camera file in it; a TUM
  /// folder's name holding freiburg1/fr1, freiburg2/fr2 or freiburg3/fr3,
  /// else TUM's default; a numbered-frames folder's name holding "icl" is
  /// ICL-NUIM), a named camera (named_camera) or a camera file path.
  std::string camera;
  /// Depth units per meter; overrides the camera file's and the default.
  std::optional<double> depth_scale;
  /// TUM rgb.txt/depth.txt association: largest time difference, seconds,
  /// > 0. Default 0.02 (associate.py's).
  double max_time_difference = 0.02;
};

/// A sequence folder, listed.
struct RgbdSequence {
  std::string folder;                 ///< as given
  RgbdSequenceFormat format = RgbdSequenceFormat::Tum;
  std::vector<RgbdSequenceFrame> frames;  ///< in time order
  PinholeCamera camera;               ///< intrinsics of the color image
  double depth_scale = 5000.0;        ///< depth image units per meter
  std::string camera_source;          ///< where the camera came from (file or name)
  std::size_t unassociated_color = 0; ///< TUM: color images without a depth image in time
  /// The reference trajectory (T_world_camera at the frames' clock) and its
  /// file, when the folder has one (groundtruth.txt, pose.txt).
  std::vector<StampedPose3> reference;
  std::string reference_path;
};

/// Lists a sequence folder (see the file comment). Errors: IoError for a
/// folder that does not exist or a list file that cannot be read;
/// ParseError naming the file and line for a malformed list line, a camera
/// file that does not parse, a pose.txt line without 7 numbers; ParseError
/// for a folder that is none of the layouts, a color image without a depth
/// image of the same number, no frame at all, a numbered-frames folder
/// without a camera (the message says how to give one), an unknown camera
/// name. A listed image that does not exist is an IoError naming it.
/// Precondition (InvalidArgument): options valid.
RgbdSequence read_rgbd_sequence(const std::string& folder, const RgbdSequenceOptions& options = {});

}  // namespace rove
