#include "rove/poses/pose_io.h"

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

#include <fmt/format.h>

#include "rove/core/error.h"

namespace rove::detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
bool is_separator(char c) { return is_space(c) || c == ','; }

[[noreturn]] void fail(std::size_t offset, std::string_view field, std::string problem) {
  ParseError::Location where;
  where.source = "<string>";
  where.offset = offset;
  where.field = std::string(field);
  throw ParseError(std::move(where), std::move(problem));
}

}  // namespace

std::vector<double> parse_bracketed(std::string_view text,
                                    std::initializer_list<std::string_view> fields,
                                    std::string_view type_name) {
  const std::string_view first_field = fields.size() > 0 ? *fields.begin() : std::string_view();
  std::size_t begin = 0;
  std::size_t end = text.size();
  while (begin < end && is_space(text[begin])) ++begin;
  while (end > begin && is_space(text[end - 1])) --end;
  if (begin == end || text[begin] != '[') {
    fail(begin, first_field,
         fmt::format("{} string must start with '[' (expected \"[{}]\"), got \"{}\"", type_name,
                     fmt::join(fields, " "), text));
  }
  if (text[end - 1] != ']') {
    fail(end == 0 ? 0 : end - 1, first_field,
         fmt::format("{} string must end with ']', got \"{}\"", type_name, text));
  }
  const std::size_t body_end = end - 1;

  std::vector<double> values;
  values.reserve(fields.size());
  std::size_t pos = begin + 1;
  auto field_it = fields.begin();
  while (true) {
    while (pos < body_end && is_separator(text[pos])) ++pos;
    if (pos >= body_end) break;
    if (field_it == fields.end()) {
      fail(pos, *(fields.end() - 1),
           fmt::format("{} string has more than {} values: \"{}\"", type_name, fields.size(),
                       text));
    }
    const std::string_view field = *field_it;
    const char* first = text.data() + pos;
    const char* last = text.data() + body_end;
    if (*first == '+') ++first;  // from_chars does not accept a leading '+'
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (ec == std::errc::result_out_of_range) {
      fail(pos, field, fmt::format("{}: value of '{}' is out of range", type_name, field));
    }
    if (ec != std::errc() || ptr == first) {
      fail(pos, field, fmt::format("{}: value of '{}' is not a number in \"{}\"", type_name,
                                   field, text));
    }
    if (!std::isfinite(value)) {
      fail(pos, field, fmt::format("{}: value of '{}' is not finite", type_name, field));
    }
    std::size_t next = static_cast<std::size_t>(ptr - text.data());
    const bool is_angle_deg = field.size() >= 4 && field.substr(field.size() - 4) == "_deg";
    if (is_angle_deg && text.substr(next, 3) == "deg" && next + 3 <= body_end) next += 3;
    if (next < body_end && !is_separator(text[next])) {
      fail(next, field, fmt::format("{}: unexpected character '{}' after the value of '{}'",
                                    type_name, text[next], field));
    }
    values.push_back(value);
    ++field_it;
    pos = next;
  }
  if (field_it != fields.end()) {
    fail(pos, *field_it,
         fmt::format("{}: missing value for '{}' (expected {} values \"[{}]\"), got \"{}\"",
                     type_name, *field_it, fields.size(), fmt::join(fields, " "), text));
  }
  return values;
}

}  // namespace rove::detail
