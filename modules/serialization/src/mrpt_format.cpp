#include "rove/serialization/mrpt_format.h"

#include <fmt/format.h>

#include <string>

namespace rove {
namespace {
// MRPT refuses longer class names as a sign of a corrupt stream.
constexpr std::uint32_t kMrptMaxClassName = 120;
}  // namespace

MrptObjectHeader read_mrpt_object_header(InArchive& ar) {
  MrptObjectHeader h;
  h.offset = ar.offset();
  const auto first = ar.read_scalar<std::uint8_t>("MRPT object header");
  std::uint32_t len = first & 0x7Fu;
  if ((first & 0x80u) == 0) {
    // Pre-0.5.5 framing: the first byte is the low byte of a u32 length.
    h.old_format = true;
    std::byte rest[3];
    ar.read_bytes(rest, "MRPT object header");
    if (rest[0] != std::byte{0} || rest[1] != std::byte{0} || rest[2] != std::byte{0}) {
      ar.fail_at(h.offset, "MRPT object header",
                 "not an MRPT object header (old-style name length above 127; a compressed "
                 "stream read without decompression?)");
    }
  }
  if (len > kMrptMaxClassName) {
    ar.fail_at(h.offset, "MRPT object header",
               fmt::format("class name length {} exceeds {}", len, kMrptMaxClassName));
  }
  h.class_name.assign(len, '\0');
  ar.read_bytes(std::as_writable_bytes(std::span<char>(h.class_name.data(), len)),
                "MRPT class name");
  h.is_null = h.class_name == "nullptr";
  if (h.old_format) {
    const std::uint64_t at = ar.offset();
    const auto v = ar.read_scalar<std::int32_t>(h.class_name);
    if (v < 0 || v >= 255) {
      ar.fail_at(at, h.class_name, fmt::format("invalid old-style version {}", v));
    }
    h.version = static_cast<std::uint8_t>(v);
  } else if (!h.is_null) {
    h.version = ar.read_scalar<std::uint8_t>(h.class_name);
  }
  return h;
}

void expect_mrpt_end_marker(InArchive& ar, const MrptObjectHeader& header) {
  if (header.old_format) return;
  const std::uint64_t at = ar.offset();
  const auto marker = ar.read_scalar<std::uint8_t>(header.class_name);
  if (marker != kMrptEndMarker) {
    ar.fail_at(at, header.class_name,
               fmt::format("end marker 0x88 expected after '{}' version {} (object at offset {}), "
                           "found 0x{:02x}",
                           header.class_name, header.version, header.offset, marker));
  }
}

void throw_unknown_mrpt_version(const InArchive& ar, const MrptObjectHeader& header) {
  ar.fail_at(header.offset, header.class_name,
             fmt::format("unknown serialization version {} of MRPT class '{}'", header.version,
                         header.class_name));
}

bool read_mrpt_bool(InArchive& ar, std::string_view field) {
  return ar.read_scalar<std::uint8_t>(field) != 0;
}

std::string read_mrpt_string(InArchive& ar, std::string_view field) {
  const std::uint64_t at = ar.offset();
  const auto n = ar.read_scalar<std::uint32_t>(field);
  ar.check_length(n, 1, field, at);
  std::vector<std::uint8_t> bytes;
  ar.append_scalars(bytes, n, field);
  return std::string(bytes.begin(), bytes.end());
}

std::vector<std::string> read_mrpt_string_vector(InArchive& ar, std::string_view field) {
  const std::uint32_t n = ar.read_length(field, 4);
  std::vector<std::string> out;
  for (std::uint32_t i = 0; i < n; ++i) out.push_back(read_mrpt_string(ar, field));
  return out;
}

std::vector<bool> read_mrpt_bool_vector(InArchive& ar, std::string_view field) {
  const std::uint32_t n = ar.read_length(field, 1);
  std::vector<std::uint8_t> bytes;
  ar.append_scalars(bytes, n, field);
  std::vector<bool> out(bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) out[i] = bytes[i] != 0;
  return out;
}

std::uint32_t read_mrpt_container_preamble(InArchive& ar, std::string_view container,
                                           std::initializer_list<std::string_view> type_names,
                                           std::string_view field) {
  const std::uint64_t at = ar.offset();
  const std::string found = read_mrpt_string(ar, field);
  if (found != container) {
    ar.fail_at(at, field, fmt::format("expected container '{}', found '{}'", container, found));
  }
  for (const std::string_view t : type_names) {
    const std::uint64_t t_at = ar.offset();
    const std::string stored = read_mrpt_string(ar, field);
    if (stored != t) {
      ar.fail_at(t_at, field,
                 fmt::format("{} of '{}' expected, stored as '{}'", container, t, stored));
    }
  }
  return ar.read_length(field, 1);
}

}  // namespace rove
