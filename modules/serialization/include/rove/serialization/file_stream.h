#pragma once
/// \file
/// Uncompressed file streams (std::FILE underneath). Errors name the path.

#include <cstdint>
#include <cstdio>
#include <string>

#include "rove/serialization/stream.h"

namespace rove {

/// Reads a plain file. The file size is taken when opening, so remaining()
/// is known and hostile length fields can be rejected before allocating.
class FileInStream final : public InStream {
 public:
  /// Opens `path` for reading; throws rove::IoError with the path if it cannot.
  explicit FileInStream(std::string path);
  ~FileInStream() override;
  FileInStream(const FileInStream&) = delete;
  FileInStream& operator=(const FileInStream&) = delete;

  /// See InStream::read_some; throws rove::IoError on a read error.
  std::size_t read_some(std::span<std::byte> out) override;
  /// See InStream::offset.
  std::uint64_t offset() const override { return pos_; }
  /// File size at opening minus the bytes consumed.
  std::optional<std::uint64_t> remaining() const override;
  /// The path given to the constructor.
  const std::string& source_name() const override { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::uint64_t size_ = 0;
  std::uint64_t pos_ = 0;
};

/// Writes a plain file, truncating it if it exists.
class FileOutStream final : public OutStream {
 public:
  /// Creates or truncates `path`; throws rove::IoError with the path.
  explicit FileOutStream(std::string path);
  /// Closes the file; errors at this point are lost, so call close() to see them.
  ~FileOutStream() override;
  FileOutStream(const FileOutStream&) = delete;
  FileOutStream& operator=(const FileOutStream&) = delete;

  /// See OutStream::write.
  void write(std::span<const std::byte> bytes) override;
  /// See OutStream::offset.
  std::uint64_t offset() const override { return pos_; }
  /// See OutStream::flush.
  void flush() override;
  /// Flushes and closes the file, throwing rove::IoError on failure. Further
  /// writes throw rove::IoError.
  void close();
  /// The path given to the constructor.
  const std::string& source_name() const override { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::uint64_t pos_ = 0;
};

}  // namespace rove
