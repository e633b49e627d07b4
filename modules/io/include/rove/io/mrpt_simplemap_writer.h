#pragma once
/// \file
/// Writing ICP-SLAM keyframes as an MRPT `.simplemap` (CSimpleMap version 1,
/// as MRPT 2.5.8 writes it), so MRPT's tools (simplemap viewers, map
/// building from a simple map) and rove's load_mrpt_simplemap read it:
///   CSimpleMap v1: u32 count, then per keyframe a CPose3DPDFGaussian v1
///   (CPose3D v3 mean: x y z and the rotation row by row; the 6×6 covariance
///   as its diagonal then the upper off-diagonal terms row by row) and a
///   CSensoryFrame v2 (u32 count, the observations).
/// Observations written: CObservation2DRangeScan version 7 (aperture,
/// right-to-left, max range, sensor pose, ranges, validity, std error,
/// timestamp, beam aperture, label, deltaPitch 0, no intensity). Class names
/// carry MRPT 2.x's namespaces. Little-endian, uncompressed.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/observation.h"
#include "rove/poses/pose2.h"

namespace rove {

/// One keyframe to write: T_map_robot with its covariance (x, y, phi) and
/// the observation taken there.
struct SimpleMapEntry2D {
  Pose2 pose;                                          ///< T_map_robot
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();///< (x, y, phi)
  const Observation* observation = nullptr;            ///< never null
};

/// What write_mrpt_simplemap wrote.
struct SimpleMapWriteReport {
  std::size_t keyframes = 0;  ///< keyframes written
  std::size_t skipped = 0;    ///< keyframes left out: observation kind not writable
};

/// Writes `entries` to `path`. Keyframes whose observation is not a
/// RangeScan2D are left out (counted in the report). Throws IoError if the
/// file cannot be written, InvalidArgument on a null observation.
SimpleMapWriteReport write_mrpt_simplemap(const std::string& path,
                                          const std::vector<SimpleMapEntry2D>& entries);

}  // namespace rove
