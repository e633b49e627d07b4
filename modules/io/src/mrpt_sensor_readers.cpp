// Readers of MRPT observation and action payloads beyond 2D scans and
// odometry: 3D motion, comments, rotating scans, Velodyne packets, GNSS,
// RGB-D / 3D range scans with their images and camera models. Field order
// and versions follow MRPT 2.5's serializeFrom of each class (cited below).

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "mrpt_read_helpers.h"
#include "rove/core/error.h"
#include "rove/obs/comment_observation.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/robot_movement_3d.h"
#include "rove/obs/rotating_scan.h"
#include "rove/obs/velodyne_scan.h"

namespace rove::detail {
namespace {

template <typename T>
void read_into(InArchive& ar, std::vector<T>& out, std::uint64_t n, std::string_view field) {
  out.clear();
  ar.append_scalars(out, n, field);
}

// CActionRobotMovement3D v0..1 (MRPT 2.5): u32 estimationMethod, the pose
// change (a CPose3DPDFGaussian object), hasVelocities (std::vector<bool>:
// u32 count, one byte each), velocities (CVectorFloat: u32 count, floats),
// (v1) timestamp. Both vectors hold vx, vy, vz, wx, wy, wz.
MrptObject read_robot_movement_3d(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version > 1) throw_unknown_mrpt_version(ar, h);
  auto mv = std::make_shared<RobotMovement3D>();
  const std::uint64_t method_at = ar.offset();
  const auto method = ar.read_scalar<std::uint32_t>("CActionRobotMovement3D.estimationMethod");
  if (method > 1) {
    ar.fail_at(method_at, "CActionRobotMovement3D.estimationMethod",
               fmt::format("unknown estimation method {}", method));
  }
  mv->source = static_cast<Movement3DSource>(method);
  mv->pose_change =
      expect_mrpt<Pose3Gaussian>(ar, "CActionRobotMovement3D.poseChange", "CPose3DPDFGaussian");
  const std::uint64_t flags_at = ar.offset();
  const std::vector<bool> known = read_mrpt_bool_vector(ar, "CActionRobotMovement3D.hasVelocities");
  const std::uint64_t values_at = ar.offset();
  const std::vector<float> values = read_mrpt_vector<float>(ar, "CActionRobotMovement3D.velocities");
  if (known.size() != 6) {
    ar.fail_at(flags_at, "CActionRobotMovement3D.hasVelocities",
               fmt::format("expected 6 flags, found {}", known.size()));
  }
  if (values.size() != 6) {
    ar.fail_at(values_at, "CActionRobotMovement3D.velocities",
               fmt::format("expected 6 values, found {}", values.size()));
  }
  bool any = false;
  double v[6];
  for (int i = 0; i < 6; ++i) {
    any = any || known[i];
    v[i] = known[i] ? static_cast<double>(values[i]) : std::numeric_limits<double>::quiet_NaN();
  }
  if (any) mv->velocity = Twist3{v[0], v[1], v[2], v[3], v[4], v[5]};
  if (h.version >= 1) mv->timestamp = read_mrpt_timestamp(ar, "CActionRobotMovement3D.timestamp");
  return std::shared_ptr<Action>(std::move(mv));
}

// CObservationComment v0: text, timestamp.
MrptObject read_comment(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version != 0) throw_unknown_mrpt_version(ar, h);
  auto c = std::make_shared<CommentObservation>();
  c->text = read_mrpt_string(ar, "CObservationComment.text");
  c->timestamp = read_mrpt_timestamp(ar, "CObservationComment.timestamp");
  return std::shared_ptr<Observation>(std::move(c));
}

// CObservationRotatingScan v0: timestamp, sensorLabel, u16 rowCount, u16
// columnCount, doubles rangeResolution, startAzimuth, azimuthSpan,
// sweepDuration, string lidarModel, doubles minRange, maxRange, sensorPose
// (CPose3D object), originalReceivedTimestamp, bool has_satellite_timestamp;
// then u16 cols, u16 rows and the u16 range image (row-major), u16 cols, u16
// rows and the u8 intensity image, u16 layer count and per layer a name and
// rowCount x columnCount u16 values.
MrptObject read_rotating_scan(InArchive& ar, const MrptObjectHeader& h) {
  constexpr std::string_view kField = "CObservationRotatingScan";
  if (h.version != 0) throw_unknown_mrpt_version(ar, h);
  auto s = std::make_shared<RotatingScan>();
  s->timestamp = read_mrpt_timestamp(ar, "CObservationRotatingScan.timestamp");
  s->sensor_label = read_mrpt_string(ar, "CObservationRotatingScan.sensorLabel");
  s->rows = ar.read_scalar<std::uint16_t>("CObservationRotatingScan.rowCount");
  s->columns = ar.read_scalar<std::uint16_t>("CObservationRotatingScan.columnCount");
  s->range_resolution_m = ar.read_scalar<double>(kField);
  s->start_azimuth_rad = ar.read_scalar<double>(kField);
  s->azimuth_span_rad = ar.read_scalar<double>(kField);
  s->sweep_duration_s = ar.read_scalar<double>(kField);
  s->lidar_model = read_mrpt_string(ar, "CObservationRotatingScan.lidarModel");
  s->min_range_m = ar.read_scalar<double>(kField);
  s->max_range_m = ar.read_scalar<double>(kField);
  s->T_robot_sensor = expect_mrpt<Pose3>(ar, "CObservationRotatingScan.sensorPose", "CPose3D");
  s->original_received_timestamp =
      read_mrpt_timestamp(ar, "CObservationRotatingScan.originalReceivedTimestamp");
  s->has_satellite_timestamp = read_mrpt_bool(ar, "CObservationRotatingScan.hasSatelliteTime");
  const std::uint64_t image_at = ar.offset();
  const auto cols = ar.read_scalar<std::uint16_t>("CObservationRotatingScan.rangeImage.cols");
  const auto rows = ar.read_scalar<std::uint16_t>("CObservationRotatingScan.rangeImage.rows");
  const std::uint64_t n = std::uint64_t{rows} * cols;
  if (n != 0 && (rows != s->rows || cols != s->columns)) {
    ar.fail_at(image_at, "CObservationRotatingScan.rangeImage",
               fmt::format("range image is {}x{} but the scan has {} rows, {} columns", rows,
                           cols, s->rows, s->columns));
  }
  ar.check_length(n, sizeof(std::uint16_t), "CObservationRotatingScan.rangeImage", image_at);
  read_into(ar, s->range, n, "CObservationRotatingScan.rangeImage");
  const std::uint64_t int_at = ar.offset();
  const auto icols = ar.read_scalar<std::uint16_t>("CObservationRotatingScan.intensity.cols");
  const auto irows = ar.read_scalar<std::uint16_t>("CObservationRotatingScan.intensity.rows");
  const std::uint64_t ni = std::uint64_t{irows} * icols;
  if (ni != 0 && (irows != s->rows || icols != s->columns)) {
    ar.fail_at(int_at, "CObservationRotatingScan.intensityImage",
               fmt::format("intensity image is {}x{} but the scan has {} rows, {} columns", irows,
                           icols, s->rows, s->columns));
  }
  ar.check_length(ni, 1, "CObservationRotatingScan.intensityImage", int_at);
  read_into(ar, s->intensity, ni, "CObservationRotatingScan.intensityImage");
  const auto layers = ar.read_scalar<std::uint16_t>("CObservationRotatingScan.otherLayers");
  for (std::uint16_t i = 0; i < layers; ++i) {
    const std::uint64_t at = ar.offset();
    std::string name = read_mrpt_string(ar, "CObservationRotatingScan.otherLayers.name");
    // MRPT sizes each layer by the range image's rows and columns.
    ar.check_length(n, sizeof(std::uint16_t), "CObservationRotatingScan.otherLayers", at);
    std::vector<std::uint16_t> layer;
    read_into(ar, layer, n, "CObservationRotatingScan.otherLayers");
    if (!s->other_range_layers.emplace(std::move(name), std::move(layer)).second) {
      ar.fail_at(at, "CObservationRotatingScan.otherLayers", "duplicate layer name");
    }
  }
  parse_guard(ar, h.offset, kField, [&] { s->check(); });
  return std::shared_ptr<Observation>(std::move(s));
}

// The element type names MRPT's generic container serialization writes.
std::vector<Timestamp> read_timestamp_vector(InArchive& ar, std::string_view field) {
  const std::uint32_t n = read_mrpt_container_preamble(ar, "std::vector", {"uint64_t"}, field);
  ar.check_length(n, sizeof(std::uint64_t), field, ar.offset());
  std::vector<Timestamp> out;
  out.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) out.push_back(read_mrpt_timestamp(ar, field));
  return out;
}

// CObservationVelodyneScan v0..2: timestamp, sensorLabel, doubles minRange,
// maxRange, sensorPose (CPose3D object), u32 packet count and the 1206-byte
// packets, u32 laser count and the per-laser calibrations (9 doubles each),
// the point cloud's x, y, z (float vectors) and intensity (u8 vector),
// (v1) bool has_satellite_timestamp, (v2) per-point timestamps (generic
// std::vector<uint64_t>), azimuth (float vector), laser_id (int16 vector)
// and pointsForLaserID (generic std::vector of std::vector<uint64_t>).
MrptObject read_velodyne_scan(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version > 2) throw_unknown_mrpt_version(ar, h);
  auto s = std::make_shared<VelodyneScan>();
  s->timestamp = read_mrpt_timestamp(ar, "CObservationVelodyneScan.timestamp");
  s->sensor_label = read_mrpt_string(ar, "CObservationVelodyneScan.sensorLabel");
  s->min_range_m = ar.read_scalar<double>("CObservationVelodyneScan.minRange");
  s->max_range_m = ar.read_scalar<double>("CObservationVelodyneScan.maxRange");
  s->T_robot_sensor = expect_mrpt<Pose3>(ar, "CObservationVelodyneScan.sensorPose", "CPose3D");
  const std::uint32_t np =
      ar.read_length("CObservationVelodyneScan.scan_packets", kVelodynePacketBytes);
  s->packets.assign(np, VelodynePacket{});
  for (VelodynePacket& p : s->packets) {
    ar.read_bytes(std::as_writable_bytes(std::span<std::uint8_t>(p.data(), p.size())),
                  "CObservationVelodyneScan.scan_packets");
  }
  const std::uint32_t nc =
      ar.read_length("CObservationVelodyneScan.laser_corrections", 9 * sizeof(double));
  s->calibration.assign(nc, VelodyneLaserCalibration{});
  for (VelodyneLaserCalibration& c : s->calibration) {
    for (double* v : {&c.azimuth_correction, &c.vertical_correction, &c.distance_correction,
                      &c.vertical_offset_correction, &c.horizontal_offset_correction,
                      &c.sin_vert_correction, &c.cos_vert_correction,
                      &c.sin_vert_offset_correction, &c.cos_vert_offset_correction}) {
      *v = ar.read_scalar<double>("CObservationVelodyneScan.laser_corrections");
    }
  }
  VelodynePointCloud& pc = s->point_cloud;
  pc.x = read_mrpt_vector<float>(ar, "CObservationVelodyneScan.point_cloud.x");
  pc.y = read_mrpt_vector<float>(ar, "CObservationVelodyneScan.point_cloud.y");
  pc.z = read_mrpt_vector<float>(ar, "CObservationVelodyneScan.point_cloud.z");
  pc.intensity = read_mrpt_vector<std::uint8_t>(ar, "CObservationVelodyneScan.point_cloud.intensity");
  if (pc.y.size() != pc.x.size() || pc.z.size() != pc.x.size() ||
      pc.intensity.size() != pc.x.size()) {
    ar.fail_at(h.offset, "CObservationVelodyneScan.point_cloud",
               fmt::format("point cloud vectors differ in size (x {}, y {}, z {}, intensity {})",
                           pc.x.size(), pc.y.size(), pc.z.size(), pc.intensity.size()));
  }
  if (h.version >= 1) {
    s->has_satellite_timestamp = read_mrpt_bool(ar, "CObservationVelodyneScan.hasSatelliteTime");
  }
  if (h.version >= 2) {
    pc.timestamp = read_timestamp_vector(ar, "CObservationVelodyneScan.point_cloud.timestamp");
    pc.azimuth = read_mrpt_vector<float>(ar, "CObservationVelodyneScan.point_cloud.azimuth");
    pc.laser_id = read_mrpt_vector<std::int16_t>(ar, "CObservationVelodyneScan.point_cloud.laser_id");
    constexpr std::string_view kLaserField = "CObservationVelodyneScan.pointsForLaserID";
    const std::uint32_t nl = read_mrpt_container_preamble(ar, "std::vector",
                                                          {"std::vector<uint64_t>"}, kLaserField);
    ar.check_length(nl, sizeof(std::uint32_t), kLaserField, ar.offset());
    pc.points_for_laser_id.reserve(nl);
    for (std::uint32_t i = 0; i < nl; ++i) {
      pc.points_for_laser_id.push_back(read_mrpt_vector<std::uint64_t>(ar, kLaserField));
    }
  }
  return std::shared_ptr<Observation>(std::move(s));
}

// ---- GNSS ------------------------------------------------------------------

// Little-endian fields of a packed struct held in `bytes`.
template <typename T>
T field_at(std::span<const std::uint8_t> bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof(T));  // rove hosts are little-endian
  return v;
}

void set_fix_quality(InArchive& ar, std::uint64_t at, GpsObservation& g, std::uint8_t q) {
  if (q > static_cast<std::uint8_t>(GpsFixQuality::Simulation)) {
    ar.fail_at(at, "CObservationGPS.GGA.fix_quality", fmt::format("unknown fix quality {}", q));
  }
  g.fix_quality = static_cast<GpsFixQuality>(q);
}

// Message_NMEA_GGA::content_t, packed (68 bytes): UTC_time {u8 hour, u8
// minute, double sec}, doubles latitude, longitude, u8 fix_quality, doubles
// altitude, geoidal_distance, orthometric_altitude,
// corrected_orthometric_altitude, u32 satellitesUsed, bool thereis_HDOP,
// float HDOP.
void decode_gga(InArchive& ar, std::uint64_t at, std::span<const std::uint8_t> b,
                GpsObservation& g) {
  g.utc_time = GpsUtcTime{b[0], b[1], field_at<double>(b, 2)};
  g.latitude_deg = field_at<double>(b, 10);
  g.longitude_deg = field_at<double>(b, 18);
  set_fix_quality(ar, at, g, b[26]);
  g.altitude_m = field_at<double>(b, 27);
  g.geoid_separation_m = field_at<double>(b, 35);
  g.satellites = field_at<std::uint32_t>(b, 59);
  g.hdop = field_at<float>(b, 64);
}

// Message_NMEA_RMC::content_t, packed (55 bytes): UTC_time, i8 validity,
// doubles latitude, longitude, speed_knots, direction_degrees, u8 day,
// month, year, double magnetic_dir, char positioning_mode.
GpsRmc decode_rmc(std::span<const std::uint8_t> b) {
  GpsRmc r;
  r.utc_time = GpsUtcTime{b[0], b[1], field_at<double>(b, 2)};
  r.status = static_cast<char>(b[10]);
  r.latitude_deg = field_at<double>(b, 11);
  r.longitude_deg = field_at<double>(b, 19);
  r.speed_knots = field_at<double>(b, 27);
  r.course_deg = field_at<double>(b, 35);
  r.day = b[43];
  r.month = b[44];
  r.year = b[45];
  r.magnetic_variation_deg = field_at<double>(b, 46);
  r.mode = static_cast<char>(b[54]);
  return r;
}

GpsUtcTime read_utc(InArchive& ar, std::string_view field) {
  GpsUtcTime t;
  t.hour = ar.read_scalar<std::uint8_t>(field);
  t.minute = ar.read_scalar<std::uint8_t>(field);
  t.second = ar.read_scalar<double>(field);
  return t;
}

constexpr std::int32_t kNmeaGga = 10;
constexpr std::int32_t kNmeaRmc = 15;

// CObservationGPS v10..11: timestamp, originalReceivedTimestamp,
// sensorLabel, sensorPose (CPose3D object), (v11) bool
// has_satellite_timestamp, u32 message count; each message is i32 type, u32
// byte count and the packed content. GGA and RMC are read; other message
// types are rejected (their layouts differ per type).
void read_gps_messages(InArchive& ar, const MrptObjectHeader& h, GpsObservation& g) {
  g.timestamp = read_mrpt_timestamp(ar, "CObservationGPS.timestamp");
  g.original_received_timestamp =
      read_mrpt_timestamp(ar, "CObservationGPS.originalReceivedTimestamp");
  g.sensor_label = read_mrpt_string(ar, "CObservationGPS.sensorLabel");
  g.T_robot_sensor = expect_mrpt<Pose3>(ar, "CObservationGPS.sensorPose", "CPose3D");
  if (h.version >= 11) {
    g.has_satellite_timestamp = read_mrpt_bool(ar, "CObservationGPS.has_satellite_timestamp");
  } else {
    g.has_satellite_timestamp = g.timestamp != g.original_received_timestamp;
  }
  const std::uint32_t n = ar.read_length("CObservationGPS.messages", 8);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    const auto type = ar.read_scalar<std::int32_t>("CObservationGPS.message.type");
    const std::size_t expected = type == kNmeaGga ? 68 : type == kNmeaRmc ? 55 : 0;
    if (expected == 0) {
      ar.fail_at(at, "CObservationGPS.message",
                 fmt::format("GNSS message type {} is not supported (NMEA GGA {} and RMC {} are)",
                             type, kNmeaGga, kNmeaRmc));
    }
    const std::uint64_t len_at = ar.offset();
    const auto len = ar.read_scalar<std::uint32_t>("CObservationGPS.message.length");
    if (len != expected) {
      ar.fail_at(len_at, "CObservationGPS.message.length",
                 fmt::format("message type {} has {} bytes, expected {}", type, len, expected));
    }
    std::vector<std::uint8_t> bytes;
    ar.append_scalars(bytes, len, "CObservationGPS.message");
    if (type == kNmeaGga) {
      decode_gga(ar, at, bytes, g);
    } else {
      g.rmc = decode_rmc(bytes);
    }
  }
  if (h.version < 10 && !g.original_received_timestamp.valid()) {
    g.original_received_timestamp = g.timestamp;
  }
}

// CObservationGPS v1..9 (before the message map): (v>=3) timestamp, bool
// has GGA and its fields one by one (v9 adds three altitude doubles), bool
// has RMC and its fields, (v>=2) sensorLabel, (v>=4) sensorPose, (v>=5)
// bool has TOPCON PZS and its fields, (v>=7) bool has TOPCON SATS. PZS and
// SATS data are rejected (MRPT 2.5 itself cannot read SATS).
void read_gps_legacy(InArchive& ar, const MrptObjectHeader& h, GpsObservation& g) {
  if (h.version >= 3) g.timestamp = read_mrpt_timestamp(ar, "CObservationGPS.timestamp");
  if (read_mrpt_bool(ar, "CObservationGPS.has_GGA")) {
    const std::uint64_t at = ar.offset();
    g.utc_time = read_utc(ar, "CObservationGPS.GGA.UTCTime");
    g.latitude_deg = ar.read_scalar<double>("CObservationGPS.GGA.latitude");
    g.longitude_deg = ar.read_scalar<double>("CObservationGPS.GGA.longitude");
    set_fix_quality(ar, at, g, ar.read_scalar<std::uint8_t>("CObservationGPS.GGA.fix_quality"));
    g.altitude_m = ar.read_scalar<double>("CObservationGPS.GGA.altitude");
    if (h.version >= 9) {
      g.geoid_separation_m = ar.read_scalar<double>("CObservationGPS.GGA.geoidal_distance");
      static_cast<void>(ar.read_scalar<double>("CObservationGPS.GGA.orthometric_altitude"));
      static_cast<void>(
          ar.read_scalar<double>("CObservationGPS.GGA.corrected_orthometric_altitude"));
    }
    g.satellites = ar.read_scalar<std::uint32_t>("CObservationGPS.GGA.satellitesUsed");
    static_cast<void>(read_mrpt_bool(ar, "CObservationGPS.GGA.thereis_HDOP"));
    g.hdop = ar.read_scalar<float>("CObservationGPS.GGA.HDOP");
  }
  if (read_mrpt_bool(ar, "CObservationGPS.has_RMC")) {
    GpsRmc r;
    r.utc_time = read_utc(ar, "CObservationGPS.RMC.UTCTime");
    r.status = static_cast<char>(ar.read_scalar<std::int8_t>("CObservationGPS.RMC.validity"));
    r.latitude_deg = ar.read_scalar<double>("CObservationGPS.RMC.latitude");
    r.longitude_deg = ar.read_scalar<double>("CObservationGPS.RMC.longitude");
    r.speed_knots = ar.read_scalar<double>("CObservationGPS.RMC.speed_knots");
    r.course_deg = ar.read_scalar<double>("CObservationGPS.RMC.direction");
    g.rmc = r;
  }
  if (h.version >= 2) g.sensor_label = read_mrpt_string(ar, "CObservationGPS.sensorLabel");
  if (h.version >= 4) {
    g.T_robot_sensor = expect_mrpt<Pose3>(ar, "CObservationGPS.sensorPose", "CPose3D");
  }
  if (h.version >= 5) {
    const std::uint64_t at = ar.offset();
    if (read_mrpt_bool(ar, "CObservationGPS.has_PZS")) {
      ar.fail_at(at, "CObservationGPS.PZS", "TOPCON PZS data is not supported");
    }
  }
  if (h.version >= 7) {
    const std::uint64_t at = ar.offset();
    if (read_mrpt_bool(ar, "CObservationGPS.has_SATS")) {
      ar.fail_at(at, "CObservationGPS.SATS", "TOPCON SATS data is not supported (nor by MRPT)");
    }
  }
  g.original_received_timestamp = g.timestamp;
  g.has_satellite_timestamp = false;
}

MrptObject read_gps(InArchive& ar, const MrptObjectHeader& h) {
  // Version 0 dumped in-memory structs of a layout no longer documented.
  if (h.version == 0 || h.version > 11) throw_unknown_mrpt_version(ar, h);
  auto g = std::make_shared<GpsObservation>();
  if (h.version >= 10) {
    read_gps_messages(ar, h, *g);
  } else {
    read_gps_legacy(ar, h, *g);
  }
  parse_guard(ar, h.offset, "CObservationGPS", [&] { g->check(); });
  return std::shared_ptr<Observation>(std::move(g));
}

// ---- images and cameras ----------------------------------------------------

// OpenCV depth codes MRPT's CImage v9 stores for gray images.
PixelType pixel_type_from_depth(InArchive& ar, std::uint64_t at, std::int32_t depth) {
  switch (depth) {
    case 0: return PixelType::U8;   // CV_8U
    case 2: return PixelType::U16;  // CV_16U
    case 5: return PixelType::F32;  // CV_32F
    default:
      ar.fail_at(at, "CImage.depth",
                 fmt::format("pixel depth {} is not supported (8U, 16U and 32F are)", depth));
  }
}

// CImage (MRPT built with OpenCV) v2..9 and v100: (v>=6) bool external
// storage; gray images as i32 width, height, origin, imageSize, (v9) i32
// depth, (v>=5) bool zipped, the rows; color images (v>=7) as i32 width,
// height: negative means raw BGR rows follow, positive a JPEG stream.
// External files, zipped data and JPEG are rejected (rove decodes neither).
MrptObject read_image(InArchive& ar, const MrptObjectHeader& h) {
  constexpr std::string_view kField = "CImage";
  if (h.version == 100) {
    ar.fail_at(h.offset, kField, "image saved by an MRPT build without OpenCV has no pixels");
  }
  if (h.version < 2 || h.version > 9) throw_unknown_mrpt_version(ar, h);
  if (h.version >= 6 && read_mrpt_bool(ar, "CImage.externalStorage")) {
    const std::string file = read_mrpt_string(ar, "CImage.externalFile");
    ar.fail_at(h.offset, kField,
               fmt::format("externally stored image '{}' is not supported", file));
  }
  const bool has_color = ar.read_scalar<std::uint8_t>("CImage.hasColor") != 0;
  Image img;
  if (!has_color) {
    const std::uint64_t at = ar.offset();
    const auto width = ar.read_scalar<std::int32_t>("CImage.width");
    const auto height = ar.read_scalar<std::int32_t>("CImage.height");
    static_cast<void>(ar.read_scalar<std::int32_t>("CImage.origin"));
    const auto size = ar.read_scalar<std::int32_t>("CImage.imageSize");
    PixelType type = PixelType::U8;
    if (h.version >= 9) {
      const std::uint64_t depth_at = ar.offset();
      type = pixel_type_from_depth(ar, depth_at, ar.read_scalar<std::int32_t>("CImage.depth"));
    }
    if (width < 0 || height < 0 || size < 0) {
      ar.fail_at(at, kField, fmt::format("negative size {}x{} ({} bytes)", width, height, size));
    }
    img.width = static_cast<std::uint32_t>(width);
    img.height = static_cast<std::uint32_t>(height);
    img.channels = 1;
    img.pixel_type = type;
    const std::uint64_t expected = std::uint64_t{img.width} * img.height * bytes_per_sample(type);
    if (static_cast<std::uint64_t>(size) != expected) {
      ar.fail_at(at, "CImage.imageSize",
                 fmt::format("{} bytes for a {}x{} image of {}-byte pixels", size, width, height,
                             bytes_per_sample(type)));
    }
    bool zipped = h.version >= 3;
    if (h.version == 4 && size <= 16 * 1024) zipped = false;
    if (h.version >= 5) zipped = read_mrpt_bool(ar, "CImage.imageIsZIP");
    if (zipped) ar.fail_at(at, kField, "zip-compressed image data is not supported (nor by MRPT)");
    ar.check_length(expected, 1, "CImage.data", at);
    ar.append_scalars(img.data, expected, "CImage.data");
    return img;
  }
  const std::uint64_t at = ar.offset();
  std::int32_t width = 1, height = 1;
  if (h.version >= 7) {
    width = ar.read_scalar<std::int32_t>("CImage.width");
    height = ar.read_scalar<std::int32_t>("CImage.height");
  }
  if (width >= 1 && height >= 1) {
    ar.fail_at(at, kField, "JPEG-compressed color image: rove has no JPEG decoder");
  }
  img.channels = 3;
  img.pixel_type = PixelType::U8;
  if (width < 0 && height < 0) {
    // Raw rows of B, G, R bytes; rove stores R, G, B.
    img.width = static_cast<std::uint32_t>(-static_cast<std::int64_t>(width));
    img.height = static_cast<std::uint32_t>(-static_cast<std::int64_t>(height));
    const std::uint64_t bytes = std::uint64_t{img.width} * img.height * 3;
    ar.check_length(bytes, 1, "CImage.data", at);
    ar.append_scalars(img.data, bytes, "CImage.data");
    for (std::size_t i = 0; i + 2 < img.data.size(); i += 3) std::swap(img.data[i], img.data[i + 2]);
  } else {
    // A 0xN or Nx0 image: MRPT stores no pixels.
    img.width = static_cast<std::uint32_t>(std::max(width, 0));
    img.height = static_cast<std::uint32_t>(std::max(height, 0));
    if (!img.empty()) ar.fail_at(at, kField, fmt::format("bad image size {}x{}", width, height));
  }
  return img;
}

// TCamera v0..6: double focalLengthMeters, 5 distortion doubles (v>=3: 8),
// (v<4) the 3x3 intrinsic matrix as a CMatrixD object, (v>=4) fx, fy, cx,
// cy, (v0) a 1x5 CMatrixD, (v>=2) u32 nrows, ncols, (v>=5) cameraName,
// (v>=6) u8 distortion model (0 none, 1 plumb_bob, 2 kannala_brandt).
MrptObject read_camera(InArchive& ar, const MrptObjectHeader& h) {
  if (h.version > 6) throw_unknown_mrpt_version(ar, h);
  PinholeCamera c;
  static_cast<void>(ar.read_scalar<double>("TCamera.focalLengthMeters"));
  std::array<double, 8> dist{};
  const std::uint64_t dist_at = ar.offset();
  for (int k = 0; k < (h.version >= 3 ? 8 : 5); ++k) dist[k] = ar.read_scalar<double>("TCamera.dist");
  if (h.version < 4) {
    const Eigen::MatrixXd K = expect_mrpt_matrix(ar, "TCamera.intrinsicParams", 3, 3);
    c.fx = K(0, 0);
    c.fy = K(1, 1);
    c.cx = K(0, 2);
    c.cy = K(1, 2);
  } else {
    c.fx = ar.read_scalar<double>("TCamera.fx");
    c.fy = ar.read_scalar<double>("TCamera.fy");
    c.cx = ar.read_scalar<double>("TCamera.cx");
    c.cy = ar.read_scalar<double>("TCamera.cy");
  }
  if (h.version == 0) static_cast<void>(expect_mrpt_matrix(ar, "TCamera.distortionParams", 1, 5));
  if (h.version >= 2) {
    c.height = ar.read_scalar<std::uint32_t>("TCamera.nrows");
    c.width = ar.read_scalar<std::uint32_t>("TCamera.ncols");
  } else {
    c.height = 480;
    c.width = 640;
  }
  if (h.version >= 5) static_cast<void>(read_mrpt_string(ar, "TCamera.cameraName"));
  std::uint8_t model = 1;
  if (h.version >= 6) {
    const std::uint64_t at = ar.offset();
    model = ar.read_scalar<std::uint8_t>("TCamera.distortion");
    if (model > 1) {
      ar.fail_at(at, "TCamera.distortion",
                 fmt::format("distortion model {} is not supported (none and plumb_bob are)",
                             model));
    }
  }
  if (dist[5] != 0.0 || dist[6] != 0.0 || dist[7] != 0.0) {
    ar.fail_at(dist_at, "TCamera.dist", "the rational distortion terms k4..k6 are not supported");
  }
  if (model == 1) {
    // MRPT's order k1, k2, p1, p2, k3 is OpenCV's, as rove's.
    for (int k = 0; k < 5; ++k) c.distortion[k] = dist[k];
  }
  return c;
}

// ---- 3D range scans --------------------------------------------------------

DepthImage read_u16_image(InArchive& ar, std::string_view field, std::uint32_t rows,
                          std::uint32_t cols, double scale, std::uint64_t at) {
  DepthImage d;
  d.width = cols;
  d.height = rows;
  d.scale = scale;
  const std::uint64_t n = std::uint64_t{rows} * cols;
  ar.check_length(n, sizeof(std::uint16_t), field, at);
  std::vector<std::uint16_t> v;
  ar.append_scalars(v, n, field);
  d.values = std::move(v);
  return d;
}

// CObservation3DRangeScan v0..10: maxRange (float), sensorPose (CPose3D
// object), (v>0) bool hasPoints3D, points (u32 N, N floats x, y, z, (v0) N
// validity bytes, (v>=8) N u16 column and N u16 row indices), (v>=1) bool
// hasRangeImage, (v>=9) float rangeUnits, the range image ((v<9) a CMatrixF
// object in meters; (v>=9) u32 rows, u32 cols, u16 values), bool
// hasIntensityImage + CImage, bool hasConfidenceImage + CImage, (v>=2)
// cameraParams (TCamera), (v>=4) cameraParamsIntensity (TCamera) and
// relativePoseIntensityWRTDepth (CPose3D); float stdError, timestamp,
// sensorLabel, (v>=3) bool + string external points file, bool + string
// external range file, (v>=5) bool range_is_depth, (v>=6) i8
// intensityImageChannel, (v>=7) bool hasPixelLabels (+ labels), (v>=10) u8
// layer count and per layer name, u32 cols, u32 rows, u16 values.
MrptObject read_range_scan_3d(InArchive& ar, const MrptObjectHeader& h) {
  constexpr std::string_view kField = "CObservation3DRangeScan";
  if (h.version > 10) throw_unknown_mrpt_version(ar, h);
  auto o = std::make_shared<RangeImage3D>();
  o->max_range = ar.read_scalar<float>("CObservation3DRangeScan.maxRange");
  o->T_robot_sensor = expect_mrpt<Pose3>(ar, "CObservation3DRangeScan.sensorPose", "CPose3D");
  const bool has_points = h.version == 0 || read_mrpt_bool(ar, "CObservation3DRangeScan.hasPoints3D");
  if (has_points) {
    constexpr std::string_view kPts = "CObservation3DRangeScan.points3D";
    const std::uint64_t min_bytes = 12 + (h.version == 0 ? 1 : 0) + (h.version >= 8 ? 4 : 0);
    const std::uint32_t n = ar.read_length(kPts, min_bytes);
    std::vector<float> x, y, z;
    ar.append_scalars(x, n, kPts);
    ar.append_scalars(y, n, kPts);
    ar.append_scalars(z, n, kPts);
    RangeImagePoints pts;
    pts.p_sensor.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) pts.p_sensor[i] = Eigen::Vector3f(x[i], y[i], z[i]);
    if (h.version == 0) {
      std::vector<std::uint8_t> valid;
      ar.append_scalars(valid, n, "CObservation3DRangeScan.validRange");
    }
    if (h.version >= 8) {
      ar.append_scalars(pts.pixel_u, n, "CObservation3DRangeScan.points3D_idxs_x");
      ar.append_scalars(pts.pixel_v, n, "CObservation3DRangeScan.points3D_idxs_y");
    }
    o->points = std::move(pts);
  }
  float range_units = 1e-3f;
  if (h.version >= 1) {
    const bool has_range = read_mrpt_bool(ar, "CObservation3DRangeScan.hasRangeImage");
    if (h.version >= 9) {
      const std::uint64_t at = ar.offset();
      range_units = ar.read_scalar<float>("CObservation3DRangeScan.rangeUnits");
      if (!(std::isfinite(range_units) && range_units > 0.0f)) {
        ar.fail_at(at, "CObservation3DRangeScan.rangeUnits",
                   fmt::format("range units {} must be > 0", range_units));
      }
    }
    const double scale = 1.0 / static_cast<double>(range_units);
    if (has_range) {
      const std::uint64_t at = ar.offset();
      if (h.version < 9) {
        // Meters as floats: kept as a float image (scale 1).
        const Eigen::MatrixXd m = expect_mrpt<Eigen::MatrixXd>(
            ar, "CObservation3DRangeScan.rangeImage", "a matrix");
        DepthImage d = DepthImage::zeros_f32(static_cast<std::uint32_t>(m.cols()),
                                             static_cast<std::uint32_t>(m.rows()), 1.0);
        auto& v = std::get<std::vector<float>>(d.values);
        for (Eigen::Index r = 0; r < m.rows(); ++r) {
          for (Eigen::Index c = 0; c < m.cols(); ++c) {
            v[static_cast<std::size_t>(r * m.cols() + c)] = static_cast<float>(m(r, c));
          }
        }
        o->depth = std::move(d);
      } else {
        const auto rows = ar.read_scalar<std::uint32_t>("CObservation3DRangeScan.rangeImage.rows");
        const auto cols = ar.read_scalar<std::uint32_t>("CObservation3DRangeScan.rangeImage.cols");
        o->depth = read_u16_image(ar, "CObservation3DRangeScan.rangeImage", rows, cols, scale, at);
      }
    } else {
      o->depth = DepthImage::zeros_u16(0, 0, scale);
    }
    if (read_mrpt_bool(ar, "CObservation3DRangeScan.hasIntensityImage")) {
      o->intensity = expect_mrpt<Image>(ar, "CObservation3DRangeScan.intensityImage", "CImage");
    }
    if (read_mrpt_bool(ar, "CObservation3DRangeScan.hasConfidenceImage")) {
      o->confidence = expect_mrpt<Image>(ar, "CObservation3DRangeScan.confidenceImage", "CImage");
    }
    if (h.version >= 2) {
      o->depth_camera =
          expect_mrpt<PinholeCamera>(ar, "CObservation3DRangeScan.cameraParams", "TCamera");
      if (h.version >= 4) {
        o->intensity_camera = expect_mrpt<PinholeCamera>(
            ar, "CObservation3DRangeScan.cameraParamsIntensity", "TCamera");
        o->T_sensor_intensity = expect_mrpt<Pose3>(
            ar, "CObservation3DRangeScan.relativePoseIntensityWRTDepth", "CPose3D");
      } else {
        o->intensity_camera = o->depth_camera;
        o->T_sensor_intensity = Pose3();  // MRPT's default for these versions
      }
    }
  } else {
    o->depth = DepthImage::zeros_u16(0, 0, 1000.0);
  }
  o->std_error_m = ar.read_scalar<float>("CObservation3DRangeScan.stdError");
  o->timestamp = read_mrpt_timestamp(ar, "CObservation3DRangeScan.timestamp");
  o->sensor_label = read_mrpt_string(ar, "CObservation3DRangeScan.sensorLabel");
  if (h.version >= 3) {
    const std::uint64_t at = ar.offset();
    const bool points_external = read_mrpt_bool(ar, "CObservation3DRangeScan.points3DExternal");
    const std::string points_file = read_mrpt_string(ar, "CObservation3DRangeScan.points3DFile");
    const bool range_external = read_mrpt_bool(ar, "CObservation3DRangeScan.rangeImageExternal");
    const std::string range_file = read_mrpt_string(ar, "CObservation3DRangeScan.rangeImageFile");
    if (points_external || range_external) {
      ar.fail_at(at, kField,
                 fmt::format("externally stored data ('{}') is not supported",
                             points_external ? points_file : range_file));
    }
  }
  o->range_is_depth =
      h.version >= 5 ? read_mrpt_bool(ar, "CObservation3DRangeScan.range_is_depth") : true;
  if (h.version >= 6) {
    const std::uint64_t at = ar.offset();
    const auto ch = ar.read_scalar<std::int8_t>("CObservation3DRangeScan.intensityImageChannel");
    if (ch != 0 && ch != 1) {
      ar.fail_at(at, "CObservation3DRangeScan.intensityImageChannel",
                 fmt::format("unknown intensity channel {}", ch));
    }
    o->intensity_channel = ch == 0 ? IntensityChannel::Visible : IntensityChannel::Infrared;
  }
  if (h.version >= 7) {
    const std::uint64_t at = ar.offset();
    if (read_mrpt_bool(ar, "CObservation3DRangeScan.hasPixelLabels")) {
      ar.fail_at(at, "CObservation3DRangeScan.pixelLabels", "pixel labels are not supported");
    }
  }
  if (h.version >= 10) {
    const auto layers = ar.read_scalar<std::uint8_t>("CObservation3DRangeScan.otherLayers");
    for (std::uint8_t i = 0; i < layers; ++i) {
      const std::uint64_t at = ar.offset();
      std::string name = read_mrpt_string(ar, "CObservation3DRangeScan.otherLayers.name");
      const auto cols = ar.read_scalar<std::uint32_t>("CObservation3DRangeScan.otherLayers.cols");
      const auto rows = ar.read_scalar<std::uint32_t>("CObservation3DRangeScan.otherLayers.rows");
      DepthImage layer =
          read_u16_image(ar, "CObservation3DRangeScan.otherLayers", rows, cols, o->depth.scale, at);
      if (!o->other_depth_layers.emplace(std::move(name), std::move(layer)).second) {
        ar.fail_at(at, "CObservation3DRangeScan.otherLayers", "duplicate layer name");
      }
    }
  }
  // MRPT corrects a camera resolution that disagrees with the range image.
  if (o->depth.pixel_count() != 0) {
    o->depth_camera.width = o->depth.width;
    o->depth_camera.height = o->depth.height;
  }
  parse_guard(ar, h.offset, kField, [&] { o->check(); });
  return std::shared_ptr<Observation>(std::move(o));
}

}  // namespace

void add_mrpt_sensor_readers(const MrptReaderAdder& add) {
  add("mrpt::obs::", "CActionRobotMovement3D", read_robot_movement_3d);
  add("mrpt::obs::", "CObservationComment", read_comment);
  add("mrpt::obs::", "CObservationRotatingScan", read_rotating_scan);
  add("mrpt::obs::", "CObservationVelodyneScan", read_velodyne_scan);
  add("mrpt::obs::", "CObservationGPS", read_gps);
  add("mrpt::obs::", "CObservation3DRangeScan", read_range_scan_3d);
  add("mrpt::img::", "CImage", read_image);
  add("mrpt::img::", "TCamera", read_camera);
}

}  // namespace rove::detail
