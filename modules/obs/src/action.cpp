#include "rove/obs/action.h"

#include "rove/serialization/version.h"

namespace rove {

void Action::save_header(OutArchive& ar) const {
  write_version(ar, 1);
  ar.write_scalar(timestamp.ns);
}

void Action::load_header(InArchive& ar) {
  read_version(ar, "Action header", 1);
  timestamp.ns = ar.read_scalar<std::int64_t>("timestamp");
}

}  // namespace rove
