#pragma once
/// \file
/// Precondition checks that report the failing expression and the values
/// involved (MRPT's ASSERT_ / ASSERT_EQUAL_ family). They are always on,
/// in every build type: a violated precondition throws rove::InvalidArgument.
///
///   ROVE_CHECK(n > 0);
///   ROVE_CHECK_MSG(q.norm() > 0, "quaternion must be non-zero");
///   ROVE_CHECK_EQ(a.size(), b.size());   // "a.size() == b.size() (3 vs 4)"
///   ROVE_CHECK_LT(t, 1.0);  ROVE_CHECK_GE(k, 0);  ROVE_CHECK_FINITE(x);

#include <cmath>
#include <concepts>
#include <sstream>
#include <string>
#include <type_traits>

#include <fmt/format.h>

#include "rove/core/error.h"

namespace rove::detail {

template <typename T>
concept Streamable = requires(std::ostream& os, const T& v) { os << v; };

/// Text for a value in a check message: fmt when it can, else operator<<.
template <typename T>
std::string check_value_string(const T& v) {
  if constexpr (fmt::is_formattable<T>::value) {
    return fmt::format("{}", v);
  } else if constexpr (Streamable<T>) {
    std::ostringstream os;
    os << v;
    return os.str();
  } else {
    return "<value>";
  }
}

[[noreturn]] void check_failed(const char* expression, const std::string& detail,
                               SourceFrame where);

template <typename A, typename B>
[[noreturn]] void check_op_failed(const char* a_text, const char* op, const char* b_text,
                                  const A& a, const B& b, SourceFrame where) {
  check_failed(fmt::format("{} {} {}", a_text, op, b_text).c_str(),
               fmt::format("{} = {}, {} = {}", a_text, check_value_string(a), b_text,
                           check_value_string(b)),
               std::move(where));
}

template <typename T>
bool all_finite(const T& v) {
  if constexpr (std::is_arithmetic_v<T>) {
    return std::isfinite(static_cast<double>(v));
  } else {
    return v.allFinite();  // Eigen expressions
  }
}

}  // namespace rove::detail

#define ROVE_DETAIL_HERE ::rove::SourceFrame{__func__, __FILE__, __LINE__}

/// Throws rove::InvalidArgument naming `cond` if it is false.
#define ROVE_CHECK(cond)                                                   \
  do {                                                                     \
    if (!(cond)) [[unlikely]]                                              \
      ::rove::detail::check_failed(#cond, std::string(), ROVE_DETAIL_HERE); \
  } while (false)

/// As ROVE_CHECK, with an fmt-style explanation appended.
#define ROVE_CHECK_MSG(cond, ...)                                              \
  do {                                                                         \
    if (!(cond)) [[unlikely]]                                                  \
      ::rove::detail::check_failed(#cond, ::fmt::format(__VA_ARGS__), ROVE_DETAIL_HERE); \
  } while (false)

#define ROVE_DETAIL_CHECK_OP(a, op, b)                                             \
  do {                                                                             \
    const auto& rove_check_a_ = (a);                                               \
    const auto& rove_check_b_ = (b);                                               \
    if (!(rove_check_a_ op rove_check_b_)) [[unlikely]]                            \
      ::rove::detail::check_op_failed(#a, #op, #b, rove_check_a_, rove_check_b_,   \
                                      ROVE_DETAIL_HERE);                           \
  } while (false)

/// Binary checks that print both operands when they fail.
#define ROVE_CHECK_EQ(a, b) ROVE_DETAIL_CHECK_OP(a, ==, b)
#define ROVE_CHECK_NE(a, b) ROVE_DETAIL_CHECK_OP(a, !=, b)
#define ROVE_CHECK_LT(a, b) ROVE_DETAIL_CHECK_OP(a, <, b)
#define ROVE_CHECK_LE(a, b) ROVE_DETAIL_CHECK_OP(a, <=, b)
#define ROVE_CHECK_GT(a, b) ROVE_DETAIL_CHECK_OP(a, >, b)
#define ROVE_CHECK_GE(a, b) ROVE_DETAIL_CHECK_OP(a, >=, b)

/// Throws if a scalar or an Eigen expression holds NaN or Inf.
#define ROVE_CHECK_FINITE(x)                                                       \
  do {                                                                             \
    if (!::rove::detail::all_finite(x)) [[unlikely]]                               \
      ::rove::detail::check_failed("isfinite(" #x ")",                             \
                                   #x " = " + ::rove::detail::check_value_string(x), \
                                   ROVE_DETAIL_HERE);                              \
  } while (false)
