#pragma once
/// \file
/// Reading MRPT's `.simplemap` files (CSimpleMap, formerly
/// CSensFrameProbSequence): a sequence of robot poses with uncertainty, each
/// with the sensory frame observed there. Plain or gzip.
///
/// Supported: CSimpleMap / CSensFrameProbSequence versions 0 (2D pose PDFs,
/// converted to 3D as MRPT's CPose3DPDF::createFrom2D does), 1 (3D pose
/// PDFs) and 2 (as 1, plus an optional local twist per keyframe, written by
/// MRPT >= 2.11). Pose PDFs: CPosePDFGaussian, CPosePDFParticles,
/// CPosePDFSOG (version 0), CPose3DPDFGaussian, CPose3DPDFParticles,
/// CPose3DPDFSOG (versions 1, 2). Anything else is a rove::ParseError naming
/// the file, the byte offset and the class.

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rove/obs/robot_movement_3d.h"

#include "rove/obs/sensory_frame.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/pdf_particles.h"
#include "rove/poses/pdf_sog.h"
#include "rove/serialization/archive.h"

namespace rove {

/// A keyframe's pose PDF as stored: a Gaussian, weighted samples or a sum
/// of Gaussians (T_map_robot; meters, radians; covariance order x, y, z,
/// yaw, pitch, roll as MRPT).
struct KeyframePosePdf {
  /// The stored PDF.
  std::variant<Pose3Gaussian, Pose3Particles, Pose3SOG> pdf;
  /// The PDF's mean (for particles and mixtures, their weighted mean).
  /// Precondition (InvalidArgument): particles/modes not empty.
  Pose3 mean() const;
  /// The PDF's covariance (for particles and mixtures, around mean()).
  /// Precondition as mean().
  Eigen::Matrix<double, 6, 6> covariance() const;
};

/// The 3D PDF MRPT's CPose3DPDF::createFrom2D makes of a 2D pose PDF: each
/// pose, mean and covariance lifted with z = pitch = roll = 0 (to_3d).
KeyframePosePdf keyframe_pdf_from_2d(const Pose2Gaussian& g);
/// As above, for particles.
KeyframePosePdf keyframe_pdf_from_2d(const Pose2Particles& p);
/// As above, for a sum of Gaussians.
KeyframePosePdf keyframe_pdf_from_2d(const Pose2SOG& s);

/// One keyframe: where the robot was (T_map_robot with its uncertainty;
/// meters, radians) and what it observed there.
struct SimpleMapKeyframe {
  /// Pose of the robot in the map frame, with uncertainty.
  KeyframePosePdf pose;
  /// The observations taken at that pose; never null (an MRPT null frame is
  /// read as an empty frame).
  std::shared_ptr<const SensoryFrame> frame;
  /// The robot's velocity at the keyframe in its own frame, if stored
  /// (CSimpleMap version 2).
  std::optional<Twist3> local_twist;
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
