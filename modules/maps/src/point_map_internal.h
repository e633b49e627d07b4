#pragma once
// The candidate points of a 2D scan in MRPT's arithmetic (point_map_mrpt.cpp),
// for detail::scan_points (point_map.cpp).

#include <vector>

#include <Eigen/Core>

#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose3.h"

namespace rove::detail {

/// Ray i of `scan` with a point (RangeScan2D::ray_yields_point) as MRPT
/// 2.5.8's loadFromRangeScan computes it, at the sensor pose T_frame_sensor:
/// into cand[i], with valid[i] set. Preconditions: scan.check() passed,
/// cand and valid have scan.size() entries.
void mrpt_scan_candidates(const RangeScan2D& scan, const Pose3& T_frame_sensor,
                          std::vector<Eigen::Vector3f>& cand, std::vector<bool>& valid);

}  // namespace rove::detail
