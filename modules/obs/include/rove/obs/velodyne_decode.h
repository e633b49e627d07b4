#pragma once
/// \file
/// decode_velodyne_scan: the points of a VelodyneScan's raw packets, in the
/// sensor frame, with the per-laser calibration the scan carries (MRPT's
/// CObservationVelodyneScan::generatePointCloud).
///
/// Sensors: the VLP-16 (a calibration of 16 lasers) and the HDL-32E (32).
/// Packet layout and firing times from their manuals: a VLP-16 block holds
/// two firing sequences of the 16 lasers, 2.304 µs apart within a sequence,
/// 55.296 µs between sequences, 110.592 µs a block; an HDL-32E block holds
/// the 32 lasers, 1.152 µs apart, 46.08 µs a block. Each return's azimuth is
/// its block's plus the sensor's turn since the block started, at the
/// median azimuth step between the packet's blocks (pairs of blocks in dual
/// return mode).
///
/// Geometry (MRPT's, for rawlogs MRPT recorded): with the laser's vertical
/// angle ω (the calibration's sin/cos), distance d = raw · 2 mm + distance
/// correction, horizontal and vertical offsets h, v and azimuth α (clockwise
/// seen from above, 0 along +x):
///   r = d cos ω + v sin ω,  x = r cos α + h sin α,  y = −(r sin α − h cos α),
///   z = d sin ω + v.
/// The calibration's azimuth correction is not applied (MRPT 2.5 does not;
/// it is zero for these sensors).
///
/// Thread-safety: a pure function.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include "rove/obs/velodyne_scan.h"

namespace rove {

/// Which returns are decoded, and how their azimuth is computed.
enum class VelodyneDecoding : std::uint8_t {
  /// Every return of every block (32 a block), each at its own interpolated
  /// azimuth, in double.
  Full = 0,
  /// MRPT 2.5.8's generatePointCloud, point for point: only the first 16
  /// returns of each block (the first firing sequence of a VLP-16, lasers
  /// 0–15 of an HDL-32E: half of the data), azimuths rounded to 0.01° and
  /// taken from its sine table, float arithmetic (velodyne_decode_mrpt.cpp).
  Mrpt = 1,
};

/// Options of decode_velodyne_scan (MRPT's TGeneratePointCloudParameters
/// defaults).
struct VelodyneDecodeOptions {
  /// Returns nearer than this (m), or than the scan's min_range_m, are
  /// dropped.
  double min_range_m = 1.0;
  /// Returns farther than this (m), or than the scan's max_range_m, are
  /// dropped.
  double max_range_m = std::numeric_limits<double>::infinity();
  /// Dual return mode: keep the strongest returns (odd blocks; one equal to
  /// the last return of its pair is always dropped).
  bool keep_strongest = true;
  /// Dual return mode: keep the last returns (even blocks).
  bool keep_last = true;
  /// Which returns, and how.
  VelodyneDecoding decoding = VelodyneDecoding::Full;
};

/// Why decoding ended.
enum class VelodyneDecodeTermination : std::uint8_t {
  Decoded = 0,                 ///< every packet was decoded
  NoCalibration = 1,           ///< the scan carries packets but no calibration
  UnsupportedCalibration = 2,  ///< a calibration for neither 16 nor 32 lasers
};

/// What decode_velodyne_scan produced.
struct VelodyneDecodeResult {
  /// The points (x, y, z, intensity, and per point its azimuth in radians
  /// and laser id), sensor frame, meters; empty unless ok().
  VelodynePointCloud cloud;
  /// Why it ended.
  VelodyneDecodeTermination termination = VelodyneDecodeTermination::Decoded;
  /// One line saying what happened; for a failure, what the scan lacks.
  std::string message;
  /// Returns read (non-zero distance), before the range and dual-return
  /// filters.
  std::size_t returns = 0;
  /// Blocks skipped for a header other than 0xEEFF (upper bank).
  std::size_t skipped_blocks = 0;
  /// True when the packets were decoded.
  bool ok() const noexcept { return termination == VelodyneDecodeTermination::Decoded; }
};

/// Decodes `scan`'s packets with its calibration (see the file comment).
/// A scan without packets decodes to no point. Throws InvalidArgument if a
/// range option is NaN or negative.
VelodyneDecodeResult decode_velodyne_scan(const VelodyneScan& scan, const VelodyneDecodeOptions& options = {});

}  // namespace rove
