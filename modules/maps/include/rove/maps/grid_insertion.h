#pragma once
/// \file
/// Inserting 2D range scans into an occupancy grid by ray casting, with
/// MRPT's algorithm, options and defaults (COccupancyGridMap2D::
/// TInsertionOptions and internal_insertObservation).
///
/// Each ray marks the cells from the sensor to the hit as more likely free
/// (fixed-point DDA with 9 fractional bits, as MRPT) and the hit cell as
/// more likely occupied; with wideningBeamsWithDistance the free area is
/// the triangle of the beam's angular width and the occupied area is the
/// arc at its end (https://www.mrpt.org/Occupancy_Grids). The grid grows
/// to hold the scan.
///
/// Where the rays end depends on GridInsertionOptions::arithmetic: by
/// default (Double) each ray points at the scan's own angle
/// (RangeScan2D::ray_angle) and ends at its range, computed in double; with
/// Arithmetic::Mrpt the geometry is MRPT 2.5.8's to the bit (angles
/// accumulated in float in steps of aperture / N, end points in float, and
/// its int8 overflow of strong occupied updates), so the cells equal MRPT's.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "rove/core/arithmetic.h"
#include "rove/core/config_section.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"

namespace rove {

/// Options of scan insertion: MRPT's TInsertionOptions with its defaults.
/// The INI key of each field is the MRPT name given in its comment.
struct GridInsertionOptions {
  /// `mapAltitude`: z of the map plane, meters (used with use_map_altitude).
  float map_altitude = 0.0f;
  /// `useMapAltitude`: insert only scans whose sensor is within 1 mm of
  /// map_altitude.
  bool use_map_altitude = false;
  /// `maxDistanceInsertion`: rays are cut at this range, meters; a cut ray
  /// marks no occupied cell.
  float max_distance_insertion = 15.0f;
  /// `maxOccupancyUpdateCertainty`: probability in [0.5, 1] of the occupied
  /// update (applied three times over, as MRPT).
  float max_occupancy_update_certainty = 0.65f;
  /// `maxFreenessUpdateCertainty`: probability of the free update; 0 means
  /// the same as max_occupancy_update_certainty.
  float max_freeness_update_certainty = 0.0f;
  /// `maxFreenessInvalidRanges`: free update along rays without echo; 0
  /// means the same as max_occupancy_update_certainty.
  float max_freeness_invalid_ranges = 0.0f;
  /// `considerInvalidRangesAsFreeSpace`: a ray without echo frees the cells
  /// up to half the last valid range (capped at max_distance_insertion).
  bool consider_invalid_ranges_as_free_space = true;
  /// `decimation`: insert one ray out of this many (>= 1).
  std::uint16_t decimation = 1;
  /// `horizontalTolerance` (degrees in the INI file): largest pitch and roll
  /// of the sensor on the robot, radians, for a scan to count as planar.
  float horizontal_tolerance = static_cast<float>(0.05 * 3.14159265358979323846 / 180.0);
  /// `CFD_features_gaussian_size`: read for compatibility with MRPT
  /// configs; used only by MRPT's filtered-image export, which rove lacks.
  float cfd_features_gaussian_size = 1.0f;
  /// `CFD_features_median_size`: as cfd_features_gaussian_size.
  float cfd_features_median_size = 3.0f;
  /// `wideningBeamsWithDistance`: beams widen with distance (triangles)
  /// instead of thin rays.
  bool widening_beams_with_distance = false;
  /// `arithmetic` (rove's key: double | mrpt): the ray geometry (file
  /// comment). Double: the scan's ray angles, spaced aperture / (N − 1),
  /// end points in double, and an occupied update that saturates at the
  /// cell type's limit. Mrpt: MRPT's float geometry (rays spaced
  /// aperture / N, so the last ray of a 361-ray 180° scan points 0.5° off
  /// its true angle) and its int8 overflow of 3·L above p ≈ 0.9. Default
  /// Double.
  Arithmetic arithmetic = Arithmetic::Double;

  /// Reads the keys present in `section` (missing keys keep their values).
  /// Throws ConfigError (file, section, key) on a malformed value or one
  /// that check() rejects.
  static GridInsertionOptions from_config(const ConfigSection& config);
  /// Throws InvalidArgument unless all values are finite, certainties are in
  /// [0, 1] (0 allowed for the two "same as" fields), max_distance_insertion
  /// > 0, decimation >= 1 and horizontal_tolerance >= 0.
  void check() const;
  /// Exact equality.
  friend bool operator==(const GridInsertionOptions&, const GridInsertionOptions&) = default;
};

/// What insert_scan did.
enum class GridInsertStatus : std::uint8_t {
  Inserted = 0,       ///< the scan was inserted
  NotHorizontal = 1,  ///< the sensor's pitch/roll exceed horizontal_tolerance
  WrongAltitude = 2,  ///< use_map_altitude and the sensor is off the map plane
};

/// Result of insert_scan.
struct GridInsertResult {
  /// Whether the scan was inserted, or why not.
  GridInsertStatus status = GridInsertStatus::Inserted;
  /// One-line explanation.
  std::string message;
  /// Rays that changed cells (after decimation).
  std::size_t rays_inserted = 0;
  /// True if status is kInserted.
  bool inserted() const noexcept { return status == GridInsertStatus::Inserted; }
};

/// Inserts `scan`, taken with the robot at T_map_robot (the scan's own
/// T_robot_sensor places the sensor on the robot), into `grid`, growing it
/// as needed. A ray counts as valid if its flag is set and its range is
/// finite and >= 0. Throws InvalidArgument if scan.check() or
/// options.check() fails.
template <GridCell Cell>
GridInsertResult insert_scan(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                             const Pose3& T_map_robot, const GridInsertionOptions& options = {});
/// As above, for a planar robot pose.
template <GridCell Cell>
GridInsertResult insert_scan(OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                             const Pose2& T_map_robot, const GridInsertionOptions& options = {}) {
  return insert_scan(grid, scan, Pose3(T_map_robot), options);
}

/// True if a sensor mounted at T_robot_sensor is horizontal within
/// `tolerance` radians (MRPT's CPose3D::isHorizontal: |pitch| or π − |pitch|
/// and |roll| or |roll − π| within tolerance).
bool is_horizontal(const Pose3& T_robot_sensor, double tolerance);

}  // namespace rove
