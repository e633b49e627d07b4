#pragma once
/// \file
/// RotatingScan: one revolution of a rotating (spinning) range sensor as an
/// organized range image, rows = lasers/rings, columns = azimuth steps
/// (MRPT's CObservationRotatingScan). 2D scanners have one row.
///
/// Frame: the sensor frame (x forward, y left, z up); column c covers the
/// azimuth start_azimuth + c · azimuth_span / columns (radians, counter-
/// clockwise about z, the sensor's rotation direction).

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rove/obs/observation.h"

namespace rove {

/// An organized scan from a spinning lidar.
class RotatingScan final : public ObservationOf<RotatingScan> {
 public:
  /// Stored class name: "RotatingScan".
  static constexpr std::string_view kClassName = "RotatingScan";

  /// Rows (lasers/rings).
  std::uint16_t rows = 0;
  /// Columns (azimuth steps).
  std::uint16_t columns = 0;
  /// Ranges, row-major (r · columns + c), in units of range_resolution_m; 0
  /// means no return. Empty, or rows · columns values.
  std::vector<std::uint16_t> range;
  /// Intensities, row-major like range; empty if the sensor gives none.
  std::vector<std::uint8_t> intensity;
  /// Further range layers (e.g. "second_return"), each rows · columns values.
  std::map<std::string, std::vector<std::uint16_t>> other_range_layers;
  /// Meters per range unit (MRPT's rangeResolution).
  double range_resolution_m = 0.01;
  /// Azimuth of column 0, radians.
  double start_azimuth_rad = -3.141592653589793;
  /// Azimuth covered by all columns, radians (negative: clockwise).
  double azimuth_span_rad = 6.283185307179586;
  /// Time the revolution took, seconds.
  double sweep_duration_s = 0.0;
  /// Sensor model name, free text.
  std::string lidar_model = "UNKNOWN_SCANNER";
  /// Shortest valid range, meters.
  double min_range_m = 1.0;
  /// Longest valid range, meters.
  double max_range_m = 130.0;
  /// Time the data arrived at the computer (timestamp may come from a
  /// satellite clock instead; see has_satellite_timestamp).
  Timestamp original_received_timestamp;
  /// True if `timestamp` comes from a GNSS clock.
  bool has_satellite_timestamp = false;

  /// An empty scan.
  RotatingScan() = default;

  /// rows · columns.
  std::size_t cell_count() const noexcept {
    return static_cast<std::size_t>(rows) * static_cast<std::size_t>(columns);
  }
  /// Range of cell (row, column) in meters (0 for no return). Precondition
  /// (InvalidArgument): row < rows, column < columns, range not empty.
  double range_m(std::uint16_t row, std::uint16_t column) const;

  /// Throws InvalidArgument unless range (if not empty) and every other layer
  /// hold rows · columns values, intensity is empty or rows · columns,
  /// range_resolution_m is finite and > 0, and the range limits are finite.
  void check() const;

  /// Exact equality of every field.
  friend bool operator==(const RotatingScan& a, const RotatingScan& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
