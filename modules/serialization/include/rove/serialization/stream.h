#pragma once
/// \file
/// The byte streams archives read from and write to. A stream moves exact
/// bytes and knows its byte offset and a name for error messages; it knows
/// nothing about the encoding of values (that is InArchive / OutArchive).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace rove {

/// A source of bytes read front to back.
///
/// Thread-safety: a stream object is not safe for concurrent use; distinct
/// objects are independent.
class InStream {
 public:
  virtual ~InStream() = default;

  /// Reads up to `out.size()` bytes into `out` and returns how many were read.
  /// Returns fewer than requested only at the end of the stream. Throws
  /// rove::IoError when the operating system reports a failure and
  /// rove::ParseError when compressed data is corrupt.
  virtual std::size_t read_some(std::span<std::byte> out) = 0;

  /// Bytes consumed so far (for compressed streams: in the decompressed data).
  virtual std::uint64_t offset() const = 0;

  /// Bytes left before the end, when the stream can tell without reading
  /// (memory buffers, plain files); std::nullopt for compressed streams.
  virtual std::optional<std::uint64_t> remaining() const = 0;

  /// The file path, or a description such as "<memory>", used in errors.
  virtual const std::string& source_name() const = 0;
};

/// A sink of bytes written front to back.
///
/// Thread-safety: as InStream.
class OutStream {
 public:
  virtual ~OutStream() = default;

  /// Writes all of `bytes`; throws rove::IoError if it cannot.
  virtual void write(std::span<const std::byte> bytes) = 0;

  /// Bytes written so far (for compressed streams: uncompressed bytes).
  virtual std::uint64_t offset() const = 0;

  /// Pushes buffered bytes to the operating system; throws rove::IoError.
  virtual void flush() = 0;

  /// The file path, or a description such as "<memory>", used in errors.
  virtual const std::string& source_name() const = 0;
};

}  // namespace rove
