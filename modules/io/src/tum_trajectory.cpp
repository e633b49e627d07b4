#include "rove/io/tum_trajectory.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {

void write_tum_trajectory(const std::string& path, const std::vector<TimedPose2>& poses) {
  AtomicOutputFile out(path);
  out.write("# t x y z qx qy qz qw\n");
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto& p = poses[i];
    const double t = p.time.valid() ? p.time.to_seconds() : static_cast<double>(i);
    const double h = 0.5 * p.pose.phi();
    out.write(fmt::format("{:.6f} {:.6f} {:.6f} 0 0 0 {:.9f} {:.9f}\n", t, p.pose.x(),
                          p.pose.y(), std::sin(h), std::cos(h)));
  }
  out.commit();
}

std::vector<TumPose> read_tum_trajectory(const std::string& path) {
  const std::string text = read_input_file(path, 1ull << 32, "trajectory");
  std::vector<TumPose> out;
  std::size_t line_no = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t eol = std::min(text.find('\n', pos), text.size());
    const std::string_view line(text.data() + pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string_view::npos || line[first] == '#') continue;
    double v[8];
    std::size_t n = 0, i = first;
    while (i < line.size()) {
      const std::size_t end = std::min(line.find_first_of(" \t\r", i), line.size());
      if (end > i) {
        if (n == 8) {
          throw ParseError({printable(path), line_no, std::nullopt, "pose"}, "more than 8 fields (t x y z qx qy qz qw)");
        }
        const std::string_view tok = line.substr(i, end - i);
        const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v[n]);
        if (r.ec != std::errc() || r.ptr != tok.data() + tok.size() || !std::isfinite(v[n])) {
          static const char* const kFields[] = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
          throw ParseError({printable(path), line_no, std::nullopt, kFields[n]},
                           fmt::format("'{}' is not a finite number", printable(tok)));
        }
        ++n;
      }
      i = end + 1;
    }
    if (n != 8) {
      throw ParseError({printable(path), line_no, std::nullopt, "pose"},
                       fmt::format("{} fields, expected 8 (t x y z qx qy qz qw)", n));
    }
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (!(q.norm() > 1e-12)) throw ParseError({printable(path), line_no, std::nullopt, "qw"}, "the quaternion is zero");
    out.push_back({v[0], SE3d(q.normalized(), Eigen::Vector3d(v[1], v[2], v[3]))});
  }
  return out;
}

}  // namespace rove
