#pragma once
// MRPT 2.5.8's arithmetic in CObservationVelodyneScan::generatePointCloud
// (internal; VelodyneDecoding::Mrpt), established against its output on
// real and synthetic scans (modules/io/tests): azimuth adjustments rounded
// to whole hundredths of a degree half to even, a VLP-16's firing times in
// float and an HDL-32E's in double, sines and cosines from a table of 36,000
// angles −π + i · 2π / 35,999, everything else in float.
#include <cstdint>

#include "rove/obs/velodyne_scan.h"

namespace rove::detail {

// The azimuth (hundredths of a degree, 0..35999) MRPT gives return `laser`
// of block `block` (of a pair `pair` in dual mode) whose block azimuth is
// `azimuth` and the packet's azimuth step `step`.
int mrpt_velodyne_azimuth(std::size_t lasers, int block, int pair, int laser, std::uint16_t azimuth, int step);

// MRPT's point for one return at that azimuth: x, y, z in the sensor frame;
// false when its distance is outside [min_range, max_range] (float).
bool mrpt_velodyne_point(std::uint16_t raw_distance, const VelodyneLaserCalibration& c, int azimuth,
                         float min_range, float max_range, float xyz[3]);

}  // namespace rove::detail
