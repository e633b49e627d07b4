#pragma once
/// \file
/// Binary archives: rove's on-disk encoding of values.
///
/// Encoding (fixed forever; tests pin it with frozen bytes):
///  - scalars: only fixed-size types (int8..int64, uint8..uint64, bool as
///    one byte 0/1, float and double as IEEE-754), little-endian on every host;
///  - std::string: u32 byte count, then the bytes;
///  - containers (stl.h), Eigen matrices (eigen.h): see those headers;
///  - user types: free functions `save(OutArchive&, const T&)` and
///    `load(InArchive&, T&)` beside the type, found by argument-dependent
///    lookup, starting with write_version / read_version (version.h).
///
/// Reading is defensive: running out of data, a length above the configured
/// cap or larger than what the stream can still hold all raise
/// rove::ParseError naming the source, the byte offset and the field, before
/// any large allocation is made.

#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "rove/serialization/stream.h"

namespace rove {

static_assert(std::numeric_limits<float>::is_iec559 && std::numeric_limits<double>::is_iec559,
              "rove archives need IEEE-754 float and double");
static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "mixed-endian hosts are not supported");

/// The scalar types archives encode directly: exactly the fixed-size integer
/// types, bool, float and double (no `char`, `long long`, `size_t` aliases
/// that differ between platforms).
template <typename T>
concept FixedScalar =
    std::same_as<T, bool> || std::same_as<T, std::int8_t> || std::same_as<T, std::uint8_t> ||
    std::same_as<T, std::int16_t> || std::same_as<T, std::uint16_t> ||
    std::same_as<T, std::int32_t> || std::same_as<T, std::uint32_t> ||
    std::same_as<T, std::int64_t> || std::same_as<T, std::uint64_t> ||
    std::same_as<T, float> || std::same_as<T, double>;

/// Bounds applied while reading untrusted data.
struct ArchiveLimits {
  /// Largest element count (or byte count for strings) one declared length
  /// may hold. Default 2^28.
  std::uint64_t max_length = std::uint64_t{1} << 28;
  /// Deepest nesting of objects inside objects (read_object, MRPT readers);
  /// bounds recursion on hostile input. Default 64.
  std::uint32_t max_nesting = 64;
};

/// Writes values to an OutStream in rove's encoding.
///
/// Thread-safety: not safe for concurrent use; one archive per thread.
class OutArchive {
 public:
  /// Writes to `stream`, which must outlive the archive.
  explicit OutArchive(OutStream& stream) : stream_(stream) {}

  /// Writes one scalar, little-endian.
  template <FixedScalar T>
  void write_scalar(T value) {
    std::byte buf[sizeof(T)];
    encode(value, buf);
    stream_.write(buf);
  }

  /// Writes scalars back to back, little-endian.
  template <FixedScalar T>
  void write_scalars(std::span<const T> values) {
    if constexpr (std::endian::native == std::endian::little && !std::same_as<T, bool>) {
      stream_.write(std::as_bytes(values));
    } else {
      for (const T& v : values) write_scalar(v);
    }
  }

  /// Writes raw bytes.
  void write_bytes(std::span<const std::byte> bytes) { stream_.write(bytes); }

  /// Writes an element or byte count as u32. Throws rove::InvalidArgument if
  /// `n` does not fit in 32 bits (`field` names what was being written).
  void write_length(std::size_t n, std::string_view field);

  /// Bytes written to the stream so far.
  std::uint64_t offset() const { return stream_.offset(); }
  /// The underlying stream.
  OutStream& stream() noexcept { return stream_; }

  /// Little-endian bytes of `value` into `out` (sizeof(T) bytes).
  template <FixedScalar T>
  static void encode(T value, std::byte* out) {
    if constexpr (std::same_as<T, bool>) {
      out[0] = value ? std::byte{1} : std::byte{0};
    } else {
      using U = std::make_unsigned_t<
          std::conditional_t<std::is_floating_point_v<T>,
                             std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>, T>>;
      const U bits = std::bit_cast<U>(value);
      for (std::size_t i = 0; i < sizeof(T); ++i) {
        out[i] = static_cast<std::byte>((bits >> (8 * i)) & 0xFFu);
      }
    }
  }

 private:
  OutStream& stream_;
};

/// Reads values in rove's encoding from an InStream, defensively.
///
/// Thread-safety: not safe for concurrent use; one archive per thread.
class InArchive {
 public:
  /// Reads from `stream`, which must outlive the archive.
  explicit InArchive(InStream& stream, ArchiveLimits limits = {})
      : stream_(stream), limits_(limits) {}

  /// Reads one little-endian scalar. A bool byte other than 0 or 1 is a
  /// ParseError. `field` names the value in errors.
  template <FixedScalar T>
  T read_scalar(std::string_view field = {}) {
    std::byte buf[sizeof(T)];
    read_bytes(buf, field);
    if constexpr (std::same_as<T, bool>) {
      if (buf[0] != std::byte{0} && buf[0] != std::byte{1}) {
        fail_at(offset() - 1, field,
                "a bool must be stored as 0 or 1, found " +
                    std::to_string(std::to_integer<unsigned>(buf[0])));
      }
    }
    return decode<T>(buf);
  }

  /// Reads `out.size()` little-endian scalars.
  template <FixedScalar T>
  void read_scalars(std::span<T> out, std::string_view field = {}) {
    if constexpr (std::endian::native == std::endian::little && !std::same_as<T, bool>) {
      read_bytes(std::as_writable_bytes(out), field);
    } else {
      for (T& v : out) v = read_scalar<T>(field);
    }
  }

  /// Appends `n` scalars to `out`, growing it chunk by chunk so that a length
  /// no data backs never causes a large allocation.
  template <FixedScalar T>
  void append_scalars(std::vector<T>& out, std::uint64_t n, std::string_view field = {}) {
    constexpr std::uint64_t kChunk = 65536;
    while (n > 0) {
      const std::size_t k = static_cast<std::size_t>(n < kChunk ? n : kChunk);
      const std::size_t old = out.size();
      out.resize(old + k);
      read_scalars(std::span<T>(out.data() + old, k), field);
      n -= k;
    }
  }

  /// Reads exactly `out.size()` bytes; ParseError (offset where the read
  /// started, `field`) if the stream ends first.
  void read_bytes(std::span<std::byte> out, std::string_view field = {});

  /// Reads a u32 element count and validates it with check_length.
  std::uint32_t read_length(std::string_view field, std::uint64_t min_bytes_per_element);

  /// Validates a count `n` read at `at_offset`: ParseError if it exceeds
  /// limits().max_length, or if `n * min_bytes_per_element` exceeds the bytes
  /// the stream can still hold (when it can tell, see InStream::remaining).
  void check_length(std::uint64_t n, std::uint64_t min_bytes_per_element, std::string_view field,
                    std::uint64_t at_offset) const;

  /// True when no byte is left. May read one byte ahead (kept for the next read).
  bool at_end();

  /// Bytes consumed so far (decompressed bytes for gzip streams).
  std::uint64_t offset() const { return stream_.offset() - (has_pending_ ? 1 : 0); }
  /// Bytes left if the stream can tell, see InStream::remaining.
  std::optional<std::uint64_t> remaining() const;
  /// The stream's name for errors.
  const std::string& source_name() const { return stream_.source_name(); }
  /// The limits in force.
  const ArchiveLimits& limits() const noexcept { return limits_; }

  /// Throws ParseError at the current offset, naming `field`.
  [[noreturn]] void fail(std::string_view field, std::string problem) const;
  /// Throws ParseError at `at_offset`, naming `field`.
  [[noreturn]] void fail_at(std::uint64_t at_offset, std::string_view field,
                            std::string problem) const;

  /// Counts one level of object nesting for its lifetime; throws ParseError
  /// (naming `field`) when limits().max_nesting would be exceeded.
  class NestingGuard {
   public:
    /// Enters one level.
    NestingGuard(InArchive& ar, std::string_view field);
    /// Leaves the level.
    ~NestingGuard() { --ar_.depth_; }
    NestingGuard(const NestingGuard&) = delete;
    NestingGuard& operator=(const NestingGuard&) = delete;

   private:
    InArchive& ar_;
  };

  /// The scalar whose little-endian bytes are `in` (sizeof(T) bytes).
  template <FixedScalar T>
  static T decode(const std::byte* in) {
    if constexpr (std::same_as<T, bool>) {
      return in[0] != std::byte{0};
    } else {
      using U = std::make_unsigned_t<
          std::conditional_t<std::is_floating_point_v<T>,
                             std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>, T>>;
      U bits = 0;
      for (std::size_t i = 0; i < sizeof(T); ++i) {
        bits = static_cast<U>(bits | (static_cast<U>(std::to_integer<unsigned>(in[i])) << (8 * i)));
      }
      return std::bit_cast<T>(bits);
    }
  }

 private:
  InStream& stream_;
  ArchiveLimits limits_;
  bool has_pending_ = false;
  std::byte pending_{};
  std::uint32_t depth_ = 0;
};

/// The fewest bytes one serialized T can take; used to reject element counts
/// the remaining data cannot hold. 1 for user types (their record starts with
/// a version byte); specialize for a user type that may encode to 0 bytes.
template <typename T>
struct SerializedMinSize {
  /// Lower bound on the encoded size, in bytes.
  static constexpr std::uint64_t value = 1;
};
/// A scalar takes its own size.
template <FixedScalar T>
struct SerializedMinSize<T> {
  /// sizeof(T).
  static constexpr std::uint64_t value = sizeof(T);
};
/// A string takes at least its u32 length.
template <>
struct SerializedMinSize<std::string> {
  /// The u32 length.
  static constexpr std::uint64_t value = 4;
};

/// Writes a scalar (see FixedScalar).
template <FixedScalar T>
void save(OutArchive& ar, const T& value) {
  ar.write_scalar(value);
}
/// Reads a scalar (see FixedScalar).
template <FixedScalar T>
void load(InArchive& ar, T& value) {
  value = ar.read_scalar<T>();
}

/// Writes a string: u32 byte count, then the bytes.
void save(OutArchive& ar, const std::string& value);
/// Reads a string written by save.
void load(InArchive& ar, std::string& value);

/// A type with save/load reachable by argument-dependent lookup.
template <typename T>
concept Archivable = requires(OutArchive& out, InArchive& in, const T& c, T& m) {
  save(out, c);
  load(in, m);
};

/// `ar << value` is `save(ar, value)`.
template <typename T>
OutArchive& operator<<(OutArchive& ar, const T& value) {
  save(ar, value);
  return ar;
}
/// `ar >> value` is `load(ar, value)`.
template <typename T>
InArchive& operator>>(InArchive& ar, T& value) {
  load(ar, value);
  return ar;
}

}  // namespace rove
