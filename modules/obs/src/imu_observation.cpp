#include "rove/obs/imu_observation.h"

#include <cmath>

#include "archive_helpers.h"
#include "rove/core/check.h"
#include "rove/serialization/eigen.h"
#include "rove/serialization/stl.h"

namespace rove {

void ImuObservation::check() const {
  if (angular_velocity) ROVE_CHECK_FINITE(*angular_velocity);
  if (linear_acceleration) ROVE_CHECK_FINITE(*linear_acceleration);
  if (orientation) {
    ROVE_CHECK_FINITE(orientation->coeffs());
    ROVE_CHECK_MSG(std::abs(orientation->norm() - 1.0) <= 1e-6,
                   "ImuObservation: orientation quaternion has norm {}, expected 1",
                   orientation->norm());
  }
}

bool operator==(const ImuObservation& a, const ImuObservation& b) {
  const bool same_q = a.orientation.has_value() == b.orientation.has_value() &&
                      (!a.orientation || a.orientation->coeffs() == b.orientation->coeffs());
  return a.header_equals(b) && a.angular_velocity == b.angular_velocity &&
         a.linear_acceleration == b.linear_acceleration && same_q;
}

void ImuObservation::save_payload(OutArchive& ar) const {
  save_header(ar);
  save(ar, angular_velocity);
  save(ar, linear_acceleration);
  ar.write_scalar(orientation.has_value());
  if (orientation) {
    for (const double c : {orientation->w(), orientation->x(), orientation->y(), orientation->z()}) {
      ar.write_scalar(c);
    }
  }
}

void ImuObservation::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  const std::uint64_t start = ar.offset();
  load_header(ar);
  load(ar, angular_velocity);
  load(ar, linear_acceleration);
  if (ar.read_scalar<bool>("has orientation")) {
    double q[4];
    for (double& c : q) c = ar.read_scalar<double>("orientation");
    orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  } else {
    orientation.reset();
  }
  parse_guard(ar, start, kClassName, [&] { check(); });
}

}  // namespace rove
