#pragma once
/// \file
/// Text support shared by the point and pose types: the fmt formatter that
/// prints a type exactly as its `operator<<` (MRPT's format), and the parser
/// of MRPT's bracketed string forms such as "[1 2 30]" used in config files.
///
/// The string form accepted by the `from_string` functions: optional
/// whitespace, '[', the values separated by whitespace and/or commas, ']',
/// optional whitespace. Values are decimal or scientific numbers; an angle
/// field given in degrees may carry a "deg" suffix ("30deg", as MRPT's
/// Pose2 as_string writes it). NaN or Inf is rejected.

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace rove::detail {

/// Formats a point or pose with `to_string(value)` (found by argument-dependent
/// lookup in namespace rove). Width/fill/alignment specs apply to the whole
/// text.
template <typename T>
struct ToStringFormatter : fmt::formatter<std::string_view> {
  template <typename FormatContext>
  auto format(const T& value, FormatContext& ctx) const {
    const std::string text = to_string(value);
    return fmt::formatter<std::string_view>::format(std::string_view(text), ctx);
  }
};

/// Parses MRPT's bracketed vector form of `type_name` (e.g. "Pose3") with one
/// value per entry of `fields`. A field whose name ends in "_deg" accepts a
/// "deg" suffix. Throws rove::ParseError (source "<string>", byte offset of the
/// problem, and the field name) on malformed text, a missing or extra value,
/// or a non-finite value.
std::vector<double> parse_bracketed(std::string_view text,
                                    std::initializer_list<std::string_view> fields,
                                    std::string_view type_name);

}  // namespace rove::detail
