#include "rove/viz/json_value.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "rove/core/error.h"

namespace rove {

namespace {

template <class T>
const T& get(const std::variant<std::nullptr_t, bool, double, std::string, JsonValue::Array, JsonValue::Object>& v,
             const char* what) {
  if (const T* p = std::get_if<T>(&v)) return *p;
  throw InvalidArgument(fmt::format("JSON value is not {}", what));
}

class Parser {
 public:
  Parser(std::string_view text, std::string_view source) : text_(text), source_(source) {}

  JsonValue document() {
    JsonValue v = value(0);
    skip_space();
    if (pos_ != text_.size()) fail("end of the document");
    return v;
  }

 private:
  [[noreturn]] void fail(std::string_view expected) const {
    throw ParseError({std::string(source_), std::nullopt, pos_, "json"}, fmt::format("expected {}", expected));
  }

  void skip_space() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n' || text_[pos_] == '\r' ||
                                   text_[pos_] == '\t')) {
      ++pos_;
    }
  }

  bool take(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }

  bool take_word(std::string_view w) {
    if (text_.substr(pos_, w.size()) != w) return false;
    pos_ += w.size();
    return true;
  }

  JsonValue value(int depth) {
    if (depth > 256) fail("nesting of at most 256 levels");
    skip_space();
    if (pos_ >= text_.size()) fail("a value");
    const char c = text_[pos_];
    if (c == '{') return object(depth);
    if (c == '[') return array(depth);
    if (c == '"') return JsonValue(string());
    if (take_word("true")) return JsonValue(true);
    if (take_word("false")) return JsonValue(false);
    if (take_word("null")) return JsonValue();
    return JsonValue(number());
  }

  JsonValue object(int depth) {
    ++pos_;
    JsonValue::Object members;
    if (take('}')) return JsonValue(std::move(members));
    do {
      skip_space();
      if (pos_ >= text_.size() || text_[pos_] != '"') fail("a member name");
      std::string key = string();
      if (!take(':')) fail("':'");
      if (members.count(key) != 0) fail(fmt::format("no duplicate member '{}'", key));
      members.emplace(std::move(key), value(depth + 1));
    } while (take(','));
    if (!take('}')) fail("',' or '}'");
    return JsonValue(std::move(members));
  }

  JsonValue array(int depth) {
    ++pos_;
    JsonValue::Array items;
    if (take(']')) return JsonValue(std::move(items));
    do {
      items.push_back(value(depth + 1));
    } while (take(','));
    if (!take(']')) fail("',' or ']'");
    return JsonValue(std::move(items));
  }

  unsigned hex4() {
    if (pos_ + 4 > text_.size()) fail("four hex digits");
    unsigned v = 0;
    const auto r = std::from_chars(text_.data() + pos_, text_.data() + pos_ + 4, v, 16);
    if (r.ec != std::errc() || r.ptr != text_.data() + pos_ + 4) fail("four hex digits");
    pos_ += 4;
    return v;
  }

  static void append_utf8(std::string& out, unsigned cp) {
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }

  void escape(std::string& out) {
    if (pos_ >= text_.size()) fail("an escape");
    const char e = text_[pos_++];
    switch (e) {
      case '"': out += '"'; return;
      case '\\': out += '\\'; return;
      case '/': out += '/'; return;
      case 'b': out += '\b'; return;
      case 'f': out += '\f'; return;
      case 'n': out += '\n'; return;
      case 'r': out += '\r'; return;
      case 't': out += '\t'; return;
      case 'u': {
        unsigned cp = hex4();
        if (cp >= 0xD800 && cp < 0xDC00) {
          if (!take_word("\\u")) fail("a low surrogate");
          const unsigned lo = hex4();
          if (lo < 0xDC00 || lo >= 0xE000) fail("a low surrogate");
          cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
        } else if (cp >= 0xDC00 && cp < 0xE000) {
          fail("a high surrogate first");
        }
        append_utf8(out, cp);
        return;
      }
      default: --pos_; fail("a valid escape");
    }
  }

  std::string string() {
    ++pos_;  // the opening quote
    std::string out;
    while (true) {
      if (pos_ >= text_.size()) fail("a closing '\"'");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) {
        --pos_;
        fail("no control character in a string");
      }
      if (c == '\\') {
        escape(out);
      } else {
        out += c;
      }
    }
  }

  double number() {
    const std::size_t start = pos_;
    if (pos_ < text_.size() && text_[pos_] == '-') ++pos_;
    const auto digits = [&] {
      const std::size_t s = pos_;
      while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
      return pos_ - s;
    };
    const std::size_t int_start = pos_;
    if (digits() == 0) fail("a value");
    if (text_[int_start] == '0' && pos_ - int_start > 1) fail("no leading zero");
    if (pos_ < text_.size() && text_[pos_] == '.') {
      ++pos_;
      if (digits() == 0) fail("digits after '.'");
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
      if (digits() == 0) fail("exponent digits");
    }
    double v = 0.0;
    const auto r = std::from_chars(text_.data() + start, text_.data() + pos_, v);
    if (r.ec != std::errc() || !std::isfinite(v)) {
      pos_ = start;
      fail("a finite number");
    }
    return v;
  }

  std::string_view text_;
  std::string_view source_;
  std::size_t pos_ = 0;
};

}  // namespace

bool JsonValue::as_bool() const { return get<bool>(value_, "a boolean"); }
double JsonValue::as_number() const { return get<double>(value_, "a number"); }
std::size_t JsonValue::as_index() const {
  const double v = as_number();
  if (!(v >= 0.0) || v != std::floor(v) || v > 9.0e15) {
    throw InvalidArgument(fmt::format("JSON number {} is not a non-negative integer", v));
  }
  return static_cast<std::size_t>(v);
}
const std::string& JsonValue::as_string() const { return get<std::string>(value_, "a string"); }
const JsonValue::Array& JsonValue::as_array() const { return get<Array>(value_, "an array"); }
const JsonValue::Object& JsonValue::as_object() const { return get<Object>(value_, "an object"); }

bool JsonValue::contains(std::string_view key) const {
  const Object* o = std::get_if<Object>(&value_);
  return o != nullptr && o->find(key) != o->end();
}

const JsonValue& JsonValue::operator[](std::string_view key) const {
  const Object& o = as_object();
  const auto it = o.find(key);
  if (it == o.end()) throw InvalidArgument(fmt::format("JSON object has no member '{}'", key));
  return it->second;
}

const JsonValue& JsonValue::operator[](std::size_t i) const {
  const Array& a = as_array();
  if (i >= a.size()) throw InvalidArgument(fmt::format("JSON index {} out of range ({} items)", i, a.size()));
  return a[i];
}

JsonValue parse_json(std::string_view text, std::string_view source) { return Parser(text, source).document(); }

}  // namespace rove
