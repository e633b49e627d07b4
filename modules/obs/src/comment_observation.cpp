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

std::unique_ptr<Observation> CommentObservation::clone() const {
  return std::make_unique<CommentObservation>(*this);
}

bool CommentObservation::equals(const Observation& other) const {
  const auto* o = dynamic_cast<const CommentObservation*>(&other);
  return o != nullptr && *this == *o;
}

}  // namespace rove
