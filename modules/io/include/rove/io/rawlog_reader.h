#pragma once
/// \file
/// Reading MRPT rawlogs (plain or gzip) entry by entry, in both of MRPT's
/// layouts: #1 alternating CActionCollection / CSensoryFrame objects, #2 a
/// time-ordered stream of observations (odometry as CObservationOdometry).
/// Objects are read with read_mrpt_object (see mrpt_objects.h for the
/// supported classes and versions).
///
/// Objects of an unknown class cannot be skipped: MRPT records carry no
/// length, so the reader stops with a rove::ParseError naming the file, the
/// byte offset (in the decompressed data) and the class.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rove/obs/action_collection.h"
#include "rove/obs/observation.h"
#include "rove/obs/sensory_frame.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/stream.h"

namespace rove {

/// One top-level entry of a rawlog: an action collection or a sensory frame
/// (layout #1) or a single observation (layout #2). Never null.
using RawlogEntry =
    std::variant<std::shared_ptr<const ActionCollection>, std::shared_ptr<const SensoryFrame>,
                 std::shared_ptr<const Observation>>;

/// Options of RawlogReader.
struct RawlogReaderOptions {
  /// Bounds on declared lengths and nesting while reading untrusted data.
  ArchiveLimits limits;
};

/// Streams the entries of an MRPT rawlog one at a time; memory use does not
/// grow with the file. Gzip is detected from the file's first bytes.
///
/// Thread-safety: not safe for concurrent use; one reader per thread.
class RawlogReader {
 public:
  /// Opens `path`. Throws rove::IoError if it cannot be opened.
  explicit RawlogReader(const std::string& path, RawlogReaderOptions options = {});
  /// Reads from an already open stream (e.g. a MemoryInStream); path() is
  /// the stream's source name. Throws InvalidArgument if `stream` is null.
  explicit RawlogReader(std::unique_ptr<InStream> stream, RawlogReaderOptions options = {});
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  /// The next entry, or std::nullopt at the end of the file. Top-level null
  /// objects are passed over. Throws rove::ParseError (file, byte offset,
  /// class) on an unsupported class or version, on a top-level object that is
  /// none of the three entry kinds, and on truncated or malformed data; the
  /// reader must not be used after an exception.
  std::optional<RawlogEntry> next();

  /// Bytes consumed so far (decompressed bytes for gzip files).
  std::uint64_t offset() const;
  /// Entries returned so far.
  std::uint64_t entries_read() const noexcept { return entries_read_; }
  /// The file path.
  const std::string& path() const noexcept { return path_; }

 private:
  std::string path_;
  std::unique_ptr<InStream> stream_;
  std::unique_ptr<InArchive> archive_;
  std::uint64_t entries_read_ = 0;
};

/// Which of MRPT's layouts a whole rawlog uses.
enum class RawlogLayout : std::uint8_t {
  Empty = 0,                ///< no entries
  ActionsSensoryFrames = 1, ///< layout #1: action collections and sensory frames only
  Observations = 2,         ///< layout #2: observations only
  Mixed = 3,                ///< both kinds of entries
};

/// A whole rawlog in memory.
struct Rawlog {
  /// The entries in file order.
  std::vector<RawlogEntry> entries;
  /// The layout the entries follow.
  RawlogLayout layout = RawlogLayout::Empty;
};

/// Reads every entry of the rawlog at `path` (see RawlogReader::next for the
/// errors). Throws rove::IoError if the file cannot be opened.
Rawlog load_rawlog(const std::string& path, RawlogReaderOptions options = {});

}  // namespace rove
