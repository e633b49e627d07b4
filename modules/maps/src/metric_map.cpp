#include "rove/maps/metric_map.h"

namespace rove {

std::size_t MetricMap::insert(const SensoryFrame& frame, const Pose3& T_map_robot) {
  std::size_t used = 0;
  for (const auto& o : frame.observations) {
    if (insert(*o, T_map_robot)) ++used;
  }
  return used;
}

}  // namespace rove
