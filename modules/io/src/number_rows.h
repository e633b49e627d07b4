#pragma once
// Text files of rows of numbers (trajectories, relations): blank lines and
// `#` comments skipped, fields separated by spaces or tabs.

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rove::detail {

/// Calls `row(values, line_no)` for every data row of `text`, the values
/// parsed from exactly `field_names.size()` fields. Throws ParseError naming
/// `source`, the 1-based line and the field for another count of fields or a
/// value that is not a finite number.
void for_each_number_row(std::string_view text, std::string_view source,
                         std::span<const char* const> field_names,
                         const std::function<void(std::span<const double>, std::size_t)>& row);

/// The fields of the first data row (empty for none).
std::vector<std::string> first_row_fields(std::string_view text);

}  // namespace rove::detail
