#include <ostream>
#include <sstream>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/poses/point2.h"
#include "rove/poses/point3.h"

namespace rove {

Point2::Point2(double x_m, double y_m) : x(x_m), y(y_m) {
  ROVE_CHECK_FINITE(x_m);
  ROVE_CHECK_FINITE(y_m);
}

std::string Point2::as_string() const { return fmt::format("[{:f} {:f}]", x, y); }

Point2 Point2::from_string(std::string_view text) {
  const auto v = detail::parse_bracketed(text, {"x", "y"}, "Point2");
  return Point2(v[0], v[1]);
}

std::ostream& operator<<(std::ostream& os, const Point2& p) {
  return os << '(' << p.x << ',' << p.y << ')';
}

std::string to_string(const Point2& p) {
  std::ostringstream os;
  os << p;
  return os.str();
}

Point3::Point3(double x_m, double y_m, double z_m) : x(x_m), y(y_m), z(z_m) {
  ROVE_CHECK_FINITE(x_m);
  ROVE_CHECK_FINITE(y_m);
  ROVE_CHECK_FINITE(z_m);
}

std::string Point3::as_string() const { return fmt::format("[{:f} {:f} {:f}]", x, y, z); }

Point3 Point3::from_string(std::string_view text) {
  const auto v = detail::parse_bracketed(text, {"x", "y", "z"}, "Point3");
  return Point3(v[0], v[1], v[2]);
}

std::ostream& operator<<(std::ostream& os, const Point3& p) {
  return os << '(' << p.x << ',' << p.y << ',' << p.z << ')';
}

std::string to_string(const Point3& p) {
  std::ostringstream os;
  os << p;
  return os.str();
}

}  // namespace rove
