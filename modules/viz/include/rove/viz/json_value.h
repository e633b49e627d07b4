#pragma once
/// \file
/// A JSON document read into memory (RFC 8259): for reading back what rove
/// writes (the JSON chunk of a .glb) and checking it. Numbers are doubles;
/// objects keep their keys sorted (duplicates are an error).

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace rove {

/// One JSON value.
class JsonValue {
 public:
  /// An array.
  using Array = std::vector<JsonValue>;
  /// An object.
  using Object = std::map<std::string, JsonValue, std::less<>>;

  /// null.
  JsonValue() = default;
  /// From any of the alternatives.
  template <class T>
  explicit JsonValue(T v) : value_(std::move(v)) {}

  /// Whether it is null.
  bool is_null() const noexcept { return std::holds_alternative<std::nullptr_t>(value_); }
  /// Whether it is a number.
  bool is_number() const noexcept { return std::holds_alternative<double>(value_); }
  /// Whether it is a string.
  bool is_string() const noexcept { return std::holds_alternative<std::string>(value_); }
  /// Whether it is an array.
  bool is_array() const noexcept { return std::holds_alternative<Array>(value_); }
  /// Whether it is an object.
  bool is_object() const noexcept { return std::holds_alternative<Object>(value_); }

  /// The boolean; InvalidArgument if it is not one.
  bool as_bool() const;
  /// The number; InvalidArgument if it is not one.
  double as_number() const;
  /// The number as a non-negative integer; InvalidArgument if it is not one.
  std::size_t as_index() const;
  /// The string; InvalidArgument if it is not one.
  const std::string& as_string() const;
  /// The array; InvalidArgument if it is not one.
  const Array& as_array() const;
  /// The object; InvalidArgument if it is not one.
  const Object& as_object() const;

  /// Whether an object has `key` (false for other values).
  bool contains(std::string_view key) const;
  /// The member `key` of an object; InvalidArgument if absent or not an object.
  const JsonValue& operator[](std::string_view key) const;
  /// Element i of an array; InvalidArgument if out of range or not an array.
  const JsonValue& operator[](std::size_t i) const;

 private:
  std::variant<std::nullptr_t, bool, double, std::string, Array, Object> value_{nullptr};
};

/// Parses JSON text. Throws ParseError naming `source`, the byte offset and
/// what was expected. Nesting deeper than 256 levels is refused.
JsonValue parse_json(std::string_view text, std::string_view source);

}  // namespace rove
