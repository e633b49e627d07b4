#pragma once
/// \file
/// Reading ROS 1 bags (format 2.0) as rove rawlogs: sensor_msgs/LaserScan →
/// RangeScan2D, nav_msgs/Odometry → RobotMovement2D increments (layout #1)
/// or OdometryObservation (layout #2), sensor_msgs/PointCloud2 →
/// RangeImage3D holding points, sensor_msgs/Image (depth 16UC1 / 32FC1)
/// with CameraInfo and the colour image of the same time → RangeImage3D,
/// other images → ImageObservation; /tf and /tf_static give each sensor's
/// pose on the robot (BagReadOptions::base_frame ← the message's frame_id).
///
/// The bag is read by rove's own parser of the file format, in file order
/// (chunks are time-ordered as rosbag writes them; messages within a chunk
/// are sorted by time), with no need of the index at the end: a bag that
/// was never closed, or that ends mid-chunk, is read up to its last
/// complete message. Chunks may be uncompressed, bz2 or lz4. What is not
/// read is reported by skipped(): messages per topic of an unsupported type
/// or left out by BagReadOptions::topics, malformed messages (with the
/// field at fault), and the byte offset where a damaged file stopped.
///
/// Sensor labels are the first component of the topic name ("/scan" →
/// "scan", "/camera/depth/image_raw" → "camera"), so several topics of one
/// device share a label.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rove/io/any_rawlog.h"

namespace rove {

/// What BagReader read and left out.
struct BagReadStats {
  /// Messages converted, by topic.
  std::map<std::string, std::uint64_t> read_by_topic;
  /// Messages left out, by "topic (type): reason".
  std::map<std::string, std::uint64_t> skipped;
  /// Chunks by compression ("none", "bz2", "lz4").
  std::map<std::string, std::uint64_t> chunks_by_compression;
  /// Where a damaged file stopped being readable (byte offset) and why.
  std::optional<std::uint64_t> stopped_at;
  /// Why it stopped (empty unless stopped_at is set).
  std::string stop_reason;
  /// Whether the bag had an index (false: it was never closed).
  bool indexed = false;
};

/// Streams the entries of a ROS 1 bag. Thread-safety: not safe for
/// concurrent use.
class BagReader final : public RawlogSource {
 public:
  /// Opens `path`. Throws IoError if it cannot be opened, ParseError if it
  /// is not a bag of format 2.0 (or its first record is not a bag header),
  /// InvalidArgument if options.layout is neither ActionsSensoryFrames nor
  /// Observations.
  explicit BagReader(const std::string& path, BagReadOptions options = {});
  ~BagReader() override;
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  /// The next entry, or std::nullopt at the end of what could be read.
  std::optional<RawlogEntry> next() override;
  /// Bytes of the file read so far.
  std::uint64_t position() const override;
  /// options.layout.
  RawlogLayout layout() const override;
  /// skipped counts and the stop, one line each.
  std::vector<std::string> skipped() const override;
  /// The counts so far.
  const BagReadStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Makes every AnyRawlogReader (and so every rove command that reads a
/// rawlog) read ROS bags through BagReader. Idempotent.
void register_bag_reader();

}  // namespace rove
