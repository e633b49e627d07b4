#include "rove/core/ini.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>

#include "ini_text.h"
#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {

using detail::ini_blank;
using detail::ini_lower;
using detail::ini_trim;

// Builds an IniFile from preprocessed lines.
class IniBuilder {
 public:
  static IniFile build(std::string_view text, std::string source, const IniOptions& options) {
    IniFile ini;
    ini.source_ = std::move(source);
    const auto lines = detail::ini_preprocess(text, ini.source_);
    IniFile::Section* current = nullptr;
    for (const auto& l : lines) {
      const std::string_view t = ini_trim(l.text);
      if (t.empty() || detail::ini_is_comment(t)) continue;
      auto malformed = [&](const std::string& reason) {
        if (options.strict) throw ParseError({ini.source_, l.line, std::nullopt, {}}, reason);
        ini.skipped_.push_back({l.line, l.text, reason});
      };
      if (t.front() == '[') {
        const std::size_t close = t.find(']');
        if (close == std::string_view::npos) {
          malformed("unterminated section header (missing ']')");
          continue;
        }
        const std::string_view name = ini_trim(t.substr(1, close - 1));
        current = &ini.section_for_write(name);
        if (current->header_line != 0) {
          ini.duplicates_.push_back({true, std::string(name), {}, l.line, current->header_line});
        } else {
          current->header_line = l.line;
        }
        const std::string_view after = ini_trim(t.substr(close + 1));
        if (!after.empty() && !detail::ini_is_comment(after))
          malformed(fmt::format("unexpected text after section header: '{}'", after));
        continue;
      }
      const std::size_t eq = t.find('=');
      if (eq == std::string_view::npos) {
        malformed("expected 'key = value', '[section]' or a comment");
        continue;
      }
      const std::string_view key = ini_trim(t.substr(0, eq));
      if (key.empty()) {
        malformed("empty key before '='");
        continue;
      }
      const std::string_view value = ini_trim(t.substr(eq + 1));
      if (current == nullptr) current = &ini.section_for_write("");
      ini.put(*current, key, detail::ini_strip_value(value), detail::ini_mrpt_raw(value), l.line);
    }
    return ini;
  }
};

IniFile IniFile::parse(std::string_view text, std::string source_name, const IniOptions& options) {
  return IniBuilder::build(text, std::move(source_name), options);
}

IniFile IniFile::load(const std::string& path, const IniOptions& options) {
  return parse(read_input_file(path, kMaxTextInputBytes, "config file"), path, options);
}

IniFile::Section& IniFile::section_for_write(std::string_view section) {
  auto lower = ini_lower(section);
  if (auto it = section_index_.find(lower); it != section_index_.end()) return sections_[it->second];
  section_index_.emplace(std::move(lower), sections_.size());
  sections_.push_back(Section{std::string(section), {}, {}});
  return sections_.back();
}

void IniFile::put(Section& s, std::string_view key, std::string value, std::string raw,
                  std::size_t line) {
  auto lower = ini_lower(key);
  if (auto it = s.index.find(lower); it != s.index.end()) {
    Entry& e = s.entries[it->second];
    if (line != 0) duplicates_.push_back({false, s.name, std::string(key), line, e.line});
    e.value = std::move(value);
    e.raw = std::move(raw);
    e.line = line;
    return;
  }
  s.index.emplace(std::move(lower), s.entries.size());
  Entry e;
  e.key = std::string(key);
  e.value = std::move(value);
  e.raw = std::move(raw);
  e.line = line;
  s.entries.push_back(std::move(e));
}

const IniFile::Section* IniFile::find_section(std::string_view section) const {
  const auto it = section_index_.find(ini_lower(section));
  return it == section_index_.end() ? nullptr : &sections_[it->second];
}

const IniFile::Entry* IniFile::find(std::string_view section, std::string_view key) const {
  const Section* s = find_section(section);
  if (s == nullptr) return nullptr;
  const auto it = s->index.find(ini_lower(key));
  return it == s->index.end() ? nullptr : &s->entries[it->second];
}

void IniFile::fail(std::string_view section, std::string_view key, const std::string& problem) const {
  throw ConfigError(source_, std::string(section), std::string(key), problem);
}

const IniFile::Entry& IniFile::require(std::string_view section, std::string_view key) const {
  const Entry* e = find(section, key);
  if (e == nullptr) {
    fail(section, key,
         find_section(section) == nullptr ? fmt::format("missing key (no section [{}])", section)
                                          : std::string("missing key"));
  }
  e->read.store(true, std::memory_order_relaxed);
  return *e;
}

std::vector<std::string> IniFile::sections() const {
  std::vector<std::string> out;
  if (const Section* g = find_section(""); g != nullptr && !g->entries.empty()) out.push_back("");
  for (const auto& s : sections_) {
    if (!s.name.empty()) out.push_back(s.name);
  }
  return out;
}

bool IniFile::has_section(std::string_view section) const { return find_section(section) != nullptr; }

std::vector<std::string> IniFile::keys(std::string_view section) const {
  std::vector<std::string> out;
  if (const Section* s = find_section(section)) {
    for (const auto& e : s->entries) out.push_back(e.key);
  }
  return out;
}

bool IniFile::has(std::string_view section, std::string_view key) const {
  return find(section, key) != nullptr;
}

std::optional<std::size_t> IniFile::line(std::string_view section, std::string_view key) const {
  const Entry* e = find(section, key);
  if (e == nullptr) return std::nullopt;
  return e->line;
}

std::string IniFile::raw(std::string_view section, std::string_view key) const {
  return require(section, key).raw;
}

std::vector<std::string> IniFile::unread_keys(std::string_view section) const {
  std::vector<std::string> out;
  if (const Section* s = find_section(section)) {
    for (const auto& e : s->entries) {
      if (!e.read.load(std::memory_order_relaxed)) out.push_back(e.key);
    }
  }
  return out;
}

// ---------------------------------------------------------------- conversions

namespace {

template <typename T>
constexpr std::string_view type_name() {
  if constexpr (std::is_same_v<T, bool>) return "a boolean (true/false, yes/no, on/off, 1/0)";
  if constexpr (std::is_same_v<T, int>) return "an int";
  if constexpr (std::is_same_v<T, std::int64_t>) return "a 64-bit integer";
  if constexpr (std::is_same_v<T, unsigned>) return "an unsigned int";
  if constexpr (std::is_same_v<T, std::uint64_t>) return "an unsigned 64-bit integer";
  if constexpr (std::is_same_v<T, double>) return "a double";
  if constexpr (std::is_same_v<T, float>) return "a float";
  return "a string";
}

/// Converts a complete token; returns a problem description on failure.
template <typename T>
std::optional<std::string> convert(std::string_view text, T& out) {
  if constexpr (std::is_same_v<T, std::string>) {
    out = std::string(text);
    return std::nullopt;
  } else {
    const std::string quoted = fmt::format("'{}' is not {}", text, type_name<T>());
    if (text.empty()) return fmt::format("empty value is not {}", type_name<T>());
    if constexpr (std::is_same_v<T, bool>) {
      const std::string l = ini_lower(text);
      if (l == "true" || l == "yes" || l == "on" || l == "1") {
        out = true;
      } else if (l == "false" || l == "no" || l == "off" || l == "0") {
        out = false;
      } else {
        return quoted;
      }
      return std::nullopt;
    } else {
      // Optional sign, then decimal, or hexadecimal after "0x" (as MRPT's
      // strtod/strtoull readers accept, e.g. colors "0x00BFFF").
      std::string_view num = text;
      bool negative = false;
      if (num.size() > 1 && (num.front() == '+' || num.front() == '-')) {
        negative = num.front() == '-';
        num.remove_prefix(1);
        if (num.front() == '+' || num.front() == '-') return quoted;
      }
      const bool hex = num.size() > 2 && num[0] == '0' && (num[1] == 'x' || num[1] == 'X');
      if (hex) {
        num.remove_prefix(2);
        if (num.front() == '+' || num.front() == '-') return quoted;
      }
      T v{};
      std::from_chars_result r{};
      if constexpr (std::is_floating_point_v<T>) {
        r = std::from_chars(num.data(), num.data() + num.size(), v,
                            hex ? std::chars_format::hex : std::chars_format::general);
        if (negative) v = -v;
      } else if constexpr (std::is_signed_v<T>) {
        // Parse the magnitude unsigned so that the most negative value fits.
        std::uint64_t mag = 0;
        r = std::from_chars(num.data(), num.data() + num.size(), mag, hex ? 16 : 10);
        const auto max = static_cast<std::uint64_t>(std::numeric_limits<T>::max());
        if (r.ec == std::errc() && mag > max + (negative ? 1u : 0u)) r.ec = std::errc::result_out_of_range;
        if (r.ec == std::errc())
          v = negative ? static_cast<T>(-static_cast<T>(mag - 1) - 1) : static_cast<T>(mag);
      } else {
        if (negative) return fmt::format("'{}' is negative, expected {}", text, type_name<T>());
        r = std::from_chars(num.data(), num.data() + num.size(), v, hex ? 16 : 10);
      }
      if (r.ec == std::errc::result_out_of_range)
        return fmt::format("'{}' is out of range for {}", text, type_name<T>());
      if (r.ec != std::errc() || r.ptr != num.data() + num.size()) return quoted;
      if constexpr (std::is_floating_point_v<T>) {
        if (std::isnan(v)) return fmt::format("'{}' is not a number", text);
      }
      out = v;
      return std::nullopt;
    }
  }
}

/// Splits a vector body on spaces, tabs and commas (MRPT's tokenize on
/// "[], \t", with brackets allowed only around the whole value).
std::vector<std::string_view> split_elements(std::string_view body) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < body.size()) {
    while (i < body.size() && (ini_blank(body[i]) || body[i] == ',')) ++i;
    const std::size_t start = i;
    while (i < body.size() && !ini_blank(body[i]) && body[i] != ',') ++i;
    if (i > start) out.push_back(body.substr(start, i - start));
  }
  return out;
}

/// The text between an optional outer pair of brackets; a problem if the
/// brackets are unbalanced or nested.
std::optional<std::string> unbracket(std::string_view& v) {
  if (!v.empty() && v.front() == '[') {
    if (v.back() != ']' || v.size() < 2) return std::string("missing closing ']'");
    v = v.substr(1, v.size() - 2);
  }
  if (v.find_first_of("[]") != std::string_view::npos)
    return std::string("unexpected '[' or ']' inside the value");
  return std::nullopt;
}

}  // namespace

template <IniScalar T>
T IniFile::get(std::string_view section, std::string_view key) const {
  const Entry& e = require(section, key);
  T out{};
  if (auto problem = convert<T>(e.value, out)) fail(section, key, fmt::format("line {}: {}", e.line, *problem));
  return out;
}

template <IniScalar T>
T IniFile::get_or(std::string_view section, std::string_view key, const T& fallback) const {
  return has(section, key) ? get<T>(section, key) : fallback;
}

std::string IniFile::get_or(std::string_view section, std::string_view key,
                            const char* fallback) const {
  return get_or<std::string>(section, key, std::string(fallback));
}

template <IniScalar T>
std::vector<T> IniFile::get_vector(std::string_view section, std::string_view key) const {
  const Entry& e = require(section, key);
  std::string_view body = e.value;
  if (auto problem = unbracket(body)) fail(section, key, fmt::format("line {}: {}", e.line, *problem));
  std::vector<T> out;
  const auto tokens = split_elements(body);
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    T v{};
    if (auto problem = convert<T>(tokens[i], v))
      fail(section, key, fmt::format("line {}: element {}: {}", e.line, i, *problem));
    out.push_back(std::move(v));
  }
  return out;
}

template <IniScalar T>
std::vector<std::vector<T>> IniFile::get_matrix(std::string_view section,
                                                std::string_view key) const {
  const Entry& e = require(section, key);
  std::string_view body = e.value;
  if (auto problem = unbracket(body)) fail(section, key, fmt::format("line {}: {}", e.line, *problem));
  std::vector<std::vector<T>> rows;
  if (ini_trim(body).empty()) return rows;
  std::size_t start = 0;
  for (;;) {
    const std::size_t semi = body.find(';', start);
    const std::string_view row_text =
        body.substr(start, semi == std::string_view::npos ? std::string_view::npos : semi - start);
    const auto tokens = split_elements(row_text);
    if (tokens.empty()) fail(section, key, fmt::format("line {}: row {} is empty", e.line, rows.size()));
    std::vector<T> row;
    for (std::size_t c = 0; c < tokens.size(); ++c) {
      T v{};
      if (auto problem = convert<T>(tokens[c], v))
        fail(section, key,
             fmt::format("line {}: element ({}, {}): {}", e.line, rows.size(), c, *problem));
      row.push_back(std::move(v));
    }
    if (!rows.empty() && row.size() != rows.front().size())
      fail(section, key,
           fmt::format("line {}: row {} has {} elements, row 0 has {}", e.line, rows.size(),
                       row.size(), rows.front().size()));
    rows.push_back(std::move(row));
    if (semi == std::string_view::npos) break;
    start = semi + 1;
  }
  return rows;
}

std::size_t IniFile::choose(std::string_view section, std::string_view key,
                            const std::vector<std::string_view>& names,
                            const std::vector<std::int64_t>& values) const {
  const Entry& e = require(section, key);
  const auto words = split_elements(e.value);
  const std::string_view word = words.empty() ? std::string_view() : words.front();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == word) return i;
  }
  const std::string lower = ini_lower(word);
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (ini_lower(names[i]) == lower) return i;
  }
  std::int64_t number = 0;
  if (!convert<std::int64_t>(word, number)) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (values[i] == number) return i;
    }
  }
  std::string accepted;
  for (std::size_t i = 0; i < names.size(); ++i) {
    accepted += fmt::format("{}{} ({})", i == 0 ? "" : ", ", names[i], values[i]);
  }
  fail(section, key, fmt::format("line {}: '{}' is not one of: {}", e.line, word, accepted));
}

// ------------------------------------------------------------------ writing

namespace {

bool has_expansion(std::string_view s) {
  return s.find("${") != std::string_view::npos || s.find("$env{") != std::string_view::npos ||
         s.find("$eval{") != std::string_view::npos;
}

bool has_line_break(std::string_view s) { return s.find_first_of("\r\n") != std::string_view::npos || s.find('\0') != std::string_view::npos; }

/// Why `value` cannot be written and read back unchanged, if it cannot.
std::optional<std::string> unwritable_value(std::string_view v) {
  if (has_line_break(v)) return "contains a line break or NUL";
  if (ini_trim(v) != v) return "has leading or trailing spaces";
  if (detail::ini_strip_value(v) != v) return "contains a comment marker after a space or ends with ';'";
  if (has_expansion(v)) return "contains ${, $env{ or $eval{";
  if (!v.empty() && v.back() == '\\') return "ends with a backslash";
  return std::nullopt;
}

std::optional<std::string> unwritable_key(std::string_view k) {
  if (k.empty()) return "is empty";
  if (has_line_break(k)) return "contains a line break or NUL";
  if (ini_trim(k) != k) return "has leading or trailing spaces";
  if (k.find('=') != std::string_view::npos) return "contains '='";
  if (detail::ini_is_comment(k) || k.front() == '[' || k.starts_with("@define"))
    return "starts with a comment marker, '[' or '@define'";
  if (has_expansion(k)) return "contains ${, $env{ or $eval{";
  if (k.starts_with("\xEF\xBB\xBF")) return "starts with a byte order mark";
  return std::nullopt;
}

std::optional<std::string> unwritable_section(std::string_view s) {
  if (has_line_break(s)) return "contains a line break or NUL";
  if (ini_trim(s) != s) return "has leading or trailing spaces";
  if (s.find(']') != std::string_view::npos) return "contains ']'";
  if (has_expansion(s)) return "contains ${, $env{ or $eval{";
  return std::nullopt;
}

void check_writable(std::string_view section, std::string_view key, std::string_view value) {
  if (auto p = unwritable_section(section))
    ROVE_CHECK_MSG(false, "INI section name '{}' {}", section, *p);
  if (auto p = unwritable_key(key)) ROVE_CHECK_MSG(false, "INI key '{}' {}", key, *p);
  if (auto p = unwritable_value(value))
    ROVE_CHECK_MSG(false, "INI value '{}' of key '{}' {}", value, key, *p);
}

}  // namespace

void IniFile::set(std::string_view section, std::string_view key, std::string_view value) {
  check_writable(section, key, value);
  put(section_for_write(section), key, std::string(value), detail::ini_mrpt_raw(value), 0);
}

std::string IniFile::to_string() const {
  std::string out;
  auto write_section = [&](const Section& s) {
    for (const auto& e : s.entries) {
      check_writable(s.name, e.key, e.value);
      out += fmt::format("{} = {}\n", e.key, e.value);
    }
  };
  if (const Section* g = find_section("")) write_section(*g);
  for (const auto& s : sections_) {
    if (s.name.empty()) continue;
    check_writable(s.name, "k", "");
    out += fmt::format("{}[{}]\n", out.empty() ? "" : "\n", s.name);
    write_section(s);
  }
  return out;
}

#define ROVE_DETAIL_INI_INSTANTIATE(T)                                                          \
  template T IniFile::get<T>(std::string_view, std::string_view) const;                         \
  template T IniFile::get_or<T>(std::string_view, std::string_view, const T&) const;            \
  template std::vector<T> IniFile::get_vector<T>(std::string_view, std::string_view) const;     \
  template std::vector<std::vector<T>> IniFile::get_matrix<T>(std::string_view, std::string_view) \
      const;
ROVE_DETAIL_INI_INSTANTIATE(bool)
ROVE_DETAIL_INI_INSTANTIATE(int)
ROVE_DETAIL_INI_INSTANTIATE(std::int64_t)
ROVE_DETAIL_INI_INSTANTIATE(unsigned)
ROVE_DETAIL_INI_INSTANTIATE(std::uint64_t)
ROVE_DETAIL_INI_INSTANTIATE(double)
ROVE_DETAIL_INI_INSTANTIATE(float)
ROVE_DETAIL_INI_INSTANTIATE(std::string)
#undef ROVE_DETAIL_INI_INSTANTIATE

}  // namespace rove
