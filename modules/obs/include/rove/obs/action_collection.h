#pragma once
/// \file
/// ActionCollection: the actions between two sensory frames (MRPT's
/// CActionCollection), in a rawlog of MRPT's "format #1".

#include <cstddef>
#include <memory>
#include <string_view>
#include <vector>

#include "rove/obs/action.h"
#include "rove/serialization/serializable.h"

namespace rove {

/// An ordered set of shared, immutable actions. Thread-compatible.
class ActionCollection final : public Serializable {
 public:
  /// Stored class name: "ActionCollection".
  static constexpr std::string_view kClassName = "ActionCollection";

  /// The actions, in insertion order; never null.
  std::vector<std::shared_ptr<const Action>> actions;

  /// An empty collection.
  ActionCollection() = default;

  /// Appends an action. Throws InvalidArgument if it is null.
  void add(std::shared_ptr<const Action> action);
  /// Number of actions.
  std::size_t size() const noexcept { return actions.size(); }
  /// True if there are none.
  bool empty() const noexcept { return actions.empty(); }

  /// The `index`-th action of dynamic type T (or derived), or nullptr.
  template <typename T>
  std::shared_ptr<const T> find(std::size_t index = 0) const {
    for (const auto& a : actions) {
      if (auto p = std::dynamic_pointer_cast<const T>(a)) {
        if (index == 0) return p;
        --index;
      }
    }
    return nullptr;
  }

  /// True if both hold equal actions (Action::equals) in order.
  friend bool operator==(const ActionCollection& a, const ActionCollection& b);

  /// The stored class name (kClassName).
  std::string_view class_name() const override { return kClassName; }
  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the count and each action with write_object.
  void save_payload(OutArchive& ar) const override;
  /// Reads actions with read_object_as<Action> from the global registry
  /// (register_obs_classes is called first).
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
