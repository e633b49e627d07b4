#pragma once
/// \file
/// gzip-compressed file streams (zlib). Offsets are counted in the
/// decompressed data: an error "at byte offset N" in a .gz file means the
/// N-th byte after decompression, not a position in the file on disk.

#include <cstdint>
#include <string>

#include "rove/serialization/stream.h"

namespace rove {

/// Reads a gzip file (one or more concatenated gzip members). A file that is
/// not gzip is read as it is. Corrupt or truncated compressed data raises
/// rove::ParseError (field "gzip") at the decompressed offset reached.
class GzipFileInStream final : public InStream {
 public:
  /// Opens `path`; throws rove::IoError with the path if it cannot.
  explicit GzipFileInStream(std::string path);
  ~GzipFileInStream() override;
  GzipFileInStream(const GzipFileInStream&) = delete;
  GzipFileInStream& operator=(const GzipFileInStream&) = delete;

  /// See InStream::read_some.
  std::size_t read_some(std::span<std::byte> out) override;
  /// Decompressed bytes consumed so far.
  std::uint64_t offset() const override { return pos_; }
  /// Unknown without decompressing: always std::nullopt.
  std::optional<std::uint64_t> remaining() const override { return std::nullopt; }
  /// The path given to the constructor.
  const std::string& source_name() const override { return path_; }

 private:
  std::string path_;
  void* file_ = nullptr;  // gzFile
  std::uint64_t pos_ = 0;
};

/// Writes a gzip file, truncating it if it exists.
class GzipFileOutStream final : public OutStream {
 public:
  /// Creates `path` compressed at `level` (1 = fastest .. 9 = smallest);
  /// throws rove::InvalidArgument for another level, rove::IoError if the
  /// file cannot be created.
  explicit GzipFileOutStream(std::string path, int level = 6);
  /// Closes the file; errors at this point are lost, so call close() to see them.
  ~GzipFileOutStream() override;
  GzipFileOutStream(const GzipFileOutStream&) = delete;
  GzipFileOutStream& operator=(const GzipFileOutStream&) = delete;

  /// See OutStream::write.
  void write(std::span<const std::byte> bytes) override;
  /// Uncompressed bytes written so far.
  std::uint64_t offset() const override { return pos_; }
  /// Flushes the compressor (a full flush: costs compression ratio).
  void flush() override;
  /// Finishes the gzip stream and closes the file, throwing rove::IoError on
  /// failure. Further writes throw rove::IoError.
  void close();
  /// The path given to the constructor.
  const std::string& source_name() const override { return path_; }

 private:
  std::string path_;
  void* file_ = nullptr;  // gzFile
  std::uint64_t pos_ = 0;
};

}  // namespace rove
