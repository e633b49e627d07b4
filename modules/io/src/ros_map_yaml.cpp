#include "rove/io/ros_map_yaml.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/gray_image.h"

namespace rove {
namespace {

// One `key: value` line of the YAML subset.
struct YamlEntry {
  std::string key;
  std::vector<std::string> items;  // one item for a scalar, any for a flow list
  bool is_list = false;
  std::size_t line = 0;
};

[[noreturn]] void fail(std::string_view source, std::size_t line, std::string_view key,
                       std::string problem) {
  throw ParseError({std::string(source), line == 0 ? std::nullopt : std::optional<std::size_t>(line),
                    std::nullopt, std::string(key)},
                   std::move(problem));
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// Removes a `#` comment: a `#` at the start or after a blank (space or
// tab), outside quoted scalars. As in YAML, a quote opens a quoted scalar
// only where a scalar starts (the line's start, after `: `, `[` or `,`);
// elsewhere it is a literal character of a plain scalar. Inside double
// quotes a backslash escapes the next character; inside single quotes ''
// is a quote.
std::string_view strip_comment(std::string_view s, std::string_view source, std::size_t line) {
  char quote = 0;
  char prev = 0;        // previous non-blank character outside quotes (0: none)
  bool blank = false;   // a blank since `prev`
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote != 0) {
      if (quote == '"' && c == '\\') {
        ++i;
      } else if (c == quote) {
        if (quote == '\'' && i + 1 < s.size() && s[i + 1] == '\'') {
          ++i;
        } else {
          quote = 0;
          prev = c;
          blank = false;
        }
      }
      continue;
    }
    if (c == ' ' || c == '\t') {
      blank = true;
      continue;
    }
    if (c == '#' && (i == 0 || blank)) return s.substr(0, i);
    const bool scalar_start = prev == 0 || prev == '[' || prev == ',' || (prev == ':' && blank);
    if ((c == '"' || c == '\'') && scalar_start) quote = c;
    prev = c;
    blank = false;
  }
  if (quote != 0) fail(source, line, "", "unterminated quoted string");
  return s;
}

// A scalar: quotes removed (no escapes beyond '' inside single quotes and
// \" \\ inside double quotes).
std::string scalar(std::string_view s, std::string_view source, std::size_t line,
                   std::string_view key) {
  s = trim(s);
  if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front()) {
    const char q = s.front();
    std::string out;
    for (std::size_t i = 1; i + 1 < s.size(); ++i) {
      if (q == '\'' && s[i] == '\'' && i + 2 < s.size() && s[i + 1] == '\'') {
        out += '\'';
        ++i;
      } else if (q == '"' && s[i] == '\\' && i + 2 < s.size()) {
        out += s[++i];
      } else {
        out += s[i];
      }
    }
    return out;
  }
  if (!s.empty() && (s.front() == '"' || s.front() == '\'')) {
    fail(source, line, key, "text after a quoted string");
  }
  for (char c : {'&', '*', '!', '|', '>', '{', '}', '[', ']'}) {
    if (!s.empty() && s.front() == c) {
      fail(source, line, key, fmt::format("unsupported YAML syntax '{}' (rove reads flat "
                                          "`key: value` files)", c));
    }
  }
  return std::string(s);
}

std::vector<YamlEntry> parse_entries(std::string_view text, std::string_view source) {
  std::vector<YamlEntry> out;
  std::size_t line_no = 0;
  std::size_t start = 0;
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF &&
      static_cast<unsigned char>(text[1]) == 0xBB && static_cast<unsigned char>(text[2]) == 0xBF) {
    start = 3;  // UTF-8 byte-order mark
  }
  while (start <= text.size()) {
    auto end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view raw = text.substr(start, end - start);
    start = end + 1;
    ++line_no;
    if (raw.find('\0') != std::string_view::npos) fail(source, line_no, "", "NUL byte in the text");
    std::string_view s = trim(strip_comment(raw, source, line_no));
    if (s.empty()) {
      if (end == text.size()) break;
      continue;
    }
    if (s == "---" && out.empty()) continue;
    if (s == "..." ) break;
    if (raw.front() == ' ' || raw.front() == '\t') {
      fail(source, line_no, "", "indented line: nested YAML is not supported (flat `key: value` only)");
    }
    if (s.front() == '-') fail(source, line_no, "", "block lists are not supported; use [a, b, c]");
    const auto colon = s.find(": ");
    const bool colon_at_end = colon == std::string_view::npos && s.back() == ':';
    if (colon == std::string_view::npos && !colon_at_end) {
      fail(source, line_no, "", "expected `key: value`");
    }
    YamlEntry e;
    e.line = line_no;
    e.key = std::string(trim(s.substr(0, colon_at_end ? s.size() - 1 : colon)));
    if (e.key.empty()) fail(source, line_no, "", "empty key");
    const std::string_view value = colon_at_end ? std::string_view() : trim(s.substr(colon + 2));
    if (value.empty()) {
      fail(source, line_no, e.key, "no value (nested blocks are not supported)");
    }
    if (value.front() == '[') {
      if (value.back() != ']') fail(source, line_no, e.key, "flow list without a closing ']'");
      e.is_list = true;
      std::string_view inner = trim(value.substr(1, value.size() - 2));
      if (!inner.empty()) {
        for (;;) {
          const auto comma = inner.find(',');
          const std::string_view item = trim(inner.substr(0, comma));
          if (item.empty()) fail(source, line_no, e.key, "empty item in a flow list");
          if (item.front() == '[') fail(source, line_no, e.key, "nested lists are not supported");
          e.items.push_back(scalar(item, source, line_no, e.key));
          if (comma == std::string_view::npos) break;
          inner = inner.substr(comma + 1);
        }
      }
    } else {
      e.items.push_back(scalar(value, source, line_no, e.key));
    }
    for (const auto& prev : out) {
      if (prev.key == e.key) {
        fail(source, line_no, e.key, fmt::format("duplicate key (first on line {})", prev.line));
      }
    }
    out.push_back(std::move(e));
    if (end == text.size()) break;
  }
  return out;
}

double to_number(const std::string& s, std::string_view source, std::size_t line,
                 std::string_view key) {
  if (s.empty()) fail(source, line, key, "expected a number, found nothing");
  const char* b = s.c_str();
  char* e = nullptr;
  errno = 0;
  const double v = std::strtod(b, &e);
  if (e != b + s.size() || errno == ERANGE || !std::isfinite(v) ||
      s.find_first_of("xXnN") != std::string::npos) {
    fail(source, line, key, fmt::format("expected a finite decimal number, found '{}'", s));
  }
  return v;
}

const std::string& single(const YamlEntry& e, std::string_view source) {
  if (e.is_list || e.items.size() != 1) fail(source, e.line, e.key, "expected a single value, found a list");
  return e.items[0];
}

// Shortest text reading back to `v`: as float when v is exactly a float.
std::string number_text(double v) {
  const float f = static_cast<float>(v);
  if (static_cast<double>(f) == v) return fmt::format("{}", f);
  return fmt::format("{}", v);
}

// A scalar as YAML text: plain when that reads back the same, else quoted.
std::string scalar_text(const std::string& v) {
  bool plain = !v.empty() && v.find_first_of("\"'&*!|>{}[]#,%@`\n\r\t") == std::string::npos &&
               v.find(": ") == std::string::npos && v.front() != ' ' && v.back() != ' ' &&
               v.front() != '-' && v.back() != ':';
  if (plain) return v;
  std::string q = "\"";
  for (char c : v) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

}  // namespace

std::string_view to_string(RosMapMode mode) {
  switch (mode) {
    case RosMapMode::Trinary: return "trinary";
    case RosMapMode::Scale: return "scale";
    case RosMapMode::Raw: return "raw";
  }
  return "?";
}

RosMapYaml parse_ros_map_yaml(std::string_view text, std::string_view source) {
  RosMapYaml y;
  bool have_image = false, have_resolution = false, have_origin = false;
  for (const YamlEntry& e : parse_entries(text, source)) {
    if (e.key == "image") {
      y.image = single(e, source);
      if (y.image.empty()) fail(source, e.line, e.key, "empty image path");
      have_image = true;
    } else if (e.key == "resolution") {
      y.resolution = to_number(single(e, source), source, e.line, e.key);
      if (!(y.resolution > 0)) {
        fail(source, e.line, e.key, fmt::format("must be > 0, got {}", y.resolution));
      }
      have_resolution = true;
    } else if (e.key == "origin") {
      if (!e.is_list || e.items.size() != 3) {
        fail(source, e.line, e.key, "expected a list of three numbers [x, y, yaw]");
      }
      for (int i = 0; i < 3; ++i) y.origin[static_cast<std::size_t>(i)] =
          to_number(e.items[static_cast<std::size_t>(i)], source, e.line, e.key);
      have_origin = true;
    } else if (e.key == "negate") {
      const std::string& v = single(e, source);
      if (v == "0" || v == "false" || v == "False" || v == "FALSE") {
        y.negate = false;
      } else if (v == "1" || v == "true" || v == "True" || v == "TRUE") {
        y.negate = true;
      } else {
        fail(source, e.line, e.key, fmt::format("expected 0, 1, true or false, found '{}'", v));
      }
    } else if (e.key == "occupied_thresh") {
      y.occupied_thresh = to_number(single(e, source), source, e.line, e.key);
    } else if (e.key == "free_thresh") {
      y.free_thresh = to_number(single(e, source), source, e.line, e.key);
    } else if (e.key == "mode") {
      const std::string& v = single(e, source);
      if (v == "trinary") {
        y.mode = RosMapMode::Trinary;
      } else if (v == "scale") {
        y.mode = RosMapMode::Scale;
      } else if (v == "raw") {
        y.mode = RosMapMode::Raw;
      } else {
        fail(source, e.line, e.key, fmt::format("expected trinary, scale or raw, found '{}'", v));
      }
    } else {
      y.unknown_keys.push_back(e.key);
    }
  }
  if (!have_image) fail(source, 0, "image", "missing required key 'image'");
  if (!have_resolution) fail(source, 0, "resolution", "missing required key 'resolution'");
  if (!have_origin) fail(source, 0, "origin", "missing required key 'origin'");
  if (!(y.free_thresh >= 0 && y.free_thresh <= y.occupied_thresh && y.occupied_thresh <= 1)) {
    fail(source, 0, "free_thresh",
         fmt::format("thresholds must satisfy 0 <= free_thresh <= occupied_thresh <= 1, got "
                     "free_thresh {} and occupied_thresh {}",
                     y.free_thresh, y.occupied_thresh));
  }
  return y;
}

RosMapYaml read_ros_map_yaml(const std::string& path) {
  // A map description is a few lines; a megabyte is already absurd.
  const std::string text = read_input_file(path, std::uint64_t{1} << 20, "map.yaml");
  return parse_ros_map_yaml(text, path);
}

std::string format_ros_map_yaml(const RosMapYaml& y) {
  std::string s = fmt::format("image: {}\nresolution: {}\norigin: [{}, {}, {}]\nnegate: {}\n",
                              scalar_text(y.image), number_text(y.resolution), number_text(y.origin[0]),
                              number_text(y.origin[1]),
                              y.origin[2] == 0 ? std::string("0.0") : number_text(y.origin[2]),
                              y.negate ? 1 : 0);
  s += fmt::format("occupied_thresh: {}\nfree_thresh: {}\n", y.occupied_thresh, y.free_thresh);
  if (y.mode != RosMapMode::Trinary) s += fmt::format("mode: {}\n", to_string(y.mode));
  return s;
}

std::string resolve_image_path(const RosMapYaml& yaml, const std::string& yaml_path) {
  const std::filesystem::path img(yaml.image);
  if (img.is_absolute()) return img.string();
  return (std::filesystem::path(yaml_path).parent_path() / img).string();
}

}  // namespace rove
