#pragma once
/// \file
/// Writing and reading polymorphic objects by class name.
///
/// Record layout: class name (u32 length + bytes, 1..255 bytes), version
/// (u8), the payload (Serializable::save_payload), end marker byte 0x88.

#include <cstdint>
#include <memory>

#include "rove/core/error.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/class_registry.h"
#include "rove/serialization/serializable.h"

namespace rove {

/// The byte closing every object record.
inline constexpr std::uint8_t kObjectEndMarker = 0x88;

/// Writes `obj` with its class name and version so read_object can rebuild it.
void write_object(OutArchive& ar, const Serializable& obj);

/// Reads one object written by write_object. Throws rove::ParseError naming
/// the class and the offset of the record when the class is not in
/// `registry`, when the stored version is newer than the class's version(),
/// when the payload does not end with the end marker, or when the data is
/// malformed.
std::unique_ptr<Serializable> read_object(InArchive& ar,
                                          const ClassRegistry& registry = ClassRegistry::global());

/// As read_object, and additionally requires the object to be a T (or derived
/// from T); throws rove::ParseError naming the class found otherwise.
template <typename T>
std::unique_ptr<T> read_object_as(InArchive& ar,
                                  const ClassRegistry& registry = ClassRegistry::global()) {
  const std::uint64_t at = ar.offset();
  std::unique_ptr<Serializable> obj = read_object(ar, registry);
  if (auto* p = dynamic_cast<T*>(obj.get())) {
    obj.release();
    return std::unique_ptr<T>(p);
  }
  ar.fail_at(at, obj->class_name(), "object is not of the expected type");
}

}  // namespace rove
