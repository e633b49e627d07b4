#pragma once
// Internal helpers shared by the INI preprocessor, parser and fuzz checks.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rove::detail {

/// True for the blanks SimpleIni trims around names and values.
inline bool ini_blank(char c) { return c == ' ' || c == '\t'; }

/// `s` without leading and trailing spaces and tabs.
std::string_view ini_trim(std::string_view s);

/// ASCII lower case, for case-insensitive lookup as SimpleIni's SI_NoCase.
std::string ini_lower(std::string_view s);

/// True if a trimmed line is a full-line comment (`#`, `;` or `//`).
bool ini_is_comment(std::string_view trimmed);

/// Position where a trailing comment starts in a trimmed value (`//`, `#`,
/// or `;` outside `[...]`, preceded by a space or tab; or `//` right after
/// a value that is a plain number, as in `0.10// meters`), or npos.
std::size_t ini_comment_start(std::string_view value);

/// The value rove's getters see: trimmed `value` cut at ini_comment_start,
/// then without `;`s that end it outside `[...]` (`1.5;` reads as 1.5, as
/// MRPT's atof does). Idempotent.
std::string ini_strip_value(std::string_view value);

/// MRPT's read_string view of a value: cut at the first `//` if it is
/// preceded by whitespace (CConfigFile::readString), then trimmed.
std::string ini_mrpt_raw(std::string_view value);

/// One logical line after joining continuations and preprocessing.
struct IniLine {
  std::string text;
  std::size_t line = 0;  // 1-based physical line where it starts
};

/// Joins continuation lines and applies `@define`, `${}`, `$env{}` and
/// `$eval{}` (see ini.h). Throws ParseError naming `source` and the line.
std::vector<IniLine> ini_preprocess(std::string_view text, const std::string& source);

}  // namespace rove::detail
