#include "rove/obs/odometry_observation.h"

#include "archive_helpers.h"
#include "rove/serialization/stl.h"

namespace rove {

bool operator==(const OdometryObservation& a, const OdometryObservation& b) {
  return a.header_equals(b) && a.odometry == b.odometry && a.encoder_ticks == b.encoder_ticks &&
         a.velocity == b.velocity;
}

void OdometryObservation::save_payload(OutArchive& ar) const {
  save_header(ar);
  detail::save_pose2(ar, odometry);
  save(ar, encoder_ticks);
  save(ar, velocity);
}

void OdometryObservation::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  odometry = detail::load_pose2(ar, "odometry");
  load(ar, encoder_ticks);
  load(ar, velocity);
}

}  // namespace rove
