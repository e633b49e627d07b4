#pragma once
/// \file
/// rove's own rawlog file: a header, then entries (action collections,
/// sensory frames or bare observations) written with write_object, then an
/// end record. gzip-compressed by default; read back entry by entry in
/// constant memory, or whole.
///
/// Byte layout (after gunzip; every integer little-endian; see
/// docs/rawlog.md):
///
///   header   magic "ROVERAWL" (8 bytes)
///            u16 format version (kRoveRawlogFormatVersion, 1)
///            u8  layout: 1 = action collections + sensory frames,
///                2 = observations, 3 = mixed
///            u32 metadata count n, then n × (string key, string value)
///            (string: u32 byte count + bytes)
///   entries  u64 record length L (>= 1), then L bytes: one write_object
///            record (class name, version, payload, end marker 0x88)
///   end      u64 0, then u64 number of entries
///
/// Every entry carries its length, so a reader can pass over an entry whose
/// class it does not know (RoveRawlogReaderOptions::skip_unknown_classes),
/// and a file cut short is told apart from a complete one (no end record).
/// Classes are looked up in ClassRegistry::global() after
/// register_obs_classes(), so every registered rove::obs type is covered.

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/rawlog_reader.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/observation.h"
#include "rove/obs/sensory_frame.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/stream.h"

namespace rove {

/// The first 8 bytes of a rove rawlog (after gunzip).
inline constexpr std::array<char, 8> kRoveRawlogMagic = {'R', 'O', 'V', 'E', 'R', 'A', 'W', 'L'};
/// The format version this build writes (and the newest it reads).
inline constexpr std::uint16_t kRoveRawlogFormatVersion = 1;

/// Metadata of a rove rawlog: free key → value strings, e.g. "source" (the
/// file it was converted from) and "tool" (the program and version that
/// wrote it). Keys are unique.
using RawlogMetadata = std::map<std::string, std::string>;

/// How RoveRawlogWriter writes.
struct RoveRawlogWriterOptions {
  /// The layout declared in the header; write() rejects entries that do not
  /// fit it (InvalidArgument). kEmpty is not allowed. Default: layout #1.
  RawlogLayout layout = RawlogLayout::ActionsSensoryFrames;
  /// gzip the file (default true); false writes plain bytes.
  bool gzip = true;
  /// gzip level 1 (fastest) .. 9 (smallest). Default 6.
  int gzip_level = 6;
  /// Stored in the header.
  RawlogMetadata metadata;
};

/// Streaming writer of rove rawlogs: each entry goes to the file as it is
/// written (one entry is buffered to learn its length). Call close() to
/// write the end record and see errors; a writer destroyed without close()
/// leaves a file without end record, which readers report as truncated.
///
/// Thread-safety: not safe for concurrent use.
class RoveRawlogWriter {
 public:
  /// Creates (truncates) `path`. Throws IoError if it cannot,
  /// InvalidArgument on bad options.
  RoveRawlogWriter(const std::string& path, RoveRawlogWriterOptions options = {});
  /// Writes to `stream` (already compressed or not as the caller chose;
  /// options.gzip is ignored). Throws InvalidArgument if it is null.
  RoveRawlogWriter(std::unique_ptr<OutStream> stream, RoveRawlogWriterOptions options = {});
  /// If close() was not called (e.g. an exception interrupted the job),
  /// closes the file without the end record, so readers report it as
  /// truncated rather than complete.
  ~RoveRawlogWriter();
  RoveRawlogWriter(const RoveRawlogWriter&) = delete;
  RoveRawlogWriter& operator=(const RoveRawlogWriter&) = delete;

  /// Appends an action collection (layouts #1 and mixed).
  void write(const ActionCollection& actions);
  /// Appends a sensory frame (layouts #1 and mixed).
  void write(const SensoryFrame& frame);
  /// Appends a bare observation (layouts #2 and mixed).
  void write(const Observation& observation);
  /// Appends any entry.
  void write(const RawlogEntry& entry);

  /// Writes the end record and closes the file. Throws IoError on failure.
  /// Later writes throw InvalidArgument; later close() calls do nothing.
  void close();

  /// Entries written so far.
  std::uint64_t entries_written() const noexcept { return entries_; }
  /// Uncompressed bytes written so far.
  std::uint64_t bytes_written() const;
  /// The layout declared in the header.
  RawlogLayout layout() const noexcept { return options_.layout; }

 private:
  void write_header();
  void write_record(const Serializable& obj, bool is_observation);

  RoveRawlogWriterOptions options_;
  std::unique_ptr<OutStream> stream_;
  std::unique_ptr<OutArchive> archive_;
  std::uint64_t entries_ = 0;
  bool closed_ = false;
};

/// Options of RoveRawlogReader.
struct RoveRawlogReaderOptions {
  /// Bounds on declared lengths and nesting while reading untrusted data.
  ArchiveLimits limits;
  /// Largest entry record accepted, bytes (default 1 GiB); a larger
  /// declared length is a ParseError before anything is allocated.
  std::uint64_t max_entry_bytes = std::uint64_t{1} << 30;
  /// false (default): an entry of a class this build does not know is a
  /// ParseError naming it. true: it is passed over and counted in
  /// skipped_entries().
  bool skip_unknown_classes = false;
};

/// Streams the entries of a rove rawlog (plain or gzip) one at a time in
/// constant memory.
///
/// Thread-safety: not safe for concurrent use.
class RoveRawlogReader {
 public:
  /// Opens `path` and reads the header. Throws IoError if it cannot be
  /// opened, ParseError (file, offset, field) if the header is not a rove
  /// rawlog header of a version this build reads.
  explicit RoveRawlogReader(const std::string& path, RoveRawlogReaderOptions options = {});
  /// Reads from an open stream (e.g. a MemoryInStream). Same errors.
  explicit RoveRawlogReader(std::unique_ptr<InStream> stream, RoveRawlogReaderOptions options = {});
  ~RoveRawlogReader();
  RoveRawlogReader(const RoveRawlogReader&) = delete;
  RoveRawlogReader& operator=(const RoveRawlogReader&) = delete;

  /// The next entry, or std::nullopt after the end record. Throws
  /// ParseError (file, byte offset in the decompressed data, class or
  /// field) on malformed, hostile or truncated data: a record whose length
  /// disagrees with its content, an entry that is not an action collection,
  /// sensory frame or observation, an entry the header's layout excludes, a
  /// missing end record, an entry count in the end record that disagrees
  /// with the entries read, or bytes after the end record. The reader must
  /// not be used after an exception.
  std::optional<RawlogEntry> next();

  /// The layout declared in the header.
  RawlogLayout layout() const noexcept { return layout_; }
  /// The format version of the file.
  std::uint16_t format_version() const noexcept { return format_version_; }
  /// The header's metadata.
  const RawlogMetadata& metadata() const noexcept { return metadata_; }
  /// Bytes consumed so far (decompressed).
  std::uint64_t offset() const;
  /// Entries returned so far.
  std::uint64_t entries_read() const noexcept { return entries_read_; }
  /// Entries of unknown classes passed over (skip_unknown_classes).
  std::uint64_t skipped_entries() const noexcept { return skipped_; }
  /// The file path (or the stream's name).
  const std::string& path() const noexcept { return path_; }

 private:
  void read_header();

  RoveRawlogReaderOptions options_;
  std::string path_;
  std::unique_ptr<InStream> stream_;
  std::unique_ptr<InArchive> archive_;
  RawlogLayout layout_ = RawlogLayout::Empty;
  std::uint16_t format_version_ = 0;
  RawlogMetadata metadata_;
  std::uint64_t entries_read_ = 0;
  std::uint64_t skipped_ = 0;
  bool done_ = false;
};

/// A rove rawlog in memory.
struct RoveRawlog {
  /// The entries in file order.
  std::vector<RawlogEntry> entries;
  /// The layout declared in the header.
  RawlogLayout layout = RawlogLayout::Empty;
  /// The header's metadata.
  RawlogMetadata metadata;
};

/// Reads a whole rove rawlog (see RoveRawlogReader for the errors).
RoveRawlog load_rove_rawlog(const std::string& path, RoveRawlogReaderOptions options = {});

/// Writes `entries` as a rove rawlog with the layout they follow
/// (layout_of; options.layout when there are none). Throws IoError on
/// failure.
void save_rove_rawlog(const std::string& path, const std::vector<RawlogEntry>& entries,
                      RoveRawlogWriterOptions options = {});

/// The layout a sequence of entries follows.
RawlogLayout layout_of(const std::vector<RawlogEntry>& entries);

}  // namespace rove
