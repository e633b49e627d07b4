#include "rove/serialization/object_io.h"

#include <fmt/format.h>

#include <string>

#include "rove/core/check.h"

namespace rove {
namespace {
constexpr std::uint32_t kMaxClassName = 255;
}  // namespace

void write_object(OutArchive& ar, const Serializable& obj) {
  const std::string_view name = obj.class_name();
  ROVE_CHECK_MSG(!name.empty() && name.size() <= kMaxClassName,
                 "class names are 1..255 bytes, got {} bytes", name.size());
  ar.write_scalar(static_cast<std::uint32_t>(name.size()));
  ar.write_bytes(std::as_bytes(std::span<const char>(name.data(), name.size())));
  ar.write_scalar(obj.version());
  obj.save_payload(ar);
  ar.write_scalar(kObjectEndMarker);
}

std::unique_ptr<Serializable> read_object(InArchive& ar, const ClassRegistry& registry) {
  const std::uint64_t start = ar.offset();
  const InArchive::NestingGuard nesting(ar, "object");
  const auto len = ar.read_scalar<std::uint32_t>("class name length");
  if (len == 0 || len > kMaxClassName) {
    ar.fail_at(start, "class name length",
               fmt::format("class name length {} is outside 1..{}", len, kMaxClassName));
  }
  std::string name(len, '\0');
  ar.read_bytes(std::as_writable_bytes(std::span<char>(name.data(), name.size())), "class name");
  std::unique_ptr<Serializable> obj = registry.create(name);
  if (!obj) ar.fail_at(start, name, fmt::format("unknown class '{}'", name));

  const std::uint64_t version_at = ar.offset();
  const auto version = ar.read_scalar<std::uint8_t>(name);
  if (version > obj->version()) {
    ar.fail_at(version_at, name,
               fmt::format("{} version {} is newer than the newest this build reads ({})", name,
                           version, obj->version()));
  }
  obj->load_payload(ar, version);
  const std::uint64_t end_at = ar.offset();
  const auto marker = ar.read_scalar<std::uint8_t>(name);
  if (marker != kObjectEndMarker) {
    ar.fail_at(end_at, name,
               fmt::format("end marker 0x{:02x} expected after the payload of '{}' (record at "
                           "offset {}), found 0x{:02x}",
                           kObjectEndMarker, name, start, marker));
  }
  return obj;
}

}  // namespace rove
