#include "rove/obs/rotating_scan.h"

#include <cmath>

#include "archive_helpers.h"
#include "rove/core/check.h"
#include "rove/serialization/stl.h"

namespace rove {

double RotatingScan::range_m(std::uint16_t row, std::uint16_t column) const {
  ROVE_CHECK_LT(row, rows);
  ROVE_CHECK_LT(column, columns);
  ROVE_CHECK_EQ(range.size(), cell_count());
  return range[static_cast<std::size_t>(row) * columns + column] * range_resolution_m;
}

void RotatingScan::check() const {
  const std::size_t n = cell_count();
  ROVE_CHECK_MSG(range.empty() || range.size() == n,
                 "RotatingScan: {} range values for {}x{} cells", range.size(), rows, columns);
  ROVE_CHECK_MSG(intensity.empty() || intensity.size() == n,
                 "RotatingScan: {} intensity values for {}x{} cells", intensity.size(), rows,
                 columns);
  for (const auto& [name, layer] : other_range_layers) {
    ROVE_CHECK_MSG(layer.size() == n, "RotatingScan: layer '{}' has {} values for {}x{} cells",
                   name, layer.size(), rows, columns);
  }
  ROVE_CHECK_MSG(std::isfinite(range_resolution_m) && range_resolution_m > 0.0,
                 "RotatingScan: range resolution {} must be > 0", range_resolution_m);
  ROVE_CHECK_FINITE(min_range_m);
  ROVE_CHECK_FINITE(max_range_m);
  ROVE_CHECK_FINITE(start_azimuth_rad);
  ROVE_CHECK_FINITE(azimuth_span_rad);
}

bool operator==(const RotatingScan& a, const RotatingScan& b) {
  return a.header_equals(b) && a.rows == b.rows && a.columns == b.columns && a.range == b.range &&
         a.intensity == b.intensity && a.other_range_layers == b.other_range_layers &&
         a.range_resolution_m == b.range_resolution_m &&
         a.start_azimuth_rad == b.start_azimuth_rad && a.azimuth_span_rad == b.azimuth_span_rad &&
         a.sweep_duration_s == b.sweep_duration_s && a.lidar_model == b.lidar_model &&
         a.min_range_m == b.min_range_m && a.max_range_m == b.max_range_m &&
         a.original_received_timestamp == b.original_received_timestamp &&
         a.has_satellite_timestamp == b.has_satellite_timestamp;
}

void RotatingScan::save_payload(OutArchive& ar) const {
  save_header(ar);
  ar.write_scalar(rows);
  ar.write_scalar(columns);
  save(ar, range);
  save(ar, intensity);
  save(ar, other_range_layers);
  for (double v : {range_resolution_m, start_azimuth_rad, azimuth_span_rad, sweep_duration_s,
                   min_range_m, max_range_m}) {
    ar.write_scalar(v);
  }
  save(ar, lidar_model);
  ar.write_scalar(original_received_timestamp.ns);
  ar.write_scalar(has_satellite_timestamp);
}

void RotatingScan::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  const std::uint64_t at = ar.offset();
  load_header(ar);
  rows = ar.read_scalar<std::uint16_t>("rows");
  columns = ar.read_scalar<std::uint16_t>("columns");
  load(ar, range);
  load(ar, intensity);
  load(ar, other_range_layers);
  for (double* v : {&range_resolution_m, &start_azimuth_rad, &azimuth_span_rad, &sweep_duration_s,
                    &min_range_m, &max_range_m}) {
    *v = ar.read_scalar<double>("RotatingScan");
  }
  load(ar, lidar_model);
  original_received_timestamp.ns = ar.read_scalar<std::int64_t>("original_received_timestamp");
  has_satellite_timestamp = ar.read_scalar<bool>("has_satellite_timestamp");
  parse_guard(ar, at, "RotatingScan", [&] { check(); });
}

}  // namespace rove
