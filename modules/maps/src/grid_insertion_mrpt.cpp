// Scan insertion with Arithmetic::Mrpt: MRPT 2.5.8's float ray geometry, so
// that the cells equal MRPT's to the bit (tests OccupancyGridMrptCompat.*).
// Built with -ffp-contract=off (cmake/RoveModule.cmake). rove's default
// geometry, in double with the scan's own ray angles, is in
// grid_insertion.cpp; both share the integer ray tracer.

#include "grid_insertion_rays.h"
#include "grid_internal.h"

namespace rove::detail {

RayDirections<float> mrpt_ray_directions(const RangeScan2D& scan, const Pose3& T_map_sensor,
                                         int step, bool widening) {
  RayDirections<float> d;
  d.px = static_cast<float>(T_map_sensor.x());
  d.py = static_cast<float>(T_map_sensor.y());
  d.step = step;
  const bool upside_down = T_map_sensor.rotation()(2, 2) < 0;
  const auto n_rays = static_cast<int>(scan.size());
  const float aperture = static_cast<float>(scan.aperture);
  const double yaw = T_map_sensor.yaw();
  const bool ccw = scan.right_to_left != upside_down;
  const float d_angle = ccw ? static_cast<float>(step) * aperture / static_cast<float>(n_rays)
                            : -static_cast<float>(step) * aperture / static_cast<float>(n_rays);
  // The first angle: MRPT rounds differently in its two branches.
  float a = widening ? (ccw ? static_cast<float>(yaw) - 0.5f * aperture
                            : static_cast<float>(yaw) + 0.5f * aperture)
                     : static_cast<float>(ccw ? yaw - 0.5f * aperture : yaw + 0.5f * aperture);
  for (int i = 0; i < n_rays; i += step, a += d_angle) d.angle.push_back(a);
  d.half_beam = 0.5f * aperture / static_cast<float>(n_rays);
  return d;
}

template GridInsertResult insert_rays(OccupancyGridT<std::int8_t>&, const RangeScan2D&,
                                      const GridInsertionOptions&, const InsertStrengths&,
                                      const RayDirections<float>&);
template GridInsertResult insert_rays(OccupancyGridT<std::int16_t>&, const RangeScan2D&,
                                      const GridInsertionOptions&, const InsertStrengths&,
                                      const RayDirections<float>&);
template ScanInformation scan_information_rays(const OccupancyGridT<std::int8_t>&,
                                               const RangeScan2D&, const GridInsertionOptions&,
                                               const InsertStrengths&, const RayDirections<float>&);
template ScanInformation scan_information_rays(const OccupancyGridT<std::int16_t>&,
                                               const RangeScan2D&, const GridInsertionOptions&,
                                               const InsertStrengths&, const RayDirections<float>&);

}  // namespace rove::detail
