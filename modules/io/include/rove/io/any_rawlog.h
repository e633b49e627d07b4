#pragma once
/// \file
/// One entry point for every robot log rove reads as a rawlog: rove rawlogs,
/// MRPT rawlogs and CARMEN logs, told apart by their first bytes (after
/// gunzip or bunzip2), plain or compressed; and ROS 1 bags, when a reader
/// for them is registered (register_rawlog_source; the optional rove::ros
/// adapter provides one, so this module does not depend on ROS).
///
/// Detection: "#ROSBAG V2.0" → ROS bag; "ROVERAWL" → rove rawlog; "BZh" or printable text → CARMEN log
/// when a line within its first 256 KiB starts with a CARMEN message name
/// (FLASER, ODOM, PARAM, ...), else an error (a .g2o, a .pcd or any other
/// text is not a log); binary data starting with an MRPT object header
/// (0x80 | name length, or an old-style u32 length below 128, then a
/// printable class name) → MRPT rawlog; anything else is an error. A CARMEN
/// log that ends without a single record, or whose records give no entry
/// (ODOM or TRUEPOS lines without a laser scan in layout #1), is an error
/// too, never an empty log.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "rove/io/carmen_to_rawlog.h"
#include "rove/io/rawlog_reader.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/motion_model_options.h"

namespace rove {

/// The file formats AnyRawlogReader reads.
enum class RawlogFormat : std::uint8_t {
  Rove = 0,    ///< rove rawlog (rove_rawlog.h)
  Mrpt = 1,    ///< MRPT rawlog (rawlog_reader.h)
  Carmen = 2,  ///< CARMEN log, converted on the fly (carmen_to_rawlog.h)
  RosBag = 3,  ///< ROS 1 bag (format 2.0), through a registered RawlogSource
};

/// The first bytes of a ROS 1 bag, format 2.0.
inline constexpr std::string_view kRosBagMagic = "#ROSBAG V2.0\n";

/// "rove", "MRPT", "CARMEN" or "ROS bag".
std::string_view to_string(RawlogFormat format) noexcept;

/// The format of the file at `path`, from its first bytes. Throws IoError
/// if it cannot be opened or read or is not a regular file (a directory,
/// /dev/zero, a FIFO); ParseError (file, offset 0, "format") if it is empty,
/// gzip-compressed text, text without CARMEN message lines, or binary data
/// that is not an MRPT object.
RawlogFormat detect_rawlog_format(const std::string& path);

/// Options of the ROS bag reader (used by the rove::ros adapter; declared
/// here so that every command can pass them without depending on ROS).
struct BagReadOptions {
  /// Topics to read (exact names, e.g. "/scan"); empty: every topic of a
  /// supported message type. Topics of unsupported types are always
  /// skipped and counted.
  std::vector<std::string> topics;
  /// The robot's frame: sensor poses (T_robot_sensor) are looked up in /tf
  /// and /tf_static as base_frame ← the message's frame_id.
  std::string base_frame = "base_link";
  /// Output layout: ActionsSensoryFrames (each observation in its own
  /// sensory frame, preceded by the odometry increment since the previous
  /// frame as a RobotMovement2D, MRPT's CActionRobotMovement2D) or
  /// Observations (odometry as OdometryObservation).
  RawlogLayout layout = RawlogLayout::ActionsSensoryFrames;
  /// Motion model of the RobotMovement2D actions made from odometry.
  MotionModelOptions motion_model;
};

/// Options of AnyRawlogReader, per format.
struct AnyRawlogOptions {
  /// For MRPT rawlogs.
  RawlogReaderOptions mrpt;
  /// For rove rawlogs.
  RoveRawlogReaderOptions rove;
  /// For CARMEN logs (layout, motion model, labels).
  CarmenToRawlogOptions carmen;
  /// For ROS bags.
  BagReadOptions bag;
};

/// A reader of a log format this module knows by its first bytes but does
/// not decode itself (ROS bags): implemented by an adapter and installed
/// with register_rawlog_source.
class RawlogSource {
 public:
  virtual ~RawlogSource() = default;
  /// The next entry, or std::nullopt at the end (or where a damaged file
  /// stops being readable; skipped() then says where).
  virtual std::optional<RawlogEntry> next() = 0;
  /// How far the reader is, in bytes of the file.
  virtual std::uint64_t position() const = 0;
  /// The layout of the entries it produces.
  virtual RawlogLayout layout() const = 0;
  /// What was left out so far, one line each (e.g. "412 messages on
  /// /camera/imu (sensor_msgs/Imu): unsupported type", "stopped at byte
  /// 1234567: truncated chunk"); empty when nothing was.
  virtual std::vector<std::string> skipped() const = 0;
};

/// Opens a file of a registered format.
using RawlogSourceOpener =
    std::function<std::unique_ptr<RawlogSource>(const std::string& path, const AnyRawlogOptions&)>;

/// Installs the reader of `format` (only RawlogFormat::RosBag is open to
/// registration); a later call replaces it, an empty function removes it.
/// Call it before any reader is opened (not thread-safe against readers
/// being constructed). Throws InvalidArgument for another format.
void register_rawlog_source(RawlogFormat format, RawlogSourceOpener opener);
/// Whether a reader of `format` is available (always true for the built-in
/// formats).
bool rawlog_format_available(RawlogFormat format);

/// Streams the entries of a rove rawlog, an MRPT rawlog or a CARMEN log, in
/// constant memory. Thread-safety: not safe for concurrent use.
class AnyRawlogReader {
 public:
  /// Opens `path` and detects its format. Throws IoError if it cannot be
  /// opened; ParseError if it is empty or (rove) its header is malformed.
  explicit AnyRawlogReader(const std::string& path, AnyRawlogOptions options = {});
  ~AnyRawlogReader();
  AnyRawlogReader(const AnyRawlogReader&) = delete;
  AnyRawlogReader& operator=(const AnyRawlogReader&) = delete;

  /// The next entry, or std::nullopt at the end; errors as the format's
  /// reader (ParseError naming the file, the byte offset or line, and the
  /// class or field). A CARMEN log that ends without any record, or
  /// without any entry from its records, is a ParseError (field "records").
  std::optional<RawlogEntry> next();

  /// The detected format.
  RawlogFormat format() const noexcept { return format_; }
  /// How far the reader is: decompressed bytes (rove, MRPT) or lines
  /// (CARMEN).
  std::uint64_t position() const;
  /// Entries returned so far.
  std::uint64_t entries_read() const noexcept { return entries_; }
  /// The declared layout (rove), the converter's layout (CARMEN), or
  /// std::nullopt (MRPT files declare none).
  std::optional<RawlogLayout> declared_layout() const;
  /// The rove reader, when format() is kRove (metadata, skipped entries);
  /// nullptr otherwise.
  const RoveRawlogReader* rove() const noexcept { return rove_.get(); }
  /// The CARMEN source, when format() is kCarmen (conversion counts);
  /// nullptr otherwise.
  const CarmenRawlogSource* carmen() const noexcept { return carmen_.get(); }
  /// The registered source, when format() is RosBag; nullptr otherwise.
  const RawlogSource* source() const noexcept { return source_.get(); }
  /// What the reader left out so far (RawlogSource::skipped; the rove
  /// reader's skipped entries by class); empty when nothing was.
  std::vector<std::string> skipped() const;
  /// The file path.
  const std::string& path() const noexcept { return path_; }

 private:
  std::string path_;
  RawlogFormat format_;
  std::unique_ptr<RoveRawlogReader> rove_;
  std::unique_ptr<RawlogReader> mrpt_;
  std::unique_ptr<CarmenRawlogSource> carmen_;
  std::unique_ptr<RawlogSource> source_;
  std::uint64_t entries_ = 0;
};

/// A whole log in memory, whatever its format.
struct AnyRawlog {
  /// The entries in file order.
  std::vector<RawlogEntry> entries;
  /// The layout the entries follow (layout_of).
  RawlogLayout layout = RawlogLayout::Empty;
  /// The file's format.
  RawlogFormat format = RawlogFormat::Mrpt;
};

/// Reads every entry of a rove rawlog, MRPT rawlog or CARMEN log.
AnyRawlog load_any_rawlog(const std::string& path, AnyRawlogOptions options = {});

}  // namespace rove
