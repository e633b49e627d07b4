#include "rove/maps/metric_map_points.h"

#include <cmath>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/angle.h"

namespace rove {

PointMapInsertionOptions PointMapInsertionOptions::from_config(const ConfigSection& s) {
  PointMapInsertionOptions o;
  o.min_dist_between_points = s.get<float>("minDistBetweenLaserPoints", o.min_dist_between_points);
  if (s.has("horizontalTolerance")) {
    o.horizontal_tolerance = static_cast<float>(deg_to_rad(s.get<double>("horizontalTolerance", 0.0)));
  }
  o.add_to_existing = s.get<bool>("addToExistingPointsMap", o.add_to_existing);
  o.also_interpolate = s.get<bool>("also_interpolate", o.also_interpolate);
  o.disable_deletion = s.get<bool>("disableDeletion", o.disable_deletion);
  o.fuse_with_existing = s.get<bool>("fuseWithExisting", o.fuse_with_existing);
  o.is_planar_map = s.get<bool>("isPlanarMap", o.is_planar_map);
  o.max_dist_for_interpolate = s.get<float>("maxDistForInterpolatePoints", o.max_dist_for_interpolate);
  o.insert_invalid_points = s.get<bool>("insertInvalidPoints", o.insert_invalid_points);
  o.arithmetic = s.get_enum("arithmetic", o.arithmetic, kArithmeticNames);
  if (!std::isfinite(o.min_dist_between_points)) s.fail("minDistBetweenLaserPoints", "must be finite");
  if (!(o.horizontal_tolerance >= 0)) s.fail("horizontalTolerance", "must be >= 0");
  if (!std::isfinite(o.max_dist_for_interpolate)) s.fail("maxDistForInterpolatePoints", "must be finite");
  return o;
}

PointMapLikelihoodOptions PointMapLikelihoodOptions::from_config(const ConfigSection& s) {
  PointMapLikelihoodOptions o;
  o.sigma_dist = s.get_in_range("sigma_dist", o.sigma_dist, 1e-300, 1e300);
  o.max_corr_distance = s.get_in_range("max_corr_distance", o.max_corr_distance, 1e-300, 1e300);
  const int d = s.get<int>("decimation", static_cast<int>(o.decimation));
  if (d < 1) s.fail("decimation", fmt::format("must be >= 1, got {}", d));
  o.decimation = static_cast<std::uint32_t>(d);
  return o;
}

namespace {
PointChannels channels_of(PointsMapFlavor f) {
  switch (f) {
    case PointsMapFlavor::Coloured: return PointChannels::Color;
    case PointsMapFlavor::Intensity: return PointChannels::Intensity;
    default: return PointChannels::None;
  }
}
}  // namespace

PointsMetricMap::PointsMetricMap(PointsMapFlavor flavor) : flavor_(flavor), map_(channels_of(flavor)) {}

std::string_view PointsMetricMap::kind() const noexcept {
  switch (flavor_) {
    case PointsMapFlavor::Simple: return "pointsMap";
    case PointsMapFlavor::Coloured: return "colourPointsMap";
    case PointsMapFlavor::Weighted: return "weightedPointsMap";
    case PointsMapFlavor::Intensity: return "pointsMapXYZI";
  }
  return "pointsMap";
}

bool PointsMetricMap::insert(const Observation& observation, const Pose3& T_map_robot) {
  if (const auto* scan = dynamic_cast<const RangeScan2D*>(&observation)) {
    return map_.insert(*scan, T_map_robot);
  }
  if (const auto* img = dynamic_cast<const RangeImage3D*>(&observation)) {
    return map_.insert(*img, T_map_robot);
  }
  return false;
}

bool PointsMetricMap::can_compute_likelihood(const Observation& o) const {
  return dynamic_cast<const RangeScan2D*>(&o) != nullptr ||
         dynamic_cast<const RangeImage3D*>(&o) != nullptr;
}

double PointsMetricMap::log_likelihood(const Observation& observation,
                                       const Pose3& T_map_robot) const {
  if (const auto* scan = dynamic_cast<const RangeScan2D*>(&observation)) {
    return map_.log_likelihood(*scan, T_map_robot);
  }
  if (const auto* img = dynamic_cast<const RangeImage3D*>(&observation)) {
    return map_.log_likelihood(*img, T_map_robot);
  }
  return 0.0;
}

void PointsMetricMap::clear() { map_.clear(); }

MapBounds PointsMetricMap::bounding_box() const {
  MapBounds b;
  const BoundingBox3 box = map_.bounding_box();
  if (box.empty()) return b;
  b.extend(box.min.cast<double>());
  b.extend(box.max.cast<double>());
  return b;
}

MapStatistics PointsMetricMap::statistics() const {
  MapStatistics s;
  s.elements = map_.size();
  s.unit = "points";
  s.bounds = bounding_box();
  return s;
}

std::unique_ptr<MetricMap> make_points_metric_map(const IniFile& ini, const std::string& p,
                                                  PointsMapFlavor flavor,
                                                  std::vector<IgnoredConfigKey>* ign) {
  ConfigSection is(ini, p + "_insertOpts", ign), ls(ini, p + "_likelihoodOpts", ign),
      rs(ini, p + "_renderOpts", ign), co(ini, p + "_colorOpts", ign);
  auto m = std::make_unique<PointsMetricMap>(flavor);
  m->points().insertion_options = PointMapInsertionOptions::from_config(is);
  m->points().likelihood_options = PointMapLikelihoodOptions::from_config(ls);
  rs.ignore({"point_size", "color.R", "color.G", "color.B", "colormap"},
            "render options only style MRPT's 3D view");
  co.ignore({"scheme", "z_min", "z_max", "d_max"}, "the color scheme only styles MRPT's 3D view");
  is.check_all_read();
  ls.check_all_read();
  rs.check_all_read();
  co.check_all_read();
  return m;
}

}  // namespace rove
