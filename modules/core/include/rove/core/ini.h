#pragma once
/// \file
/// Reader (and writer) for MRPT-style INI configuration files, compatible
/// with the files MRPT's CConfigFile loads (MRPT 2.x: SimpleIni plus
/// mrpt::config::config_parser). The rules, in the order they apply:
///
/// 1. Preprocessing, per logical line (as MRPT's config_parser):
///    - a backslash immediately before a line break joins the next line
///      (backslash and line break are removed, nothing is inserted);
///    - `@define NAME value` at the start of a line defines NAME;
///    - `${NAME}` is replaced by the value of a defined NAME (unknown names
///      are an error), `$env{VAR}` by the environment variable VAR (empty if
///      unset), `$eval{expr}` by the arithmetic value of expr (see
///      rove/core/arith_expr.h; defined names are its variables) printed as
///      printf's `%e`, e.g. `6.283185e+00`.
///    Full-line comments are left alone (see "Differences from MRPT").
/// 2. Lines: `[section]`, `key = value`, blank lines, and full-line comments
///    starting with `#`, `;` or `//` (after optional whitespace). Keys before
///    the first section belong to the section named "" (MRPT's global
///    section); `[]` also names it. Section and key names are trimmed and
///    compared case-insensitively (ASCII); the spelling of their first
///    appearance is kept. A section that appears twice is merged; a key that
///    appears twice keeps its first position and its last value (as MRPT).
/// 3. Values are trimmed. A trailing comment is cut off where `//`, `#`, or
///    `;` follows a space or tab, and where `//` directly follows a value
///    that is a plain number (`0.10// meters`, as in MRPT's own files); a `;`
///    inside `[...]` is kept (it separates matrix rows). So
///    `x = 0.05 # cell size` reads 0.05 and `M = [1 2; 3 4]` keeps its `;`. Then `;`s ending the value outside
///    `[...]` are dropped (`d = 1.5;` reads 1.5, as MRPT's atof does).
///    raw() returns the value exactly as MRPT's read_string would.
///
/// Typed reads are strict: `get<double>` of "abc", "1.5x", "nan" or "1e999"
/// throws rove::ConfigError naming file, section, key and line. Numbers are
/// decimal with an optional sign, or hexadecimal after `0x` (`0x00BFFF`);
/// `inf` is accepted for floating point. Booleans accept true/false, yes/no,
/// on/off, 1/0 in any case.
///
/// Differences from MRPT (each turns a silent misreading into an error or a
/// clearer result): in strict mode (the default) lines MRPT silently skips
/// (no `=`, empty key, unterminated `[section`, text after `]`) are a
/// ParseError; IniOptions::strict = false skips them like MRPT and lists them
/// in skipped_lines(). Lines starting with `//` are comments (SimpleIni
/// makes a line `// a = b` a key named "// a"). `on`/`off` are booleans
/// (MRPT reads `on` as false).
/// `@define`, `${}`, `$env{}`, `$eval{}` inside full-line comments are not
/// processed (MRPT processes them, so a commented-out `@define` still
/// defines). `@define` values are expanded when defined. `$eval` of a name
/// whose value is not a number is an error (MRPT uses 0). MRPT 2.x has no
/// `@include`, and neither has rove.
///
/// Thread-safety: const member functions may be called concurrently
/// (read tracking uses atomics); set() needs exclusive access.

#include <atomic>
#include <concepts>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace rove {

/// The value types IniFile's typed getters support.
template <typename T>
concept IniScalar =
    std::same_as<T, bool> || std::same_as<T, int> || std::same_as<T, std::int64_t> ||
    std::same_as<T, unsigned> || std::same_as<T, std::uint64_t> || std::same_as<T, double> ||
    std::same_as<T, float> || std::same_as<T, std::string>;

/// How IniFile::parse treats input.
struct IniOptions {
  /// true: a line MRPT would silently skip is a ParseError. false: skip it
  /// as MRPT does and record it in IniFile::skipped_lines().
  bool strict = true;
};

/// A line that a non-strict parse skipped.
struct IniSkippedLine {
  std::size_t line = 0;  ///< 1-based line in the source
  std::string text;      ///< the line after preprocessing
  std::string reason;    ///< why it is not a section or key line
};

/// A section header or a key that appears more than once (MRPT merges the
/// section and keeps the key's last value; so does IniFile).
struct IniDuplicate {
  bool is_section = false;  ///< true: a repeated `[section]` header; false: a repeated key
  std::string section;      ///< the section (its spelling at this line)
  std::string key;          ///< the key (empty for a section)
  std::size_t line = 0;     ///< 1-based line of this repetition
  std::size_t first_line = 0;  ///< 1-based line of the previous appearance
};

/// One name of an enumeration and its value, for IniFile::get_enum.
template <typename E>
struct IniEnumName {
  std::string_view name;
  E value;
};

/// An MRPT-style INI document: sections of key/value strings with typed,
/// strict getters and tracking of which keys were read.
class IniFile {
 public:
  /// An empty document (no sections).
  IniFile() = default;

  /// Reads and parses the file at `path`: a regular file (a directory, a
  /// device or a FIFO is refused) of at most kMaxTextInputBytes
  /// (rove/core/files.h). Throws IoError naming the path if it cannot be
  /// read, ParseError (path, line) if it is malformed.
  static IniFile load(const std::string& path, const IniOptions& options = {});
  /// Parses `text`; `source_name` names it in errors (e.g. a path).
  /// Throws ParseError (source_name, line) if malformed.
  static IniFile parse(std::string_view text, std::string source_name = "<string>",
                       const IniOptions& options = {});

  /// The file path or source name given to load()/parse().
  const std::string& source() const noexcept { return source_; }
  /// Section names in order of first appearance ("" first if it has keys).
  std::vector<std::string> sections() const;
  /// True if the section exists (case-insensitive).
  bool has_section(std::string_view section) const;
  /// Key names of a section in order of first appearance; empty if the
  /// section does not exist.
  std::vector<std::string> keys(std::string_view section) const;
  /// True if the key exists in the section (case-insensitive). Does not
  /// count as a read.
  bool has(std::string_view section, std::string_view key) const;
  /// 1-based source line of the key's last definition (0 if added by set()),
  /// if the key exists.
  std::optional<std::size_t> line(std::string_view section, std::string_view key) const;

  /// The value converted to T. Throws ConfigError (file, section, key) if the
  /// key is missing or its value is not a complete, in-range T.
  template <IniScalar T>
  T get(std::string_view section, std::string_view key) const;
  /// As get(), but returns `fallback` if the key is missing. A present but
  /// malformed value still throws.
  template <IniScalar T>
  T get_or(std::string_view section, std::string_view key, const T& fallback) const;
  /// get_or for string literals.
  std::string get_or(std::string_view section, std::string_view key, const char* fallback) const;
  /// A vector written as `[a b c]`, `[a, b, c]` or `a b c` (MRPT's
  /// read_vector); an empty value gives an empty vector. Throws ConfigError
  /// if missing or if any element is malformed.
  template <IniScalar T>
  std::vector<T> get_vector(std::string_view section, std::string_view key) const;
  /// A matrix written MATLAB-style as MRPT's read_matrix: `[1 2 3; 4 5 6]`,
  /// rows separated by `;`, elements by spaces or commas; returned as rows.
  /// `[]` gives no rows. Throws ConfigError if missing, malformed or ragged.
  template <IniScalar T>
  std::vector<std::vector<T>> get_matrix(std::string_view section, std::string_view key) const;
  /// An enumeration value named by the first word of the value, matched
  /// against `names` exactly, then case-insensitively; an integer is accepted
  /// if it equals the underlying value of one of `names` (MRPT's read_enum).
  /// Throws ConfigError listing the accepted names otherwise.
  template <typename E>
    requires std::is_enum_v<E>
  E get_enum(std::string_view section, std::string_view key,
             std::initializer_list<IniEnumName<E>> names) const;

  /// The value as MRPT's read_string returns it (only MRPT's comment rule
  /// applied: text from the first `//` is cut if a space precedes it).
  /// Throws ConfigError if missing. Counts as a read.
  std::string raw(std::string_view section, std::string_view key) const;

  /// Keys of `section` that no getter (get, get_or, get_vector, get_matrix,
  /// get_enum, raw) has read yet, in file order: the unknown or unused keys a
  /// caller should report.
  std::vector<std::string> unread_keys(std::string_view section) const;

  /// Sets (or adds) a key. Precondition (InvalidArgument): section and key
  /// are single-line without `]`/`=` and surrounding spaces, the key is not
  /// empty and does not start with a comment marker, `[` or `@define`; the value
  /// is a single line that to_string() can write and parse() read back
  /// unchanged (no surrounding spaces, no comment marker after a space, no
  /// final `;` outside brackets, no `${`/`$env{`/`$eval{`, no final
  /// backslash).
  void set(std::string_view section, std::string_view key, std::string_view value);

  /// The document as INI text that parse() reads back to the same sections,
  /// keys and values (comments, `@define`s and raw() text are not kept).
  /// Throws InvalidArgument if a parsed value cannot be written back that
  /// way (e.g. it came from `$env{}` and contains `${`).
  std::string to_string() const;

  /// Lines a non-strict parse skipped (always empty after a strict parse).
  const std::vector<IniSkippedLine>& skipped_lines() const noexcept { return skipped_; }

  /// Repeated section headers and keys, in file order (set() records none).
  const std::vector<IniDuplicate>& duplicates() const noexcept { return duplicates_; }

 private:
  struct Entry {
    std::string key;
    std::string value;  // comments cut, trimmed
    std::string raw;    // MRPT's read_string view
    std::size_t line = 0;
    mutable std::atomic<bool> read{false};

    Entry() = default;
    Entry(const Entry& o) : key(o.key), value(o.value), raw(o.raw), line(o.line), read(o.read.load()) {}
    Entry& operator=(const Entry& o) {
      key = o.key;
      value = o.value;
      raw = o.raw;
      line = o.line;
      read.store(o.read.load());
      return *this;
    }
  };
  struct Section {
    std::string name;
    std::vector<Entry> entries;
    std::unordered_map<std::string, std::size_t> index;  // lower-case key -> entry
    std::size_t header_line = 0;  // line of its first `[section]` header (0: none yet)
  };
  friend class IniBuilder;

  const Section* find_section(std::string_view section) const;
  const Entry* find(std::string_view section, std::string_view key) const;
  const Entry& require(std::string_view section, std::string_view key) const;
  [[noreturn]] void fail(std::string_view section, std::string_view key,
                         const std::string& problem) const;
  std::size_t choose(std::string_view section, std::string_view key,
                     const std::vector<std::string_view>& names,
                     const std::vector<std::int64_t>& values) const;
  Section& section_for_write(std::string_view section);
  void put(Section& s, std::string_view key, std::string value, std::string raw, std::size_t line);

  std::string source_;
  std::vector<Section> sections_;
  std::unordered_map<std::string, std::size_t> section_index_;  // lower-case name -> section
  std::vector<IniSkippedLine> skipped_;
  std::vector<IniDuplicate> duplicates_;
};

#define ROVE_DETAIL_INI_EXTERN(T)                                                              \
  extern template T IniFile::get<T>(std::string_view, std::string_view) const;                 \
  extern template T IniFile::get_or<T>(std::string_view, std::string_view, const T&) const;    \
  extern template std::vector<T> IniFile::get_vector<T>(std::string_view, std::string_view)    \
      const;                                                                                   \
  extern template std::vector<std::vector<T>> IniFile::get_matrix<T>(std::string_view,         \
                                                                     std::string_view) const;
ROVE_DETAIL_INI_EXTERN(bool)
ROVE_DETAIL_INI_EXTERN(int)
ROVE_DETAIL_INI_EXTERN(std::int64_t)
ROVE_DETAIL_INI_EXTERN(unsigned)
ROVE_DETAIL_INI_EXTERN(std::uint64_t)
ROVE_DETAIL_INI_EXTERN(double)
ROVE_DETAIL_INI_EXTERN(float)
ROVE_DETAIL_INI_EXTERN(std::string)
#undef ROVE_DETAIL_INI_EXTERN

template <typename E>
  requires std::is_enum_v<E>
E IniFile::get_enum(std::string_view section, std::string_view key,
                    std::initializer_list<IniEnumName<E>> names) const {
  std::vector<std::string_view> labels;
  std::vector<std::int64_t> values;
  for (const auto& n : names) {
    labels.push_back(n.name);
    values.push_back(static_cast<std::int64_t>(static_cast<std::underlying_type_t<E>>(n.value)));
  }
  return (names.begin() + choose(section, key, labels, values))->value;
}

}  // namespace rove
