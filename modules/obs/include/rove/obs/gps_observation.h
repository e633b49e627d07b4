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
  kInvalid = 0,        ///< no fix
  kGps = 1,            ///< standalone GNSS
  kDgps = 2,           ///< differential
  kPps = 3,            ///< PPS
  kRtkFixed = 4,       ///< RTK, integer ambiguities fixed
  kRtkFloat = 5,       ///< RTK, float ambiguities
  kDeadReckoning = 6,  ///< estimated
  kManual = 7,         ///< manual input
  kSimulation = 8,     ///< simulator
};

/// A GNSS fix. T_robot_sensor's translation is the antenna position.
class GpsObservation final : public Observation {
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
  GpsFixQuality fix_quality = GpsFixQuality::kInvalid;
  /// Satellites used in the fix.
  std::uint32_t satellites = 0;
  /// Horizontal dilution of precision (dimensionless).
  double hdop = 0.0;
  /// Antenna position in a local East-North-Up frame chosen by the user,
  /// meters, if computed.
  std::optional<Eigen::Vector3d> enu_position;
  /// Covariance of enu_position, m², if known.
  std::optional<Eigen::Matrix3d> enu_covariance;

  /// No fix.
  GpsObservation() = default;

  /// Throws InvalidArgument unless latitude is in [−90, 90], longitude in
  /// [−180, 180], altitude and hdop finite, hdop >= 0, and the ENU values
  /// (if any) finite.
  void check() const;

  /// Exact equality of every field.
  friend bool operator==(const GpsObservation& a, const GpsObservation& b);

  /// The stored class name (kClassName).
  std::string_view class_name() const override { return kClassName; }
  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
  /// A deep copy.
  std::unique_ptr<Observation> clone() const override;
  /// Same dynamic type and operator==.
  bool equals(const Observation& other) const override;
};

}  // namespace rove
