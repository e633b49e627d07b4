#pragma once
/// \file
/// Internal: the byte and line layers under CarmenLogReader. A byte source
/// (file or memory), optionally decompressed as bzip2, split into lines of
/// bounded length.

#include <bzlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rove::detail {

/// Raw bytes from a file or a memory buffer, read in chunks.
class CarmenRawSource {
 public:
  /// Opens `path`; throws IoError if it cannot be opened.
  static CarmenRawSource file(const std::string& path);
  /// Serves `bytes`.
  static CarmenRawSource memory(std::string bytes);
  CarmenRawSource(CarmenRawSource&& other) noexcept;
  CarmenRawSource& operator=(CarmenRawSource&&) = delete;
  CarmenRawSource(const CarmenRawSource&) = delete;
  ~CarmenRawSource();

  /// Copies up to `capacity` bytes into `out`; returns how many (0 at end).
  /// Throws IoError on a read failure; `name` is used in the message.
  std::size_t read(char* out, std::size_t capacity, const std::string& name);

 private:
  CarmenRawSource() = default;
  std::FILE* file_ = nullptr;
  std::string memory_;
  std::size_t memory_pos_ = 0;
};

/// Decompressed (or plain) bytes of a log, detecting bzip2 by its "BZh"
/// magic at the start.
class CarmenByteStream {
 public:
  CarmenByteStream(CarmenRawSource source, std::string name);
  CarmenByteStream(CarmenByteStream&&) = delete;
  ~CarmenByteStream();

  /// Fills `out` with the next bytes; returns how many (0 at end). Throws
  /// ParseError (offset into the compressed input, field "bzip2") on
  /// corrupt or truncated bzip2 data.
  std::size_t read(char* out, std::size_t capacity);
  /// True if the input was detected as bzip2.
  bool compressed() const noexcept { return compressed_; }

 private:
  bool refill_raw();
  [[noreturn]] void fail(const std::string& problem) const;

  CarmenRawSource source_;
  std::string name_;
  std::vector<char> raw_;
  std::size_t raw_begin_ = 0, raw_end_ = 0;
  std::uint64_t raw_consumed_ = 0;  // compressed bytes handed to bzip2
  bool raw_eof_ = false;
  bool compressed_ = false;
  bool bz_active_ = false;
  bool finished_ = false;
  bz_stream bz_{};
};

/// Splits a byte stream into lines ('\n', a trailing '\r' removed).
class CarmenLineReader {
 public:
  CarmenLineReader(CarmenRawSource source, std::string name, std::size_t max_line_bytes);

  /// Reads the next line into `line`. Returns false at end of input. Sets
  /// `too_long` if the line exceeded the limit (its bytes are discarded and
  /// `line` holds its first max_line_bytes bytes).
  bool next(std::string& line, bool& too_long);

 private:
  bool fill();
  CarmenByteStream bytes_;
  std::size_t max_line_bytes_;
  std::vector<char> buf_;
  std::size_t begin_ = 0, end_ = 0;
  bool eof_ = false;
};

}  // namespace rove::detail
