#include "rove/obs/comment_observation.h"

#include "rove/serialization/stl.h"

namespace rove {

bool operator==(const CommentObservation& a, const CommentObservation& b) {
  return a.header_equals(b) && a.text == b.text;
}

void CommentObservation::save_payload(OutArchive& ar) const {
  save_header(ar);
  save(ar, text);
}

void CommentObservation::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  load(ar, text);
}

}  // namespace rove
