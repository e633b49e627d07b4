#include "rove/poses/pose2.h"

#include <ostream>

#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {

Pose2::Pose2(double x, double y, double phi) : x_(x), y_(y), phi_(0.0) {
  ROVE_CHECK_FINITE(x);
  ROVE_CHECK_FINITE(y);
  ROVE_CHECK_FINITE(phi);
  phi_ = wrap_to_pi(phi);
}

std::string Pose2::as_string() const {
  return fmt::format("[{:f} {:f} {:f}deg]", x_, y_, rad_to_deg(phi_));
}

Pose2 Pose2::from_string(std::string_view text) {
  const auto v = detail::parse_bracketed(text, {"x", "y", "phi_deg"}, "Pose2");
  return Pose2(v[0], v[1], deg_to_rad(v[2]));
}

std::string to_string(const Pose2& p) {
  // printf "%.03f" and "%.02f" as MRPT's operator<<.
  return fmt::format("({:.3f},{:.3f},{:.2f}deg)", p.x(), p.y(), rad_to_deg(p.phi()));
}

std::ostream& operator<<(std::ostream& os, const Pose2& p) { return os << to_string(p); }

}  // namespace rove
