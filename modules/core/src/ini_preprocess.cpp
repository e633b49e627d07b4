// MRPT-compatible preprocessing of INI text; the rules follow MRPT 2.x
// mrpt::config::config_parser() (see the comments in rove/core/ini.h).

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>

#include "ini_text.h"
#include "rove/core/arith_expr.h"
#include "rove/core/error.h"

namespace rove::detail {

std::string_view ini_trim(std::string_view s) {
  while (!s.empty() && ini_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && ini_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string ini_lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

bool ini_is_comment(std::string_view t) {
  return !t.empty() && (t[0] == '#' || t[0] == ';' || t.starts_with("//"));
}

namespace {
// True if `s` is exactly a decimal number such as "0", "-0.10" or "2e3".
bool is_plain_number(std::string_view s) {
  if (!s.empty() && (s.front() == '+' || s.front() == '-')) s.remove_prefix(1);
  if (s.empty() || !((s.front() >= '0' && s.front() <= '9') || s.front() == '.')) return false;
  double v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && ptr == s.data() + s.size();
}
}  // namespace

std::size_t ini_comment_start(std::string_view v) {
  int depth = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const char c = v[i];
    const bool after_blank = i > 0 && ini_blank(v[i - 1]);
    // "0.10// comment": MRPT's files write this, and MRPT's atof reads 0.10.
    if (!after_blank && i > 0 && c == '/' && i + 1 < v.size() && v[i + 1] == '/' &&
        is_plain_number(v.substr(0, i)))
      return i;
    if (after_blank) {
      if (c == '#' || (c == '/' && i + 1 < v.size() && v[i + 1] == '/')) return i;
      if (c == ';' && depth == 0) return i;
    }
    if (c == '[') ++depth;
    if (c == ']' && depth > 0) --depth;
  }
  return std::string_view::npos;
}

std::string ini_strip_value(std::string_view v) {
  v = ini_trim(v);
  if (const auto c = ini_comment_start(v); c != std::string_view::npos) v = ini_trim(v.substr(0, c));
  while (!v.empty() && v.back() == ';') {
    int depth = 0;
    for (const char c : v) {
      if (c == '[') ++depth;
      if (c == ']' && depth > 0) --depth;
    }
    if (depth != 0) break;
    v = ini_trim(v.substr(0, v.size() - 1));
  }
  return std::string(v);
}

std::string ini_mrpt_raw(std::string_view value) {
  // CConfigFile::readString: only the first "//" is considered, and it is
  // cut when the character before it is whitespace.
  const std::size_t pos = value.find("//");
  if (pos != std::string_view::npos && pos > 0 &&
      (ini_blank(value[pos - 1]) || value[pos - 1] == '\v' || value[pos - 1] == '\f'))
    value = value.substr(0, pos);
  return std::string(ini_trim(value));
}

namespace {

struct Define {
  std::string text;
  std::optional<double> number;
};

class Preprocessor {
 public:
  explicit Preprocessor(const std::string& source) : source_(source) {}

  [[noreturn]] void fail(std::size_t line, std::string field, const std::string& problem) const {
    throw ParseError({source_, line, std::nullopt, std::move(field)}, problem);
  }

  /// Expands `${}`, `$env{}` and `$eval{}` in one logical line.
  std::string expand(std::string_view s, std::size_t line) const {
    std::string out;
    out.reserve(s.size());
    std::size_t i = 0;
    while (i < s.size()) {
      if (s[i] != '$') {
        out += s[i++];
        continue;
      }
      const std::string_view rest = s.substr(i);
      std::size_t open = 0;
      if (rest.starts_with("${")) {
        open = 2;
      } else if (rest.starts_with("$env{")) {
        open = 5;
      } else if (rest.starts_with("$eval{")) {
        open = 6;
      } else {
        out += s[i++];
        continue;
      }
      const std::size_t close = rest.find('}', open);
      if (close == std::string_view::npos)
        fail(line, std::string(rest), "missing closing '}'");
      const std::string_view inner = rest.substr(open, close - open);
      if (open == 2) {
        const auto it = defines_.find(std::string(inner));
        if (it == defines_.end())
          fail(line, std::string(rest.substr(0, close + 1)),
               fmt::format("unknown variable '{}' (not @define'd above)", inner));
        out += it->second.text;
      } else if (open == 5) {
        out += env(inner, line);
      } else {
        out += eval(inner, line);
      }
      i += close + 1;
    }
    return out;
  }

  std::string env(std::string_view name, std::size_t line) const {
    const char* v = std::getenv(std::string(name).c_str());
    if (v == nullptr) return {};
    std::string value(v);
    if (value.find_first_of("\r\n") != std::string::npos)
      fail(line, fmt::format("$env{{{}}}", name), "environment variable contains a line break");
    return value;
  }

  std::string eval(std::string_view expr, std::size_t line) const {
    // The body ends at the first '}' (as MRPT), so it holds no $env{}/${}.
    const std::string_view text = expr;
    double v = 0;
    try {
      v = evaluate_arithmetic(text, numbers_);
    } catch (const ParseError& e) {
      fail(line, fmt::format("$eval{{{}}}", expr), e.problem());
    }
    if (!std::isfinite(v)) fail(line, fmt::format("$eval{{{}}}", expr), "result is not finite");
    return fmt::format("{:e}", v);
  }

  void define(std::string_view rest, std::size_t line) {
    // rest: the text after "@define"
    if (!rest.empty() && !ini_blank(rest.front()))
      fail(line, "@define", "expected a space after @define");
    rest = ini_trim(rest);
    std::size_t end = 0;
    while (end < rest.size() && !ini_blank(rest[end])) ++end;
    const std::string name(rest.substr(0, end));
    if (name.empty()) fail(line, "@define", "@define needs a name");
    Define d;
    d.text = std::string(ini_trim(expand(rest.substr(end), line)));
    const std::string stripped = ini_strip_value(d.text);
    std::string_view num = stripped;
    if (!num.empty() && num.front() == '+') num.remove_prefix(1);
    double value = 0;
    const auto [ptr, ec] = std::from_chars(num.data(), num.data() + num.size(), value);
    if (!num.empty() && ec == std::errc() && ptr == num.data() + num.size() && std::isfinite(value))
      d.number = value;
    if (d.number) {
      numbers_[name] = *d.number;
    } else {
      numbers_.erase(name);
    }
    defines_[name] = std::move(d);
  }

 private:
  const std::string& source_;
  std::map<std::string, Define> defines_;
  ArithVariables numbers_;
};

}  // namespace

std::vector<IniLine> ini_preprocess(std::string_view text, const std::string& source) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark

  // Physical lines end at "\r\n", "\n" or "\r" (SimpleIni's line breaks). A
  // backslash right before a line break joins the next line (MRPT).
  std::vector<IniLine> logical;
  std::size_t line_no = 1;
  std::size_t i = 0;
  bool joining = false;
  while (i < text.size() || joining) {
    std::size_t end = i;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    std::string_view phys = text.substr(i, end - i);
    if (phys.find('\0') != std::string_view::npos)
      throw ParseError({source, line_no, std::nullopt, {}}, "NUL byte in text");
    const bool has_break = end < text.size();
    std::size_t next = end;
    if (has_break) next += (text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n') ? 2 : 1;
    const bool continues = has_break && !phys.empty() && phys.back() == '\\';
    if (continues) phys.remove_suffix(1);
    if (joining) {
      logical.back().text += phys;
    } else {
      logical.push_back({std::string(phys), line_no});
    }
    joining = continues;
    if (joining && next >= text.size()) joining = false;  // final break: nothing to join
    ++line_no;
    i = next;
    if (!has_break) break;
  }

  Preprocessor pp(source);
  std::vector<IniLine> out;
  out.reserve(logical.size());
  for (auto& l : logical) {
    const std::string_view t = ini_trim(l.text);
    if (t.empty() || ini_is_comment(t)) {
      out.push_back(std::move(l));
    } else if (t.starts_with("@define")) {
      pp.define(t.substr(7), l.line);
    } else {
      out.push_back({pp.expand(l.text, l.line), l.line});
    }
  }
  return out;
}

}  // namespace rove::detail
