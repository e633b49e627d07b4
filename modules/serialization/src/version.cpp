#include "rove/serialization/version.h"

#include <fmt/format.h>

namespace rove {

void write_version(OutArchive& ar, std::uint8_t version) { ar.write_scalar(version); }

std::uint8_t read_version(InArchive& ar, std::string_view type_name, std::uint8_t newest_known) {
  const std::uint64_t at = ar.offset();
  const auto v = ar.read_scalar<std::uint8_t>(type_name);
  if (v > newest_known) {
    ar.fail_at(at, type_name,
               fmt::format("{} version {} is newer than the newest this build reads ({})",
                           type_name, v, newest_known));
  }
  return v;
}

}  // namespace rove
