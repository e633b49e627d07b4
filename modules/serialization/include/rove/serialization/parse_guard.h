#pragma once
/// \file
/// Turning a value a type rejects into a ParseError while loading: the
/// constructors and check() of rove's types throw InvalidArgument on bad
/// values; read from a file, the same value is bad input and must be
/// reported with the source, the byte offset and the field.

#include <cstdint>
#include <string_view>

#include "rove/core/error.h"
#include "rove/serialization/archive.h"

namespace rove {

/// Runs `f` and returns its result; an InvalidArgument it throws becomes a
/// ParseError of `ar` at byte offset `at` naming `field` ("invalid value:
/// <message>"). Other exceptions pass through unchanged.
template <typename F>
auto parse_guard(InArchive& ar, std::uint64_t at, std::string_view field, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InvalidArgument& e) {
    ar.fail_at(at, field, "invalid value: " + e.message());
  }
}

}  // namespace rove
