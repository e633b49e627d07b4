#include "rove/maps/grid_insertion.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/angle.h"
#include "grid_insertion_rays.h"
#include "grid_internal.h"

namespace rove {

GridInsertionOptions GridInsertionOptions::from_config(const ConfigSection& config) {
  GridInsertionOptions o;
  const IniFile& ini = config.ini();
  const std::string_view section = config.name();
  const std::string sec(section);
  const auto read_float = [&](const char* key, float& v) {
    if (ini.has(section, key)) v = ini.get<float>(section, key);
  };
  const auto read_bool = [&](const char* key, bool& v) {
    if (ini.has(section, key)) v = ini.get<bool>(section, key);
  };
  read_float("mapAltitude", o.map_altitude);
  read_float("maxDistanceInsertion", o.max_distance_insertion);
  read_float("maxOccupancyUpdateCertainty", o.max_occupancy_update_certainty);
  read_float("maxFreenessUpdateCertainty", o.max_freeness_update_certainty);
  read_float("maxFreenessInvalidRanges", o.max_freeness_invalid_ranges);
  read_bool("useMapAltitude", o.use_map_altitude);
  read_bool("considerInvalidRangesAsFreeSpace", o.consider_invalid_ranges_as_free_space);
  if (ini.has(section, "decimation")) {
    const int d = ini.get<int>(section, "decimation");
    if (d < 1 || d > 65535) {
      throw ConfigError(ini.source(), sec, "decimation", "must be in [1, 65535]");
    }
    o.decimation = static_cast<std::uint16_t>(d);
  }
  if (ini.has(section, "horizontalTolerance")) {
    const float deg = ini.get<float>(section, "horizontalTolerance");
    o.horizontal_tolerance = static_cast<float>(deg * (kPi / 180.0));
  }
  read_float("CFD_features_gaussian_size", o.cfd_features_gaussian_size);
  read_float("CFD_features_median_size", o.cfd_features_median_size);
  read_bool("wideningBeamsWithDistance", o.widening_beams_with_distance);
  if (ini.has(section, "arithmetic"))
    o.arithmetic = ini.get_enum<Arithmetic>(section, "arithmetic", kArithmeticNames);
  // Each value against its range, naming the key (check() below is the
  // precondition of the algorithms and stays the last line of defence).
  const auto need = [&](bool ok, const char* key, float v, std::string_view range) {
    if (!ok) {
      throw ConfigError(ini.source(), sec, key,
                        fmt::format("line {}: {} is outside {}", ini.line(section, key).value_or(0),
                                    v, range));
    }
  };
  const auto unit = [](float v) { return v >= 0.0f && v <= 1.0f; };
  need(std::isfinite(o.map_altitude), "mapAltitude", o.map_altitude, "the finite numbers");
  need(std::isfinite(o.max_distance_insertion) && o.max_distance_insertion > 0.0f,
       "maxDistanceInsertion", o.max_distance_insertion, "(0, inf) meters");
  need(unit(o.max_occupancy_update_certainty), "maxOccupancyUpdateCertainty",
       o.max_occupancy_update_certainty, "[0, 1]");
  need(unit(o.max_freeness_update_certainty), "maxFreenessUpdateCertainty",
       o.max_freeness_update_certainty, "[0, 1]");
  need(unit(o.max_freeness_invalid_ranges), "maxFreenessInvalidRanges", o.max_freeness_invalid_ranges,
       "[0, 1]");
  need(std::isfinite(o.horizontal_tolerance) && o.horizontal_tolerance >= 0.0f, "horizontalTolerance",
       static_cast<float>(o.horizontal_tolerance * (180.0 / kPi)), "[0, inf) degrees");
  need(std::isfinite(o.cfd_features_gaussian_size), "CFD_features_gaussian_size",
       o.cfd_features_gaussian_size, "the finite numbers");
  need(std::isfinite(o.cfd_features_median_size), "CFD_features_median_size",
       o.cfd_features_median_size, "the finite numbers");
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), sec, "", e.message());
  }
  return o;
}

void GridInsertionOptions::check() const {
  ROVE_CHECK_FINITE(map_altitude);
  ROVE_CHECK_FINITE(max_distance_insertion);
  ROVE_CHECK_GT(max_distance_insertion, 0.0f);
  ROVE_CHECK_MSG(max_occupancy_update_certainty >= 0.0f && max_occupancy_update_certainty <= 1.0f,
                 "maxOccupancyUpdateCertainty = {} is outside [0, 1]",
                 max_occupancy_update_certainty);
  ROVE_CHECK_MSG(max_freeness_update_certainty >= 0.0f && max_freeness_update_certainty <= 1.0f,
                 "maxFreenessUpdateCertainty = {} is outside [0, 1]",
                 max_freeness_update_certainty);
  ROVE_CHECK_MSG(max_freeness_invalid_ranges >= 0.0f && max_freeness_invalid_ranges <= 1.0f,
                 "maxFreenessInvalidRanges = {} is outside [0, 1]", max_freeness_invalid_ranges);
  ROVE_CHECK_GE(decimation, 1);
  ROVE_CHECK_FINITE(horizontal_tolerance);
  ROVE_CHECK_GE(horizontal_tolerance, 0.0f);
  ROVE_CHECK_FINITE(cfd_features_gaussian_size);
  ROVE_CHECK_FINITE(cfd_features_median_size);
}

bool is_horizontal(const Pose3& T_robot_sensor, double tolerance) {
  const auto ypr = T_robot_sensor.yaw_pitch_roll();
  return (std::fabs(ypr.pitch) <= tolerance || kPi - std::fabs(ypr.pitch) <= tolerance) &&
         (std::fabs(ypr.roll) <= tolerance || std::fabs(wrap_to_pi(ypr.roll - kPi)) <= tolerance);
}

namespace detail {

// The float instantiations live in grid_insertion_mrpt.cpp (Arithmetic::Mrpt).
extern template GridInsertResult insert_rays(OccupancyGridT<std::int8_t>&, const RangeScan2D&,
                                             const GridInsertionOptions&, const InsertStrengths&,
                                             const RayDirections<float>&);
extern template GridInsertResult insert_rays(OccupancyGridT<std::int16_t>&, const RangeScan2D&,
                                             const GridInsertionOptions&, const InsertStrengths&,
                                             const RayDirections<float>&);
extern template ScanInformation scan_information_rays(const OccupancyGridT<std::int8_t>&,
                                                      const RangeScan2D&, const GridInsertionOptions&,
                                                      const InsertStrengths&,
                                                      const RayDirections<float>&);
extern template ScanInformation scan_information_rays(const OccupancyGridT<std::int16_t>&,
                                                      const RangeScan2D&, const GridInsertionOptions&,
                                                      const InsertStrengths&,
                                                      const RayDirections<float>&);

template <GridCell Cell>
InsertStrengths insert_strengths(const GridInsertionOptions& opt, bool mrpt_wrap) {
  using Traits = LogOddsTraits<Cell>;
  const auto& lut = LogOddsLut<Cell>::instance();
  const float max_certainty = opt.max_occupancy_update_certainty;
  const float max_free =
      opt.max_freeness_update_certainty == 0.0f ? max_certainty : opt.max_freeness_update_certainty;
  const float max_noecho =
      opt.max_freeness_invalid_ranges == 0.0f ? max_certainty : opt.max_freeness_invalid_ranges;
  InsertStrengths st;
  st.obs_free = std::max<int>(1, lut.p2l(max_free));
  st.obs_noecho_free = std::max<int>(1, lut.p2l(max_noecho));
  // The occupied update counts three times (MRPT). MRPT computes 3·L in the
  // cell type, which wraps around for int8 above p ≈ 0.9; rove saturates at
  // the type's maximum unless it reproduces MRPT.
  const int occupied = 3 * std::max<int>(1, lut.p2l(max_certainty));
  st.obs_occupied = mrpt_wrap ? static_cast<Cell>(occupied) : std::min(Traits::kMax, occupied);
  st.thres_occupied = mrpt_wrap ? static_cast<Cell>(Traits::kMin + st.obs_occupied)
                                : Traits::kMin + st.obs_occupied;
  st.thres_free = Traits::kMax - std::max(st.obs_noecho_free, st.obs_free);
  return st;
}

template InsertStrengths insert_strengths<std::int8_t>(const GridInsertionOptions&, bool);
template InsertStrengths insert_strengths<std::int16_t>(const GridInsertionOptions&, bool);

RayDirections<double> ray_directions(const RangeScan2D& scan, const Pose3& T_map_sensor, int step) {
  RayDirections<double> d;
  d.px = T_map_sensor.x();
  d.py = T_map_sensor.y();
  d.step = step;
  const std::size_t n = scan.size();
  const double yaw = T_map_sensor.yaw();
  const double sign = T_map_sensor.rotation()(2, 2) < 0 ? -1.0 : 1.0;
  for (std::size_t i = 0; i < n; i += static_cast<std::size_t>(step))
    d.angle.push_back(n >= 2 ? yaw + sign * scan.ray_angle(i) : yaw);
  d.half_beam = 0.5 * (n >= 2 ? scan.aperture / static_cast<double>(n - 1) : scan.aperture);
  return d;
}


template <GridCell Cell>
ScanInformation scan_information(const OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                                 const Pose3& T_map_robot, const GridInsertionOptions& opt,
                                 int ray_step) {
  scan.check();
  opt.check();
  ROVE_CHECK_GE(ray_step, 1);
  if (scan.size() == 0) return {};
  const Pose3 T_map_sensor = T_map_robot + scan.T_robot_sensor;
  const InsertStrengths st = insert_strengths<Cell>(opt, false);
  if (opt.arithmetic == Arithmetic::Mrpt) {
    return scan_information_rays(grid, scan, opt, st,
                                 mrpt_ray_directions(scan, T_map_sensor, ray_step, false));
  }
  return scan_information_rays(grid, scan, opt, st, ray_directions(scan, T_map_sensor, ray_step));
}

template ScanInformation scan_information(const OccupancyGridT<std::int8_t>&, const RangeScan2D&,
                                          const Pose3&, const GridInsertionOptions&, int);
template ScanInformation scan_information(const OccupancyGridT<std::int16_t>&, const RangeScan2D&,
                                          const Pose3&, const GridInsertionOptions&, int);

}  // namespace detail

template <GridCell Cell>
GridInsertResult insert_scan(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                             const Pose3& T_map_robot, const GridInsertionOptions& opt) {
  scan.check();
  opt.check();
  GridInsertResult result;
  const Pose3 T_map_sensor = T_map_robot + scan.T_robot_sensor;
  if (!is_horizontal(scan.T_robot_sensor, opt.horizontal_tolerance)) {
    result.status = GridInsertStatus::NotHorizontal;
    result.message = "the scan is not horizontal within horizontalTolerance";
    return result;
  }
  if (opt.use_map_altitude && std::fabs(opt.map_altitude - T_map_sensor.z()) > 0.001) {
    result.status = GridInsertStatus::WrongAltitude;
    result.message = "the sensor is not at mapAltitude";
    return result;
  }
  const bool mrpt = opt.arithmetic == Arithmetic::Mrpt;
  const detail::InsertStrengths st = detail::insert_strengths<Cell>(opt, mrpt);
  if (mrpt) {
    return detail::insert_rays(grid, scan, opt, st,
                               detail::mrpt_ray_directions(scan, T_map_sensor, opt.decimation,
                                                           opt.widening_beams_with_distance));
  }
  return detail::insert_rays(grid, scan, opt, st,
                             detail::ray_directions(scan, T_map_sensor, opt.decimation));
}

template GridInsertResult insert_scan(OccupancyGridT<std::int8_t>&, const RangeScan2D&,
                                      const Pose3&, const GridInsertionOptions&);
template GridInsertResult insert_scan(OccupancyGridT<std::int16_t>&, const RangeScan2D&,
                                      const Pose3&, const GridInsertionOptions&);

}  // namespace rove
