#include "rove/core/json.h"

#include <fmt/format.h>

#include <cmath>

#include "rove/core/error.h"
#include "utf8.h"

namespace rove {
std::string json_quote(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out += '"';
  std::size_t i = 0;
  while (i < text.size()) {
    const char ch = text[i];
    const std::size_t len = detail::utf8_sequence_length(text, i);
    if (len == 0) {
      out += "\ufffd";
      ++i;
      continue;
    }
    if (len > 1) {
      out.append(text.substr(i, len));
      i += len;
      continue;
    }
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(ch)));
        } else {
          out += ch;
        }
    }
    ++i;
  }
  out += '"';
  return out;
}

void JsonWriter::newline() {
  if (indent_ <= 0) return;
  out_ += '\n';
  out_.append(stack_.size() * static_cast<std::size_t>(indent_), ' ');
}

void JsonWriter::before_value() {
  if (done_) throw InvalidArgument("JsonWriter: a value after the document was complete");
  if (stack_.empty()) return;
  Level& top = stack_.back();
  if (top.object) {
    if (!top.expecting_value) throw InvalidArgument("JsonWriter: a value in an object needs a key");
    top.expecting_value = false;
    return;
  }
  if (!top.empty) out_ += ',';
  top.empty = false;
  newline();
}

JsonWriter& JsonWriter::key(std::string_view k) {
  if (stack_.empty() || !stack_.back().object || stack_.back().expecting_value) {
    throw InvalidArgument("JsonWriter: a key outside an object or after another key");
  }
  Level& top = stack_.back();
  if (!top.empty) out_ += ',';
  top.empty = false;
  newline();
  out_ += json_quote(k);
  out_ += indent_ > 0 ? ": " : ":";
  top.expecting_value = true;
  return *this;
}

JsonWriter& JsonWriter::begin_object() {
  before_value();
  out_ += '{';
  stack_.push_back({true});
  return *this;
}

JsonWriter& JsonWriter::begin_array() {
  before_value();
  out_ += '[';
  stack_.push_back({false});
  return *this;
}

JsonWriter& JsonWriter::end_object() {
  if (stack_.empty() || !stack_.back().object || stack_.back().expecting_value) {
    throw InvalidArgument("JsonWriter: end_object without a matching begin_object");
  }
  const bool empty = stack_.back().empty;
  stack_.pop_back();
  if (!empty) newline();
  out_ += '}';
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::end_array() {
  if (stack_.empty() || stack_.back().object) {
    throw InvalidArgument("JsonWriter: end_array without a matching begin_array");
  }
  const bool empty = stack_.back().empty;
  stack_.pop_back();
  if (!empty) newline();
  out_ += ']';
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view v) {
  before_value();
  out_ += json_quote(v);
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(bool v) { return raw(v ? "true" : "false"); }

JsonWriter& JsonWriter::value(double v) {
  if (!std::isfinite(v)) return null();
  return raw(fmt::format("{}", v));
}

JsonWriter& JsonWriter::value(std::int64_t v) { return raw(fmt::format("{}", v)); }
JsonWriter& JsonWriter::value(std::uint64_t v) { return raw(fmt::format("{}", v)); }
JsonWriter& JsonWriter::null() { return raw("null"); }

JsonWriter& JsonWriter::raw(std::string_view json) {
  before_value();
  out_ += json;
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(const std::vector<std::string>& items) {
  begin_array();
  for (const auto& s : items) value(std::string_view(s));
  return end_array();
}

std::string JsonWriter::str() const {
  if (!stack_.empty()) throw InvalidArgument("JsonWriter: an object or array is still open");
  return out_ + (indent_ > 0 ? "\n" : "");
}

}  // namespace rove
