// libFuzzer target for rove::IniFile. Any input must either parse or be
// rejected with a rove::Error; a parsed document must survive every getter,
// its repeated sections and keys must name what the document holds, in file
// order, and, when to_string() can write it, read back to the same content
// without any repetition.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "rove/core/error.h"
#include "rove/core/ini.h"

namespace {

enum class Mode { A, B, C };

[[noreturn]] void die(const char* what, const std::string& detail) {
  std::fprintf(stderr, "ini_fuzz: %s: %s\n", what, detail.c_str());
  std::abort();
}

template <typename T>
void read_all_ways(const rove::IniFile& ini, const std::string& s, const std::string& k) {
  try {
    (void)ini.get<T>(s, k);
  } catch (const rove::ConfigError&) {
  }
  try {
    (void)ini.get_vector<T>(s, k);
  } catch (const rove::ConfigError&) {
  }
  try {
    (void)ini.get_matrix<T>(s, k);
  } catch (const rove::ConfigError&) {
  }
}

void exercise(const rove::IniFile& ini) {
  for (const auto& s : ini.sections()) {
    for (const auto& k : ini.keys(s)) {
      if (!ini.has(s, k)) die("listed key not found", s + "/" + k);
      read_all_ways<bool>(ini, s, k);
      read_all_ways<int>(ini, s, k);
      read_all_ways<std::int64_t>(ini, s, k);
      read_all_ways<unsigned>(ini, s, k);
      read_all_ways<std::uint64_t>(ini, s, k);
      read_all_ways<double>(ini, s, k);
      read_all_ways<float>(ini, s, k);
      read_all_ways<std::string>(ini, s, k);
      (void)ini.raw(s, k);
      try {
        (void)ini.get_enum<Mode>(s, k, {{"a", Mode::A}, {"b", Mode::B}, {"c", Mode::C}});
      } catch (const rove::ConfigError&) {
      }
    }
    if (!ini.unread_keys(s).empty()) die("keys left unread", s);
  }
}

void check_duplicates(const rove::IniFile& ini) {
  std::size_t previous = 0;
  for (const rove::IniDuplicate& d : ini.duplicates()) {
    const std::string where = d.section + "/" + d.key + " line " + std::to_string(d.line);
    if (d.first_line == 0 || d.line <= d.first_line) die("repetition before its first line", where);
    if (d.line < previous) die("repetitions out of file order", where);
    previous = d.line;
    if (!ini.has_section(d.section)) die("repeated section not in the document", where);
    if (d.is_section != d.key.empty()) die("section repetition with a key, or key without", where);
    if (!d.is_section && !ini.has(d.section, d.key)) die("repeated key not in the document", where);
  }
}

void check_round_trip(const rove::IniFile& ini) {
  std::string text;
  try {
    text = ini.to_string();
  } catch (const rove::InvalidArgument&) {
    return;  // a value that cannot be written back (documented)
  }
  rove::IniFile back;
  try {
    back = rove::IniFile::parse(text, "<round trip>");
  } catch (const rove::Error& e) {
    die("to_string() output does not parse", std::string(e.what()) + "\n---\n" + text);
  }
  if (back.sections() != ini.sections()) die("sections differ after round trip", text);
  if (!back.duplicates().empty()) die("to_string() output repeats a section or key", text);
  for (const auto& s : ini.sections()) {
    if (back.keys(s) != ini.keys(s)) die("keys differ after round trip", s);
    for (const auto& k : ini.keys(s)) {
      if (back.get<std::string>(s, k) != ini.get<std::string>(s, k))
        die("value differs after round trip", s + "/" + k);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const bool strict : {true, false}) {
    try {
      rove::IniOptions options;
      options.strict = strict;
      const rove::IniFile ini = rove::IniFile::parse(text, "<fuzz>", options);
      exercise(ini);
      check_duplicates(ini);
      check_round_trip(ini);
    } catch (const rove::Error&) {
      // rejected input: the only acceptable failure
    }
  }
  return 0;
}
