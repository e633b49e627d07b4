#pragma once
/// \file
/// A small JSON writer for rove's summaries (`--json`, summary.json). Strings
/// are escaped per RFC 8259; bytes that are not valid UTF-8 (a non-UTF-8 path)
/// become U+FFFD, so the output is always valid JSON. Non-finite numbers are
/// written as null.
///
///   rove::JsonWriter j;
///   j.begin_object();
///   j.key("converged").value(true);
///   j.key("issues").begin_array().value("max-iterations").end_array();
///   j.end_object();
///   std::string text = j.str();

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rove {

/// `text` as a quoted JSON string.
std::string json_quote(std::string_view text);

/// Streaming JSON builder with indentation. Misuse (a key outside an object,
/// unbalanced ends) throws rove::InvalidArgument.
class JsonWriter {
 public:
  explicit JsonWriter(int indent = 2) : indent_(indent) {}
  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  JsonWriter& key(std::string_view k);
  JsonWriter& value(std::string_view v);
  JsonWriter& value(const char* v) { return value(std::string_view(v)); }
  JsonWriter& value(const std::string& v) { return value(std::string_view(v)); }
  JsonWriter& value(bool v);
  JsonWriter& value(double v);
  JsonWriter& value(float v) { return value(static_cast<double>(v)); }
  JsonWriter& value(std::int64_t v);
  JsonWriter& value(int v) { return value(static_cast<std::int64_t>(v)); }
  JsonWriter& value(long long v) { return value(static_cast<std::int64_t>(v)); }
  JsonWriter& value(std::uint64_t v);
  JsonWriter& value(unsigned v) { return value(static_cast<std::uint64_t>(v)); }
  JsonWriter& value(unsigned long long v) { return value(static_cast<std::uint64_t>(v)); }
  JsonWriter& null();
  /// Inserts already-formatted JSON as a value (a nested document).
  JsonWriter& raw(std::string_view json);
  /// An array of strings.
  JsonWriter& value(const std::vector<std::string>& items);
  /// The document; throws rove::InvalidArgument if an object or array is open.
  std::string str() const;

 private:
  void before_value();
  void newline();
  struct Level {
    bool object;
    bool empty = true;
    bool expecting_value = false;
  };
  std::string out_;
  std::vector<Level> stack_;
  int indent_;
  bool done_ = false;
};

}  // namespace rove
