#include "rove/io/tum_trajectory.h"

#include <cmath>
#include <cstddef>

#include <fmt/format.h>

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

}  // namespace rove
