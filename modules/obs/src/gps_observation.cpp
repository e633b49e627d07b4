#include "rove/obs/gps_observation.h"

#include <cmath>
#include <string>

#include "archive_helpers.h"
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
  ROVE_CHECK_FINITE(geoid_separation_m);
  if (utc_time) ROVE_CHECK_FINITE(utc_time->second);
  if (rmc) {
    ROVE_CHECK_FINITE(rmc->utc_time.second);
    ROVE_CHECK_MSG(std::isfinite(rmc->latitude_deg) && std::abs(rmc->latitude_deg) <= 90.0,
                   "GpsObservation: RMC latitude {} deg not in [-90, 90]", rmc->latitude_deg);
    ROVE_CHECK_MSG(std::isfinite(rmc->longitude_deg) && std::abs(rmc->longitude_deg) <= 180.0,
                   "GpsObservation: RMC longitude {} deg not in [-180, 180]", rmc->longitude_deg);
    ROVE_CHECK_FINITE(rmc->speed_knots);
    ROVE_CHECK_FINITE(rmc->course_deg);
    ROVE_CHECK_FINITE(rmc->magnetic_variation_deg);
  }
}

void save(OutArchive& ar, const GpsUtcTime& t) {
  ar.write_scalar(t.hour);
  ar.write_scalar(t.minute);
  ar.write_scalar(t.second);
}

void load(InArchive& ar, GpsUtcTime& t) {
  t.hour = ar.read_scalar<std::uint8_t>("utc_time.hour");
  t.minute = ar.read_scalar<std::uint8_t>("utc_time.minute");
  t.second = ar.read_scalar<double>("utc_time.second");
}

void save(OutArchive& ar, const GpsRmc& r) {
  save(ar, r.utc_time);
  ar.write_scalar(static_cast<std::uint8_t>(r.status));
  for (double v : {r.latitude_deg, r.longitude_deg, r.speed_knots, r.course_deg}) ar.write_scalar(v);
  ar.write_scalar(r.day);
  ar.write_scalar(r.month);
  ar.write_scalar(r.year);
  ar.write_scalar(r.magnetic_variation_deg);
  ar.write_scalar(static_cast<std::uint8_t>(r.mode));
}

void load(InArchive& ar, GpsRmc& r) {
  load(ar, r.utc_time);
  r.status = static_cast<char>(ar.read_scalar<std::uint8_t>("rmc.status"));
  for (double* v : {&r.latitude_deg, &r.longitude_deg, &r.speed_knots, &r.course_deg}) {
    *v = ar.read_scalar<double>("rmc");
  }
  r.day = ar.read_scalar<std::uint8_t>("rmc.day");
  r.month = ar.read_scalar<std::uint8_t>("rmc.month");
  r.year = ar.read_scalar<std::uint8_t>("rmc.year");
  r.magnetic_variation_deg = ar.read_scalar<double>("rmc.magnetic_variation");
  r.mode = static_cast<char>(ar.read_scalar<std::uint8_t>("rmc.mode"));
}

bool operator==(const GpsObservation& a, const GpsObservation& b) {
  return a.header_equals(b) && a.latitude_deg == b.latitude_deg &&
         a.longitude_deg == b.longitude_deg && a.altitude_m == b.altitude_m &&
         a.fix_quality == b.fix_quality && a.satellites == b.satellites && a.hdop == b.hdop &&
         a.enu_position == b.enu_position && a.enu_covariance == b.enu_covariance &&
         a.utc_time == b.utc_time && a.geoid_separation_m == b.geoid_separation_m &&
         a.rmc == b.rmc && a.original_received_timestamp == b.original_received_timestamp &&
         a.has_satellite_timestamp == b.has_satellite_timestamp;
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
  // version 2
  save(ar, utc_time);
  ar.write_scalar(geoid_separation_m);
  save(ar, rmc);
  ar.write_scalar(original_received_timestamp.ns);
  ar.write_scalar(has_satellite_timestamp);
}

void GpsObservation::load_payload(InArchive& ar, std::uint8_t version) {
  const std::uint64_t start = ar.offset();
  load_header(ar);
  latitude_deg = ar.read_scalar<double>("latitude");
  longitude_deg = ar.read_scalar<double>("longitude");
  altitude_m = ar.read_scalar<double>("altitude");
  const std::uint64_t at = ar.offset();
  const auto q = ar.read_scalar<std::uint8_t>("fix_quality");
  if (q > static_cast<std::uint8_t>(GpsFixQuality::Simulation)) {
    ar.fail_at(at, "fix_quality", "unknown GPS fix quality " + std::to_string(q));
  }
  fix_quality = static_cast<GpsFixQuality>(q);
  satellites = ar.read_scalar<std::uint32_t>("satellites");
  hdop = ar.read_scalar<double>("hdop");
  load(ar, enu_position);
  load(ar, enu_covariance);
  if (version >= 2) {
    load(ar, utc_time);
    geoid_separation_m = ar.read_scalar<double>("geoid_separation");
    load(ar, rmc);
    original_received_timestamp.ns = ar.read_scalar<std::int64_t>("original_received_timestamp");
    has_satellite_timestamp = ar.read_scalar<bool>("has_satellite_timestamp");
  } else {
    utc_time.reset();
    geoid_separation_m = 0.0;
    rmc.reset();
    original_received_timestamp = Timestamp::invalid();
    has_satellite_timestamp = false;
  }
  // Latitude/longitude ranges and finite values, as MRPT's reader checks.
  parse_guard(ar, start, kClassName, [&] { check(); });
}

}  // namespace rove
