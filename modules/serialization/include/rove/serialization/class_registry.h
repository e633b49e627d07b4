#pragma once
/// \file
/// The map from stored class names to factories that read_object uses.

#include <concepts>
#include <functional>
#include <memory>
#include <shared_mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "rove/serialization/serializable.h"

namespace rove {

/// Class name → factory of default-constructed objects.
///
/// Thread-safety: every member may be called concurrently (a shared mutex
/// guards the map); registering while other threads read objects is safe.
class ClassRegistry {
 public:
  /// Makes an empty object of one class.
  using Factory = std::function<std::unique_ptr<Serializable>()>;

  /// The process-wide registry that Registrar fills and read_object uses by
  /// default. Constructed on first use, so static registrars in any
  /// translation unit may use it.
  static ClassRegistry& global();

  /// Registers `factory` under `name`. Registering the same name again
  /// replaces the factory only if `replace` is true; otherwise it throws
  /// rove::InvalidArgument. Names are 1..255 bytes.
  void add(std::string name, Factory factory, bool replace = false);

  /// Registers T under T().class_name().
  template <typename T>
    requires std::derived_from<T, Serializable> && std::default_initializable<T>
  void add(bool replace = false) {
    const T probe{};
    add(std::string(probe.class_name()), [] { return std::make_unique<T>(); }, replace);
  }

  /// A new object of class `name`, or nullptr if it is not registered.
  std::unique_ptr<Serializable> create(std::string_view name) const;

  /// Whether `name` is registered.
  bool contains(std::string_view name) const;

  /// The registered names, sorted.
  std::vector<std::string> names() const;

 private:
  struct Hash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const noexcept {
      return std::hash<std::string_view>{}(s);
    }
  };
  mutable std::shared_mutex mutex_;
  std::unordered_map<std::string, Factory, Hash, std::equal_to<>> factories_;
};

/// Registers T in ClassRegistry::global() when constructed; meant for a
/// namespace-scope static beside the class's implementation:
///
///   static const rove::Registrar<Odometry> kRegisterOdometry;
///
/// A static library drops translation units nothing references, and their
/// registrars with them: call ClassRegistry::global().add<T>() from an
/// initialization function instead when that matters.
template <typename T>
struct Registrar {
  /// Adds T (replacing nothing; a duplicate name throws at start-up).
  Registrar() { ClassRegistry::global().add<T>(); }
};

}  // namespace rove
