#pragma once
/// \file
/// RGB-D sequences: the list of (color, depth) image pairs with their
/// times, the camera, the depth scale and the reference trajectory when the
/// folder has one. Three folder layouts are recognized, and rawlogs:
///  - TUM RGB-D (Sturm et al., IROS 2012): `associations.txt` (`t_rgb
///    rgb/… t_depth depth/…` per line), else `rgb.txt` and `depth.txt`
///    associated by nearest time (one-to-one, closest pairs first, as TUM's
///    associate.py); `groundtruth.txt` is the reference; depth 5000 per meter;
///  - ICL-NUIM as TUM-less numbered frames: `color/` (or `rgb/`) and
///    `depth/` holding `1.png`, `2.png`, … and `pose.txt` (`x y z qx qy qz
///    qw` per frame, T_world_camera): the reference; depth 5000 per meter;
///  - numbered frames with a camera file: the same folders, the camera from
///    a camera file in the folder (`camera.yaml`, `camera.txt`,
///    `parameters.txt`, `camera.ini`) or given;
///  - a rawlog (MRPT's or rove's, any AnyRawlogReader reads) of 3D range
///    scans with intensity images (MRPT's CObservation3DRangeScan,
///    RangeImage3D), bare or in sensory frames: the scans of the first
///    scan's sensor label are the frames, the intensity camera is the
///    camera (rove/vision/range_image_frame.h registers the depth to it).
/// Numbered frames get their number as time (seconds); rawlog frames their
/// timestamps (Unix seconds), or their number when no scan has one. Only
/// file names (and rawlog entry numbers) are listed here; images are read
/// by the pipeline.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/rawlog_reader.h"
#include "rove/io/trajectory_files.h"
#include "rove/obs/pinhole_camera.h"
#include "rove/obs/range_image_3d.h"

namespace rove {

/// Which layout a sequence folder has.
enum class RgbdSequenceFormat {
  Tum,             ///< TUM RGB-D benchmark folder
  NumberedFrames,  ///< color/ and depth/ with numbered images
  Rawlog,          ///< a rawlog of 3D range scans with intensity images
};

/// "tum", "numbered-frames" or "rawlog".
std::string_view to_string(RgbdSequenceFormat format);

/// One color image and its registered depth image.
struct RgbdSequenceFrame {
  double time = 0.0;        ///< seconds (the color image's)
  std::string color_path;   ///< color image file
  std::string depth_path;   ///< depth image file
  double depth_time = 0.0;  ///< seconds (the depth image's; equal to time for numbered frames)
  /// Rawlog frames (paths empty): the entry holding the scan (0-based, in
  /// file order) and the scan's index among the entry's range_images_of().
  std::uint64_t rawlog_entry = 0;
  std::size_t rawlog_scan = 0;
};

/// The 3D range scans (RangeImage3D) of a rawlog entry, in order: a bare
/// one, or those of a sensory frame; none in an action collection.
std::vector<std::shared_ptr<const RangeImage3D>> range_images_of(const RawlogEntry& entry);

/// The intrinsics and depth scale of a named camera: "tum-fr1", "tum-fr2",
/// "tum-fr3" (TUM's published calibrations of the RGB cameras; depth 5000
/// per meter), "tum" (TUM's default for registered depth: f 525, c (319.5,
/// 239.5)), "icl-nuim" (fx 481.2, fy −480, c (319.5, 239.5), 5000 per
/// meter), "kinect" (the RGB-D SLAM tutorial's: fx 518, fy 519, c (325.5,
/// 253.5), 1000 per meter). std::nullopt for another name.
struct NamedCamera {
  PinholeCamera camera;  ///< intrinsics (640×480)
  double depth_scale = 5000.0;  ///< depth image units per meter
  /// Rolling shutter: seconds from reading the first row to the last; 0 for
  /// a global shutter or a camera not measured. "tum-fr1": 0.02, calibrated
  /// on fr1/rpy without its ground truth (docs/rgbd-slam.md).
  double rolling_shutter_readout = 0.0;
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
  std::string folder;                 ///< as given (the rawlog file for Rawlog)
  RgbdSequenceFormat format = RgbdSequenceFormat::Tum;
  std::vector<RgbdSequenceFrame> frames;  ///< in time order
  PinholeCamera camera;               ///< intrinsics of the color image
  double depth_scale = 5000.0;        ///< depth image units per meter
  std::string camera_source;          ///< where the camera came from (file or name)
  double rolling_shutter_readout = 0.0;  ///< the named camera's (NamedCamera), else 0
  std::size_t unassociated_color = 0; ///< TUM: color images without a depth image in time
  /// Rawlog: the frames' sensor label, and the 3D range scans of other
  /// labels, left out.
  std::string sensor_label;
  std::size_t other_sensor_scans = 0;
  /// The reference trajectory (T_world_camera at the frames' clock) and its
  /// file, when the folder has one (groundtruth.txt, pose.txt).
  std::vector<StampedPose3> reference;
  std::string reference_path;
};

/// Lists a sequence folder or rawlog (see the file comment). Errors:
/// IoError for a path that does not exist or a list file that cannot be
/// read; for a rawlog, ParseError naming the file (and the entry) for a log
/// without 3D range scans, a scan without a depth or an intensity image, an
/// intensity image that is not 8-bit gray or RGB, a scan whose intensity
/// camera or image size differs from the first's, times that do not
/// increase, and the reader's errors; InvalidArgument when options.camera or
/// options.depth_scale is given for a rawlog (its scans carry both);
/// ParseError naming the file and line for a malformed list line, a camera
/// file that does not parse, a pose.txt line without 7 numbers; ParseError
/// for a folder that is none of the layouts, a color image without a depth
/// image of the same number, no frame at all, a numbered-frames folder
/// without a camera (the message says how to give one), an unknown camera
/// name. A listed image that does not exist is an IoError naming it.
/// Precondition (InvalidArgument): options valid.
RgbdSequence read_rgbd_sequence(const std::string& path, const RgbdSequenceOptions& options = {});

}  // namespace rove
