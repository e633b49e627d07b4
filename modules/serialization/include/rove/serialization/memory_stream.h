#pragma once
/// \file
/// Streams over bytes held in memory.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rove/serialization/stream.h"

namespace rove {

/// Reads from a byte buffer. The buffer is either borrowed (the span
/// constructor: the caller keeps it alive) or owned (the vector constructor).
class MemoryInStream final : public InStream {
 public:
  /// Reads the borrowed bytes `data`, which must outlive the stream.
  explicit MemoryInStream(std::span<const std::byte> data, std::string name = "<memory>");
  /// Reads bytes it owns.
  explicit MemoryInStream(std::vector<std::byte> data, std::string name = "<memory>");

  MemoryInStream(const MemoryInStream&) = delete;
  MemoryInStream& operator=(const MemoryInStream&) = delete;

  /// See InStream::read_some.
  std::size_t read_some(std::span<std::byte> out) override;
  /// See InStream::offset.
  std::uint64_t offset() const override { return pos_; }
  /// Always known for a memory buffer.
  std::optional<std::uint64_t> remaining() const override { return view_.size() - pos_; }
  /// See InStream::source_name.
  const std::string& source_name() const override { return name_; }

 private:
  std::vector<std::byte> owned_;
  std::span<const std::byte> view_;
  std::size_t pos_ = 0;
  std::string name_;
};

/// Appends written bytes to a growing buffer.
class MemoryOutStream final : public OutStream {
 public:
  /// An empty buffer named `name` in errors.
  explicit MemoryOutStream(std::string name = "<memory>");

  /// See OutStream::write.
  void write(std::span<const std::byte> bytes) override;
  /// See OutStream::offset.
  std::uint64_t offset() const override { return data_.size(); }
  /// Nothing to do for memory.
  void flush() override {}
  /// See OutStream::source_name.
  const std::string& source_name() const override { return name_; }

  /// The bytes written so far.
  const std::vector<std::byte>& data() const noexcept { return data_; }
  /// Moves the bytes out, leaving the stream empty.
  std::vector<std::byte> take() noexcept;

 private:
  std::vector<std::byte> data_;
  std::string name_;
};

}  // namespace rove
