#pragma once
/// \file
/// One version number per record. A record's save writes its newest version
/// first; its load reads it, rejects versions newer than it knows, and
/// switches on the value so that every older layout stays readable:
///
///   void save(OutArchive& ar, const Odometry& o) {
///     write_version(ar, 2);
///     ar << o.pose << o.stamp;
///   }
///   void load(InArchive& ar, Odometry& o) {
///     const auto v = read_version(ar, "Odometry", 2);
///     ar >> o.pose;
///     if (v >= 2) ar >> o.stamp; else o.stamp = 0;
///   }

#include <cstdint>
#include <string_view>

#include "rove/serialization/archive.h"

namespace rove {

/// Writes a record's version (one byte).
void write_version(OutArchive& ar, std::uint8_t version);

/// Reads a record's version. Throws rove::ParseError naming `type_name`, the
/// version found and the byte offset if it is newer than `newest_known`.
std::uint8_t read_version(InArchive& ar, std::string_view type_name, std::uint8_t newest_known);

}  // namespace rove
