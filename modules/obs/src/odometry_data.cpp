#include "rove/obs/odometry_data.h"

#include "rove/serialization/version.h"

namespace rove {

void save(OutArchive& ar, const EncoderTicks& t) {
  write_version(ar, 1);
  ar.write_scalar(t.left);
  ar.write_scalar(t.right);
}

void load(InArchive& ar, EncoderTicks& t) {
  read_version(ar, "EncoderTicks", 1);
  t.left = ar.read_scalar<std::int32_t>("left ticks");
  t.right = ar.read_scalar<std::int32_t>("right ticks");
}

void save(OutArchive& ar, const Twist2& t) {
  write_version(ar, 1);
  ar.write_scalar(t.vx);
  ar.write_scalar(t.vy);
  ar.write_scalar(t.omega);
}

void load(InArchive& ar, Twist2& t) {
  read_version(ar, "Twist2", 1);
  t.vx = ar.read_scalar<double>("vx");
  t.vy = ar.read_scalar<double>("vy");
  t.omega = ar.read_scalar<double>("omega");
}

}  // namespace rove
