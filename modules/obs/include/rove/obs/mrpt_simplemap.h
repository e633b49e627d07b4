#pragma once
/// \file
/// Reading MRPT's `.simplemap` files (CSimpleMap, formerly
/// CSensFrameProbSequence): a sequence of robot poses with uncertainty, each
/// with the sensory frame observed there. Plain or gzip.
///
/// Supported: CSimpleMap / CSensFrameProbSequence versions 0 (2D poses,
/// CPosePDFGaussian, converted with to_3d as MRPT's createFrom2D does) and 1
/// (CPose3DPDFGaussian). Version 2 (with an optional local twist per
/// keyframe) and pose PDFs other than Gaussians are rejected with a
/// rove::ParseError naming the file, the byte offset and the class.

#include <memory>
#include <string>
#include <vector>

#include "rove/obs/sensory_frame.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/serialization/archive.h"

namespace rove {

/// One keyframe: where the robot was (T_map_robot with its uncertainty;
/// meters, radians) and what it observed there.
struct SimpleMapKeyframe {
  /// Pose of the robot in the map frame with covariance (x, y, z, yaw,
  /// pitch, roll order, as MRPT).
  Pose3Gaussian pose;
  /// The observations taken at that pose; never null (an MRPT null frame is
  /// read as an empty frame).
  std::shared_ptr<const SensoryFrame> frame;
};

/// A whole simple map: the keyframes in file order.
struct SimpleMap {
  /// The keyframes.
  std::vector<SimpleMapKeyframe> keyframes;
};

/// Reads one CSimpleMap object at the current position of `ar`. Throws
/// rove::ParseError on another class, an unsupported version or bad data.
SimpleMap read_mrpt_simplemap(InArchive& ar);

/// Reads the `.simplemap` file at `path` (gzip detected from its first
/// bytes); the file must hold exactly one CSimpleMap. Throws rove::IoError if
/// it cannot be opened and rove::ParseError as read_mrpt_simplemap, or if
/// bytes follow the map.
SimpleMap load_mrpt_simplemap(const std::string& path, ArchiveLimits limits = {});

}  // namespace rove
