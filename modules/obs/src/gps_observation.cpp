#include "rove/obs/gps_observation.h"

#include <cmath>
#include <string>

#include "rove/core/check.h"
#include "rove/serialization/eigen.h"
#include "rove/serialization/stl.h"

namespace rove {

void GpsObservation::check() const {
  ROVE_CHECK_MSG(std::isfinite(latitude_deg) && std::abs(latitude_deg) <= 90.0,
                 "GpsObservation: latitude {} deg not in [-90, 90]", latitude_deg);
  ROVE_CHECK_MSG(std::isfinite(longitude_deg) && std::abs(longitude_deg) <= 180.0,
                 "GpsObservation: longitude {} deg not in [-180, 180]", longitude_deg);
  ROVE_CHECK_FINITE(altitude_m);
  ROVE_CHECK_MSG(std::isfinite(hdop) && hdop >= 0.0, "GpsObservation: hdop {} must be >= 0",
                 hdop);
  if (enu_position) ROVE_CHECK_FINITE(*enu_position);
  if (enu_covariance) ROVE_CHECK_FINITE(*enu_covariance);
}

bool operator==(const GpsObservation& a, const GpsObservation& b) {
  return a.header_equals(b) && a.latitude_deg == b.latitude_deg &&
         a.longitude_deg == b.longitude_deg && a.altitude_m == b.altitude_m &&
         a.fix_quality == b.fix_quality && a.satellites == b.satellites && a.hdop == b.hdop &&
         a.enu_position == b.enu_position && a.enu_covariance == b.enu_covariance;
}

void GpsObservation::save_payload(OutArchive& ar) const {
  save_header(ar);
  ar.write_scalar(latitude_deg);
  ar.write_scalar(longitude_deg);
  ar.write_scalar(altitude_m);
  ar.write_scalar(static_cast<std::uint8_t>(fix_quality));
  ar.write_scalar(satellites);
  ar.write_scalar(hdop);
  save(ar, enu_position);
  save(ar, enu_covariance);
}

void GpsObservation::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  latitude_deg = ar.read_scalar<double>("latitude");
  longitude_deg = ar.read_scalar<double>("longitude");
  altitude_m = ar.read_scalar<double>("altitude");
  const std::uint64_t at = ar.offset();
  const auto q = ar.read_scalar<std::uint8_t>("fix_quality");
  if (q > static_cast<std::uint8_t>(GpsFixQuality::kSimulation)) {
    ar.fail_at(at, "fix_quality", "unknown GPS fix quality " + std::to_string(q));
  }
  fix_quality = static_cast<GpsFixQuality>(q);
  satellites = ar.read_scalar<std::uint32_t>("satellites");
  hdop = ar.read_scalar<double>("hdop");
  load(ar, enu_position);
  load(ar, enu_covariance);
}

std::unique_ptr<Observation> GpsObservation::clone() const {
  return std::make_unique<GpsObservation>(*this);
}

bool GpsObservation::equals(const Observation& other) const {
  const auto* o = dynamic_cast<const GpsObservation*>(&other);
  return o != nullptr && *this == *o;
}

}  // namespace rove
