#pragma once
/// \file
/// GpsObservation: a GNSS position fix (the GGA part of MRPT's
/// CObservationGPS), optionally with a local East-North-Up position.

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include <Eigen/Core>

#include "rove/obs/observation.h"

namespace rove {

/// Fix quality as NMEA GGA field 6 reports it.
enum class GpsFixQuality : std::uint8_t {
  Invalid = 0,        ///< no fix
  Gps = 1,            ///< standalone GNSS
  Dgps = 2,           ///< differential
  Pps = 3,            ///< PPS
  RtkFixed = 4,       ///< RTK, integer ambiguities fixed
  RtkFloat = 5,       ///< RTK, float ambiguities
  DeadReckoning = 6,  ///< estimated
  Manual = 7,         ///< manual input
  Simulation = 8,     ///< simulator
};

/// UTC time of day as NMEA sentences give it.
struct GpsUtcTime {
  std::uint8_t hour = 0;    ///< 0..23
  std::uint8_t minute = 0;  ///< 0..59
  double second = 0.0;      ///< [0, 61)
  /// Exact equality.
  friend bool operator==(const GpsUtcTime&, const GpsUtcTime&) = default;
};

/// The NMEA RMC sentence ("recommended minimum"): position, speed, course.
struct GpsRmc {
  /// Time of the fix.
  GpsUtcTime utc_time;
  /// Status 'A' (valid) or 'V' (warning), as received.
  char status = 'V';
  /// Latitude, degrees, north positive.
  double latitude_deg = 0.0;
  /// Longitude, degrees, east positive.
  double longitude_deg = 0.0;
  /// Speed over ground, knots.
  double speed_knots = 0.0;
  /// Course over ground, degrees from true north.
  double course_deg = 0.0;
  /// Date: day 1..31, month 1..12, year (two digits); all 0 if not received.
  std::uint8_t day = 0, month = 0, year = 0;
  /// Magnetic variation, degrees (east positive).
  double magnetic_variation_deg = 0.0;
  /// Positioning mode indicator ('A' autonomous, 'D' differential, 'N' not
  /// valid, ...).
  char mode = 'N';
  /// Exact equality.
  friend bool operator==(const GpsRmc&, const GpsRmc&) = default;
};

/// Writes a GpsUtcTime (part of GpsObservation's record).
void save(OutArchive& ar, const GpsUtcTime& t);
/// Reads a GpsUtcTime written by save.
void load(InArchive& ar, GpsUtcTime& t);
/// Writes a GpsRmc (part of GpsObservation's record).
void save(OutArchive& ar, const GpsRmc& r);
/// Reads a GpsRmc written by save.
void load(InArchive& ar, GpsRmc& r);

/// A GNSS fix. T_robot_sensor's translation is the antenna position.
class GpsObservation final : public ObservationOf<GpsObservation> {
 public:
  /// Stored class name: "GpsObservation".
  static constexpr std::string_view kClassName = "GpsObservation";

  /// Latitude, degrees, WGS84, north positive, in [−90, 90].
  double latitude_deg = 0.0;
  /// Longitude, degrees, WGS84, east positive, in [−180, 180].
  double longitude_deg = 0.0;
  /// Altitude above mean sea level, meters (GGA's altitude).
  double altitude_m = 0.0;
  /// Fix quality.
  GpsFixQuality fix_quality = GpsFixQuality::Invalid;
  /// Satellites used in the fix.
  std::uint32_t satellites = 0;
  /// Horizontal dilution of precision (dimensionless).
  double hdop = 0.0;
  /// Antenna position in a local East-North-Up frame chosen by the user,
  /// meters, if computed.
  std::optional<Eigen::Vector3d> enu_position;
  /// Covariance of enu_position, m², if known.
  std::optional<Eigen::Matrix3d> enu_covariance;
  /// UTC time of the GGA fix, if received (version 2).
  std::optional<GpsUtcTime> utc_time;
  /// Height of the geoid above the WGS84 ellipsoid, meters (GGA field 11;
  /// 0 when not received).
  double geoid_separation_m = 0.0;
  /// The RMC sentence received with this fix, if any.
  std::optional<GpsRmc> rmc;
  /// When the data reached the computer; `timestamp` may instead come from
  /// the satellite clock (see has_satellite_timestamp).
  Timestamp original_received_timestamp;
  /// True if `timestamp` comes from the GNSS clock.
  bool has_satellite_timestamp = false;

  /// No fix.
  GpsObservation() = default;

  /// Throws InvalidArgument unless latitude is in [−90, 90], longitude in
  /// [−180, 180], altitude and hdop finite, hdop >= 0, the ENU values
  /// (if any) and geoid_separation_m finite, and the RMC's latitude,
  /// longitude, speed and course (if any) finite.
  void check() const;

  /// Exact equality of every field.
  friend bool operator==(const GpsObservation& a, const GpsObservation& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 2; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data,
  /// including values that fail check().
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
