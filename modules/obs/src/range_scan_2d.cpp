#include "rove/obs/range_scan_2d.h"

#include <cmath>

#include "archive_helpers.h"
#include "rove/core/check.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {

void RangeScan2D::set_ranges(std::vector<float> new_ranges) {
  ranges = std::move(new_ranges);
  valid.assign(ranges.size(), false);
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const float r = ranges[i];
    valid[i] = std::isfinite(r) && r > 0.0f && r < max_range;
  }
  intensity.clear();
}

void RangeScan2D::check() const {
  ROVE_CHECK_MSG(valid.size() == ranges.size(),
                 "RangeScan2D: {} validity flags for {} ranges", valid.size(), ranges.size());
  ROVE_CHECK_MSG(intensity.empty() || intensity.size() == ranges.size(),
                 "RangeScan2D: {} intensities for {} ranges", intensity.size(), ranges.size());
  ROVE_CHECK_MSG(std::isfinite(aperture) && aperture > 0.0 && aperture <= 2.0 * kPi,
                 "RangeScan2D: aperture {} rad is not in (0, 2π]", aperture);
  ROVE_CHECK_MSG(std::isfinite(max_range) && max_range >= 0.0f,
                 "RangeScan2D: max_range {} m must be finite and >= 0", max_range);
  ROVE_CHECK_MSG(std::isfinite(std_error) && std_error >= 0.0f,
                 "RangeScan2D: std_error {} m must be finite and >= 0", std_error);
}

bool RangeScan2D::ray_yields_point(std::size_t i) const {
  ROVE_CHECK_LT(i, ranges.size());
  ROVE_CHECK_EQ(valid.size(), ranges.size());
  const float r = ranges[i];
  return valid[i] && std::isfinite(r) && r >= 0.0f;
}

double RangeScan2D::ray_angle(std::size_t i) const {
  const std::size_t n = ranges.size();
  ROVE_CHECK_MSG(n >= 2, "RangeScan2D: ray angles need at least 2 rays (spacing aperture/(N-1)), "
                         "the scan has {}", n);
  ROVE_CHECK_LT(i, n);
  ROVE_CHECK_MSG(std::isfinite(aperture) && aperture > 0.0 && aperture <= 2.0 * kPi,
                 "RangeScan2D: aperture {} rad is not in (0, 2π]", aperture);
  const double step = aperture / static_cast<double>(n - 1);
  const double k = static_cast<double>(i);
  return right_to_left ? -0.5 * aperture + k * step : 0.5 * aperture - k * step;
}

std::vector<double> RangeScan2D::ray_angles() const {
  std::vector<double> out(ranges.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = ray_angle(i);
  return out;
}

std::vector<std::size_t> RangeScan2D::point_ray_indices() const {
  check();
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (ray_yields_point(i)) out.push_back(i);
  }
  return out;
}

std::vector<Eigen::Vector3d> RangeScan2D::points_3d(ScanFrame frame) const {
  const std::vector<std::size_t> rays = point_ray_indices();
  std::vector<Eigen::Vector3d> out;
  out.reserve(rays.size());
  if (rays.empty()) return out;
  const bool to_robot = frame == ScanFrame::Robot;
  const Eigen::Matrix3d& R = T_robot_sensor.rotation();
  const Eigen::Vector3d& t = T_robot_sensor.translation();
  for (const std::size_t i : rays) {
    const double a = ray_angle(i);
    const double r = static_cast<double>(ranges[i]);
    const Eigen::Vector3d p(r * std::cos(a), r * std::sin(a), 0.0);
    out.push_back(to_robot ? Eigen::Vector3d(R * p + t) : p);
  }
  return out;
}

std::vector<Eigen::Vector2d> RangeScan2D::points_2d(ScanFrame frame) const {
  const std::vector<Eigen::Vector3d> p3 = points_3d(frame);
  std::vector<Eigen::Vector2d> out;
  out.reserve(p3.size());
  for (const auto& p : p3) out.emplace_back(p.x(), p.y());
  return out;
}

bool operator==(const RangeScan2D& a, const RangeScan2D& b) {
  return a.header_equals(b) && a.ranges == b.ranges && a.valid == b.valid &&
         a.intensity == b.intensity && a.aperture == b.aperture &&
         a.right_to_left == b.right_to_left && a.max_range == b.max_range &&
         a.std_error == b.std_error && a.beam_aperture == b.beam_aperture;
}

void RangeScan2D::save_payload(OutArchive& ar) const {
  check();
  save_header(ar);
  save(ar, ranges);
  save(ar, valid);
  save(ar, intensity);
  ar.write_scalar(aperture);
  ar.write_scalar(right_to_left);
  ar.write_scalar(max_range);
  ar.write_scalar(std_error);
  ar.write_scalar(beam_aperture);
}

void RangeScan2D::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  const std::uint64_t start = ar.offset();
  load_header(ar);
  load(ar, ranges);
  const std::uint64_t at = ar.offset();
  load(ar, valid);
  if (valid.size() != ranges.size()) {
    ar.fail_at(at, "valid", std::to_string(valid.size()) + " validity flags for " +
                                std::to_string(ranges.size()) + " ranges");
  }
  const std::uint64_t at_i = ar.offset();
  load(ar, intensity);
  if (!intensity.empty() && intensity.size() != ranges.size()) {
    ar.fail_at(at_i, "intensity", std::to_string(intensity.size()) + " intensities for " +
                                      std::to_string(ranges.size()) + " ranges");
  }
  aperture = ar.read_scalar<double>("aperture");
  right_to_left = ar.read_scalar<bool>("right_to_left");
  max_range = ar.read_scalar<float>("max_range");
  std_error = ar.read_scalar<float>("std_error");
  beam_aperture = ar.read_scalar<float>("beam_aperture");
  parse_guard(ar, start, kClassName, [&] { check(); });
}

}  // namespace rove
