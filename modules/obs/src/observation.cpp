#include "rove/obs/observation.h"

#include "archive_helpers.h"
#include "rove/serialization/version.h"

namespace rove {

bool Observation::header_equals(const Observation& other) const {
  return timestamp == other.timestamp && sensor_label == other.sensor_label &&
         T_robot_sensor == other.T_robot_sensor;
}

void Observation::save_header(OutArchive& ar) const {
  write_version(ar, 1);
  ar.write_scalar(timestamp.ns);
  save(ar, sensor_label);
  detail::save_pose3(ar, T_robot_sensor);
}

void Observation::load_header(InArchive& ar) {
  read_version(ar, "Observation header", 1);
  timestamp.ns = ar.read_scalar<std::int64_t>("timestamp");
  load(ar, sensor_label);
  T_robot_sensor = detail::load_pose3(ar, "T_robot_sensor");
}

}  // namespace rove
