#pragma once
/// \file
/// Reading an algorithm's or a map's options from one section of an
/// MRPT-style INI file with MRPT's defaults, strictly: a key the options do
/// not know is reported by name (file, section, key, line) instead of being
/// silently ignored, as MRPT does. Keys that MRPT's own files carry but that
/// have no effect in rove (image-feature options, options MRPT itself no
/// longer reads) are accepted and listed, so a user can see what was not
/// applied.
///
/// Every options struct that a config file can set has the same loader:
///   static Options from_config(const ConfigSection& section);
/// starting from the documented defaults and overriding the keys present.

#include <initializer_list>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "rove/core/ini.h"

namespace rove {

/// A key that was present in a configuration but has no effect in rove.
struct IgnoredConfigKey {
  std::string section;  ///< section name as written in the file
  std::string key;      ///< key name as written in the file
  std::string reason;   ///< why it has no effect
};

/// One section of an IniFile seen by an options loader. A missing
/// section reads as empty (every option keeps its default), as in MRPT.
/// Not thread-safe (it records ignored keys through the pointer it holds).
class ConfigSection {
 public:
  /// Views `section` of `ini`. `ignored` (may be null) collects the keys
  /// ignore() finds present. `ini` must outlive this object.
  ConfigSection(const IniFile& ini, std::string section,
                std::vector<IgnoredConfigKey>* ignored = nullptr);

  /// The section name.
  const std::string& name() const noexcept { return section_; }
  /// The file the section belongs to (IniFile::source()).
  const std::string& file() const noexcept { return ini_->source(); }
  /// True if the key is present (does not count as a read).
  bool has(std::string_view key) const { return ini_->has(section_, key); }

  /// The value of `key`, or `fallback` if absent. Throws ConfigError naming
  /// file, section and key if the value is malformed.
  template <IniScalar T>
  T get(std::string_view key, const T& fallback) const {
    return ini_->get_or<T>(section_, key, fallback);
  }
  /// The enumerator named by `key` (MRPT's names, or the enumerator's
  /// number), or `fallback` if absent. Throws ConfigError listing the names
  /// if the value is none of them.
  template <typename E>
    requires std::is_enum_v<E>
  E get_enum(std::string_view key, E fallback, std::initializer_list<IniEnumName<E>> names) const {
    return has(key) ? ini_->get_enum<E>(section_, key, names) : fallback;
  }
  /// The list value of `key` (MRPT's "[a b c]" or "a b c"), or `fallback` if
  /// absent.
  template <IniScalar T>
  std::vector<T> get_vector(std::string_view key, std::vector<T> fallback) const {
    return has(key) ? ini_->get_vector<T>(section_, key) : fallback;
  }
  /// As get(), and throws ConfigError unless lo <= value <= hi.
  double get_in_range(std::string_view key, double fallback, double lo, double hi) const;
  /// The underlying document.
  const IniFile& ini() const noexcept { return *ini_; }

  /// Marks `keys` as known but without effect: each one present is recorded
  /// in the ignored list with `reason` and no longer counts as unknown.
  void ignore(std::initializer_list<std::string_view> keys, std::string_view reason) const;
  /// As ignore(), for every present key starting with `prefix`
  /// (case-insensitive).
  void ignore_prefix(std::string_view prefix, std::string_view reason) const;

  /// Throws ConfigError (file, section, first unknown key, its line, and the
  /// list of all unknown keys) if any key of the section has been neither
  /// read nor ignored.
  void check_all_read() const;

  /// Throws ConfigError naming `key` with `problem`.
  [[noreturn]] void fail(std::string_view key, const std::string& problem) const;

 private:
  const IniFile* ini_;
  std::string section_;
  std::vector<IgnoredConfigKey>* ignored_;
};

}  // namespace rove
