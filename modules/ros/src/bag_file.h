#pragma once
// rove's own reader of the ROS 1 bag file format 2.0 (records, chunks,
// connections; http://wiki.ros.org/Bags/Format/2.0), streaming in file
// order. It needs no index, so a bag that was never closed (no index) or
// that ends mid-record is read up to its last complete message, and it
// reports the byte offset where it stopped instead of refusing the file.

#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace rove::bag_detail {

// A connection: one topic of one message type.
struct BagConnection {
  std::uint32_t id = 0;
  std::string topic;
  std::string datatype;
  std::string md5sum;
};

// One message: its connection, record time and serialized bytes (valid
// until the next call of BagFile::next).
struct BagMessage {
  const BagConnection* connection = nullptr;
  std::uint32_t sec = 0, nsec = 0;
  std::span<const std::uint8_t> data;
  std::int64_t time_ns() const { return std::int64_t{sec} * 1'000'000'000 + nsec; }
};

// What the file held and where reading stopped.
struct BagFileStats {
  std::map<std::string, std::uint64_t> chunks_by_compression;
  std::uint64_t messages = 0;
  std::uint64_t unknown_records = 0;
  // Set when the file ended early or a record is malformed: the byte offset
  // of the record that could not be read, and why.
  std::optional<std::uint64_t> stopped_at;
  std::string stop_reason;
  // Messages of a connection no record defined (skipped).
  std::uint64_t orphan_messages = 0;
  // Whether the bag header points to an index (false: never closed).
  bool indexed = false;
};

class BagFile {
 public:
  // Opens `path`: checks the "#ROSBAG V2.0" line and reads the bag header
  // record. Throws IoError / ParseError (file, offset, field).
  explicit BagFile(const std::string& path);

  // The next message in file order (within a chunk, stably sorted by record
  // time), or std::nullopt at the end or where the file stops being
  // readable (stats().stopped_at).
  std::optional<BagMessage> next();

  // Bytes of the file consumed so far.
  std::uint64_t position() const noexcept { return offset_; }
  std::uint64_t file_size() const noexcept { return size_; }
  const BagFileStats& stats() const noexcept { return stats_; }
  const std::string& path() const noexcept { return path_; }

 private:
  struct Pending {
    std::uint32_t conn = 0;
    std::uint32_t sec = 0, nsec = 0;
    std::size_t begin = 0, size = 0;  // in chunk_
  };
  bool read_record();           // one top-level record; false at the end
  void stop(std::uint64_t at, std::string reason);
  void parse_chunk_records(std::size_t valid_bytes, std::uint64_t chunk_offset);
  void add_connection(std::uint32_t id, const std::string& topic, std::span<const std::uint8_t> data);

  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
  bool done_ = false;
  std::map<std::uint32_t, BagConnection> connections_;
  std::vector<std::uint8_t> chunk_;
  std::vector<Pending> pending_;
  std::size_t next_pending_ = 0;
  BagFileStats stats_;
};

}  // namespace rove::bag_detail
