#include "rove/obs/sensory_frame.h"

#include <string>

#include "rove/core/check.h"
#include "rove/obs/obs_registry.h"
#include "rove/serialization/object_io.h"

namespace rove {

void SensoryFrame::add(std::shared_ptr<const Observation> observation) {
  ROVE_CHECK_MSG(observation != nullptr, "SensoryFrame::add: null observation");
  observations.push_back(std::move(observation));
}

std::shared_ptr<const Observation> SensoryFrame::find_by_label(std::string_view label) const {
  for (const auto& o : observations) {
    if (o->sensor_label == label) return o;
  }
  return nullptr;
}

bool operator==(const SensoryFrame& a, const SensoryFrame& b) {
  if (a.observations.size() != b.observations.size()) return false;
  for (std::size_t i = 0; i < a.observations.size(); ++i) {
    if (!a.observations[i]->equals(*b.observations[i])) return false;
  }
  return true;
}

void SensoryFrame::save_payload(OutArchive& ar) const {
  ar.write_length(observations.size(), "SensoryFrame observations");
  for (const auto& o : observations) {
    ROVE_CHECK_MSG(o != nullptr, "SensoryFrame: null observation cannot be saved");
    write_object(ar, *o);
  }
}

void SensoryFrame::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  static const bool registered = (register_obs_classes(), true);
  (void)registered;
  // Each object record takes at least its name length, a version and the end marker.
  const std::uint32_t n = ar.read_length("SensoryFrame observations", 6);
  observations.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    observations.push_back(std::shared_ptr<const Observation>(read_object_as<Observation>(ar)));
  }
}

}  // namespace rove
