#pragma once
/// \file
/// SensoryFrame: observations taken together at (roughly) one robot pose
/// (MRPT's CSensoryFrame).

#include <cstddef>
#include <memory>
#include <string_view>
#include <vector>

#include "rove/obs/observation.h"
#include "rove/serialization/serializable.h"

namespace rove {

/// An ordered set of shared, immutable observations. Copies share the
/// observations (they are const). Thread-safety: thread-compatible.
class SensoryFrame final : public Serializable {
 public:
  /// Stored class name: "SensoryFrame".
  static constexpr std::string_view kClassName = "SensoryFrame";

  /// The observations, in insertion order; never null.
  std::vector<std::shared_ptr<const Observation>> observations;

  /// An empty frame.
  SensoryFrame() = default;

  /// Appends an observation. Throws InvalidArgument if it is null.
  void add(std::shared_ptr<const Observation> observation);
  /// Number of observations.
  std::size_t size() const noexcept { return observations.size(); }
  /// True if there are none.
  bool empty() const noexcept { return observations.empty(); }

  /// The `index`-th observation (0-based, in order) whose dynamic type is T
  /// (or derives from T), or nullptr.
  template <typename T>
  std::shared_ptr<const T> find(std::size_t index = 0) const {
    for (const auto& o : observations) {
      if (auto p = std::dynamic_pointer_cast<const T>(o)) {
        if (index == 0) return p;
        --index;
      }
    }
    return nullptr;
  }
  /// All observations of dynamic type T (or derived), in order.
  template <typename T>
  std::vector<std::shared_ptr<const T>> find_all() const {
    std::vector<std::shared_ptr<const T>> out;
    for (const auto& o : observations) {
      if (auto p = std::dynamic_pointer_cast<const T>(o)) out.push_back(std::move(p));
    }
    return out;
  }
  /// The first observation whose sensor_label equals `label` exactly, or
  /// nullptr.
  std::shared_ptr<const Observation> find_by_label(std::string_view label) const;
  /// The first observation of type T with that label, or nullptr.
  template <typename T>
  std::shared_ptr<const T> find_by_label(std::string_view label) const {
    for (const auto& o : observations) {
      if (o->sensor_label != label) continue;
      if (auto p = std::dynamic_pointer_cast<const T>(o)) return p;
    }
    return nullptr;
  }

  /// True if both hold equal observations (Observation::equals) in order.
  friend bool operator==(const SensoryFrame& a, const SensoryFrame& b);

  /// The stored class name (kClassName).
  std::string_view class_name() const override { return kClassName; }
  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the count and each observation with write_object.
  void save_payload(OutArchive& ar) const override;
  /// Reads observations with read_object_as<Observation> from the global
  /// ClassRegistry (register_obs_classes is called first).
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
