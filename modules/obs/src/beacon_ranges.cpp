#include "rove/obs/beacon_ranges.h"

#include "rove/serialization/eigen.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {

std::optional<float> BeaconRanges::range_to(std::int32_t id) const {
  for (const auto& r : readings) {
    if (r.beacon_id == id) return r.range;
  }
  return std::nullopt;
}

bool operator==(const BeaconRanges& a, const BeaconRanges& b) {
  return a.header_equals(b) && a.readings == b.readings &&
         a.min_sensor_distance == b.min_sensor_distance &&
         a.max_sensor_distance == b.max_sensor_distance && a.std_error == b.std_error &&
         a.aux_estimate == b.aux_estimate;
}

void save(OutArchive& ar, const BeaconRange& r) {
  write_version(ar, 1);
  ar.write_scalar(r.beacon_id);
  ar.write_scalar(r.range);
  save(ar, r.position_on_robot);
}

void load(InArchive& ar, BeaconRange& r) {
  read_version(ar, "BeaconRange", 1);
  r.beacon_id = ar.read_scalar<std::int32_t>("beacon_id");
  r.range = ar.read_scalar<float>("range");
  load(ar, r.position_on_robot);
}

void BeaconRanges::save_payload(OutArchive& ar) const {
  save_header(ar);
  save(ar, readings);
  ar.write_scalar(min_sensor_distance);
  ar.write_scalar(max_sensor_distance);
  ar.write_scalar(std_error);
  // version 2
  ar.write_scalar(aux_estimate.has_value());
  if (aux_estimate) {
    ar.write_scalar(aux_estimate->x_m);
    ar.write_scalar(aux_estimate->y_m);
    save(ar, aux_estimate->heading_rad);
  }
}

void BeaconRanges::load_payload(InArchive& ar, std::uint8_t version) {
  load_header(ar);
  load(ar, readings);
  min_sensor_distance = ar.read_scalar<float>("min_sensor_distance");
  max_sensor_distance = ar.read_scalar<float>("max_sensor_distance");
  std_error = ar.read_scalar<float>("std_error");
  aux_estimate.reset();
  if (version >= 2 && ar.read_scalar<bool>("has aux_estimate")) {
    BeaconAuxEstimate e;
    e.x_m = ar.read_scalar<double>("aux_estimate.x");
    e.y_m = ar.read_scalar<double>("aux_estimate.y");
    load(ar, e.heading_rad);
    aux_estimate = e;
  }
}

}  // namespace rove
