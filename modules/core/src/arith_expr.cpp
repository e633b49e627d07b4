#include "rove/core/arith_expr.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "rove/core/error.h"

namespace rove {
namespace {

constexpr int kMaxDepth = 256;

bool is_name_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool is_name_char(char c) { return is_name_start(c) || (c >= '0' && c <= '9'); }

/// Recursive-descent evaluator; one instance per expression.
class Evaluator {
 public:
  Evaluator(std::string_view text, const ArithVariables& vars) : text_(text), vars_(vars) {}

  double run() {
    const double v = expression();
    skip_space();
    if (pos_ != text_.size()) fail(fmt::format("unexpected '{}'", text_[pos_]));
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    ParseError::Location where;
    where.source = "<expression>";
    where.offset = pos_;
    where.field = std::string(text_);
    throw ParseError(std::move(where), problem);
  }

  void skip_space() {
    while (pos_ < text_.size() &&
           (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r' || text_[pos_] == '\n'))
      ++pos_;
  }

  bool accept(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }

  void expect(char c) {
    if (!accept(c)) fail(fmt::format("expected '{}'", c));
  }

  struct DepthGuard {
    explicit DepthGuard(Evaluator& e) : ev(e) {
      if (++ev.depth_ > kMaxDepth) ev.fail("expression nested too deeply");
    }
    ~DepthGuard() { --ev.depth_; }
    DepthGuard(const DepthGuard&) = delete;
    DepthGuard& operator=(const DepthGuard&) = delete;
    Evaluator& ev;
  };

  // expression := term (('+' | '-') term)*
  double expression() {
    DepthGuard guard(*this);
    double v = term();
    for (;;) {
      if (accept('+')) {
        v += term();
      } else if (accept('-')) {
        v -= term();
      } else {
        return v;
      }
    }
  }

  // term := unary (('*' | '/' | '%') unary)*
  double term() {
    double v = unary();
    for (;;) {
      if (accept('*')) {
        v *= unary();
      } else if (accept('/')) {
        v /= unary();
      } else if (accept('%')) {
        v = std::fmod(v, unary());
      } else {
        return v;
      }
    }
  }

  // unary := ('-' | '+') unary | power
  double unary() {
    DepthGuard guard(*this);
    if (accept('-')) return -unary();
    if (accept('+')) return unary();
    return power();
  }

  // power := primary ('^' unary)?      (right-associative through unary)
  double power() {
    const double base = primary();
    if (accept('^')) return std::pow(base, unary());
    return base;
  }

  double primary() {
    skip_space();
    if (pos_ >= text_.size()) fail("unexpected end of expression");
    const char c = text_[pos_];
    if (c == '(') {
      ++pos_;
      const double v = expression();
      expect(')');
      return v;
    }
    if ((c >= '0' && c <= '9') || c == '.') return number();
    if (is_name_start(c)) return name();
    fail(fmt::format("unexpected '{}'", c));
  }

  double number() {
    double v = 0;
    const char* first = text_.data() + pos_;
    const char* last = text_.data() + text_.size();
    const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
    if (ec == std::errc::result_out_of_range) fail("number out of range");
    if (ec != std::errc() || ptr == first) fail("malformed number");
    pos_ += static_cast<std::size_t>(ptr - first);
    if (pos_ < text_.size() && is_name_char(text_[pos_])) fail("malformed number");
    return v;
  }

  double name() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
    const std::string_view id = text_.substr(start, pos_ - start);
    if (accept('(')) return call(id, start);
    if (auto it = vars_.find(id); it != vars_.end()) return it->second;
    if (id == "pi" || id == "M_PI") return std::numbers::pi;
    if (id == "epsilon") return std::numeric_limits<double>::epsilon();
    if (id == "inf") return std::numeric_limits<double>::infinity();
    pos_ = start;
    fail(fmt::format("unknown name '{}'", id));
  }

  double call(std::string_view fn, std::size_t fn_pos) {
    double args[2] = {0, 0};
    int n = 0;
    if (!accept(')')) {
      do {
        if (n == 2) {
          pos_ = fn_pos;
          fail(fmt::format("too many arguments to '{}'", fn));
        }
        args[n++] = expression();
      } while (accept(','));
      expect(')');
    }
    const double a = args[0];
    const double b = args[1];
    if (n == 1) {
      if (fn == "abs") return std::fabs(a);
      if (fn == "sqrt") return std::sqrt(a);
      if (fn == "exp") return std::exp(a);
      if (fn == "log") return std::log(a);
      if (fn == "log10") return std::log10(a);
      if (fn == "log2") return std::log2(a);
      if (fn == "sin") return std::sin(a);
      if (fn == "cos") return std::cos(a);
      if (fn == "tan") return std::tan(a);
      if (fn == "asin") return std::asin(a);
      if (fn == "acos") return std::acos(a);
      if (fn == "atan") return std::atan(a);
      if (fn == "sinh") return std::sinh(a);
      if (fn == "cosh") return std::cosh(a);
      if (fn == "tanh") return std::tanh(a);
      if (fn == "floor") return std::floor(a);
      if (fn == "ceil") return std::ceil(a);
      if (fn == "round") return std::round(a);
      if (fn == "trunc") return std::trunc(a);
    } else if (n == 2) {
      if (fn == "atan2") return std::atan2(a, b);
      if (fn == "pow") return std::pow(a, b);
      if (fn == "min") return std::fmin(a, b);
      if (fn == "max") return std::fmax(a, b);
      if (fn == "hypot") return std::hypot(a, b);
      if (fn == "fmod") return std::fmod(a, b);
    }
    pos_ = fn_pos;
    fail(fmt::format("unknown function '{}' with {} argument(s)", fn, n));
  }

  std::string_view text_;
  const ArithVariables& vars_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

}  // namespace

double evaluate_arithmetic(std::string_view expression, const ArithVariables& variables) {
  return Evaluator(expression, variables).run();
}

}  // namespace rove
