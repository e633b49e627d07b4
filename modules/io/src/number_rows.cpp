#include "number_rows.h"

#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove::detail {

namespace {

constexpr std::string_view kSpace = " \t\r";

/// The fields of a line, or nullopt for a blank or comment line.
std::optional<std::vector<std::string_view>> fields_of(std::string_view line) {
  const std::size_t first = line.find_first_not_of(kSpace);
  if (first == std::string_view::npos || line[first] == '#') return std::nullopt;
  std::vector<std::string_view> out;
  for (std::size_t i = first; i < line.size();) {
    const std::size_t end = std::min(line.find_first_of(kSpace, i), line.size());
    if (end > i) out.push_back(line.substr(i, end - i));
    i = end + 1;
  }
  return out;
}

template <class Fn>
void for_each_line(std::string_view text, Fn&& fn) {
  std::size_t line_no = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t eol = std::min(text.find('\n', pos), text.size());
    ++line_no;
    if (!fn(text.substr(pos, eol - pos), line_no)) return;
    pos = eol + 1;
  }
}

}  // namespace

void for_each_number_row(std::string_view text, std::string_view source,
                         std::span<const char* const> field_names,
                         const std::function<void(std::span<const double>, std::size_t)>& row) {
  std::vector<double> values(field_names.size());
  for_each_line(text, [&](std::string_view line, std::size_t line_no) {
    const auto fields = fields_of(line);
    if (!fields) return true;
    if (fields->size() != field_names.size()) {
      std::string names;
      for (const char* n : field_names) {
        if (!names.empty()) names += ' ';
        names += n;
      }
      throw ParseError({printable(source), line_no, std::nullopt, "row"},
                       fmt::format("{} fields, expected {} ({})", fields->size(),
                                   field_names.size(), names));
    }
    for (std::size_t k = 0; k < values.size(); ++k) {
      const std::string_view tok = (*fields)[k];
      const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), values[k]);
      if (r.ec != std::errc() || r.ptr != tok.data() + tok.size() || !std::isfinite(values[k]))
        throw ParseError({printable(source), line_no, std::nullopt, field_names[k]},
                         fmt::format("'{}' is not a finite number", printable(tok)));
    }
    row(values, line_no);
    return true;
  });
}

std::vector<std::string> first_row_fields(std::string_view text) {
  std::vector<std::string> out;
  for_each_line(text, [&](std::string_view line, std::size_t) {
    const auto fields = fields_of(line);
    if (!fields) return true;
    out.assign(fields->begin(), fields->end());
    return false;
  });
  return out;
}

}  // namespace rove::detail
