#pragma once
/// \file
/// The interface of types written polymorphically (write_object /
/// read_object in object_io.h): types chosen at run time, such as the
/// observations in a rawlog. Plain value types use free save/load instead.

#include <cstdint>
#include <string_view>

#include "rove/serialization/archive.h"

namespace rove {

/// A type that can be written and read back without the reader knowing it
/// in advance. Implementations must be default-constructible to be
/// registered (ClassRegistry::add<T>).
class Serializable {
 public:
  virtual ~Serializable() = default;

  /// The name stored in archives; unique among registered classes and stable
  /// forever (renaming a class breaks old files). At most 255 bytes.
  virtual std::string_view class_name() const = 0;

  /// The version save_payload writes (the newest this build knows).
  virtual std::uint8_t version() const = 0;

  /// Writes the object's data (without name or version).
  virtual void save_payload(OutArchive& ar) const = 0;

  /// Reads data written by save_payload of `version` (never newer than
  /// version(): read_object rejects those before calling).
  virtual void load_payload(InArchive& ar, std::uint8_t version) = 0;

 protected:
  Serializable() = default;
  Serializable(const Serializable&) = default;
  Serializable& operator=(const Serializable&) = default;
};

}  // namespace rove
