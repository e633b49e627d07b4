// The points of a 2D scan with Arithmetic::Mrpt: MRPT 2.5.8's float
// arithmetic, so that a point map holds MRPT's points to the bit. Built with
// -ffp-contract=off (cmake/RoveModule.cmake). rove's default, in double, is
// in point_map.cpp; both share MRPT's filter.

#include <cmath>

#include "point_map_internal.h"

namespace rove::detail {

void mrpt_scan_candidates(const RangeScan2D& scan, const Pose3& T_frame_sensor,
                          std::vector<Eigen::Vector3f>& cand, std::vector<bool>& valid) {
  // MRPT's 2D scan insertion into a points map and its sin/cos table of the
  // rays: the ray angle accumulated in double from the first ray, its cos
  // and sin rounded to float, the sensor pose's rotation and translation
  // rounded to float, and x = t_x + (r·cos·R_xx + r·sin·R_xy) in float.
  // Computing in double instead moves points by an ulp or two, and
  // ICP-SLAM runs that match MRPT's to 1e-6 m can then take another gate
  // schedule and part by centimeters (docs/icp-slam.md).
  const std::size_t n = scan.size();
  const Eigen::Matrix<float, 3, 2> Rf = T_frame_sensor.rotation().leftCols<2>().cast<float>();
  const Eigen::Vector3f tf = T_frame_sensor.translation().cast<float>();
  const double step = (scan.right_to_left ? 1.0 : -1.0) * (scan.aperture / static_cast<double>(n - 1));
  double angle = (scan.right_to_left ? -0.5 : 0.5) * scan.aperture;
  for (std::size_t i = 0; i < n; ++i, angle += step) {
    if (!scan.ray_yields_point(i)) continue;
    const float r = scan.ranges[i];
    const float xs = r * static_cast<float>(std::cos(angle));
    const float ys = r * static_cast<float>(std::sin(angle));
    for (int d = 0; d < 3; ++d) cand[i][d] = tf[d] + (xs * Rf(d, 0) + ys * Rf(d, 1));
    valid[i] = true;
  }
}

}  // namespace rove::detail
