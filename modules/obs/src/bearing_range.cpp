#include "rove/obs/bearing_range.h"

#include <cmath>

#include "rove/core/check.h"
#include "rove/serialization/eigen.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {

Eigen::Vector3d LandmarkMeasurement::point_in_sensor() const {
  const double r = range, cy = std::cos(double{yaw}), sy = std::sin(double{yaw});
  const double cp = std::cos(double{pitch}), sp = std::sin(double{pitch});
  return {r * cp * cy, r * cp * sy, -r * sp};
}

Eigen::Matrix3d BearingRange::measurement_covariance(std::size_t i) const {
  ROVE_CHECK_LT(i, measurements.size());
  if (measurements[i].covariance) return *measurements[i].covariance;
  const double sr = sensor_std_range, sy = sensor_std_yaw, sp = sensor_std_pitch;
  return Eigen::Vector3d(sr * sr, sy * sy, sp * sp).asDiagonal();
}

bool operator==(const BearingRange& a, const BearingRange& b) {
  return a.header_equals(b) && a.measurements == b.measurements &&
         a.min_sensor_distance == b.min_sensor_distance &&
         a.max_sensor_distance == b.max_sensor_distance &&
         a.field_of_view_yaw == b.field_of_view_yaw &&
         a.field_of_view_pitch == b.field_of_view_pitch &&
         a.sensor_std_range == b.sensor_std_range && a.sensor_std_yaw == b.sensor_std_yaw &&
         a.sensor_std_pitch == b.sensor_std_pitch;
}

void save(OutArchive& ar, const LandmarkMeasurement& m) {
  write_version(ar, 1);
  ar.write_scalar(m.landmark_id);
  ar.write_scalar(m.range);
  ar.write_scalar(m.yaw);
  ar.write_scalar(m.pitch);
  save(ar, m.covariance);
}

void load(InArchive& ar, LandmarkMeasurement& m) {
  read_version(ar, "LandmarkMeasurement", 1);
  m.landmark_id = ar.read_scalar<std::int32_t>("landmark_id");
  m.range = ar.read_scalar<float>("range");
  m.yaw = ar.read_scalar<float>("yaw");
  m.pitch = ar.read_scalar<float>("pitch");
  load(ar, m.covariance);
}

void BearingRange::save_payload(OutArchive& ar) const {
  save_header(ar);
  save(ar, measurements);
  for (const float f : {min_sensor_distance, max_sensor_distance, field_of_view_yaw,
                        field_of_view_pitch, sensor_std_range, sensor_std_yaw, sensor_std_pitch}) {
    ar.write_scalar(f);
  }
}

void BearingRange::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  load(ar, measurements);
  for (float* f : {&min_sensor_distance, &max_sensor_distance, &field_of_view_yaw,
                   &field_of_view_pitch, &sensor_std_range, &sensor_std_yaw, &sensor_std_pitch}) {
    *f = ar.read_scalar<float>("BearingRange parameters");
  }
}

}  // namespace rove
