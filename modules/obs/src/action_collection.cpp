#include "rove/obs/action_collection.h"

#include "rove/core/check.h"
#include "rove/obs/obs_registry.h"
#include "rove/serialization/object_io.h"

namespace rove {

void ActionCollection::add(std::shared_ptr<const Action> action) {
  ROVE_CHECK_MSG(action != nullptr, "ActionCollection::add: null action");
  actions.push_back(std::move(action));
}

bool operator==(const ActionCollection& a, const ActionCollection& b) {
  if (a.actions.size() != b.actions.size()) return false;
  for (std::size_t i = 0; i < a.actions.size(); ++i) {
    if (!a.actions[i]->equals(*b.actions[i])) return false;
  }
  return true;
}

void ActionCollection::save_payload(OutArchive& ar) const {
  ar.write_length(actions.size(), "ActionCollection actions");
  for (const auto& a : actions) {
    ROVE_CHECK_MSG(a != nullptr, "ActionCollection: null action cannot be saved");
    write_object(ar, *a);
  }
}

void ActionCollection::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  static const bool registered = (register_obs_classes(), true);
  (void)registered;
  const std::uint32_t n = ar.read_length("ActionCollection actions", 6);
  actions.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    actions.push_back(std::shared_ptr<const Action>(read_object_as<Action>(ar)));
  }
}

}  // namespace rove
