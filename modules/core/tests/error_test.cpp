// Tests of rove/core/error.h and check.h: messages carry the expression and
// the values, traces accumulate innermost-first, foreign exceptions are
// wrapped, and parse/config errors name where the problem is.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <typeinfo>

#include "rove/core/check.h"
#include "rove/core/error.h"

namespace {

using rove::InvalidArgument;

// Runs `f`, expects InvalidArgument and returns its what().
template <typename F>
std::string check_message(F&& f) {
  try {
    f();
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InvalidArgument thrown";
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(Check, PassingChecksDoNotThrow) {
  const int a = 3;
  const int b = 4;
  EXPECT_NO_THROW(ROVE_CHECK(a < b));
  EXPECT_NO_THROW(ROVE_CHECK_MSG(a < b, "never {}", 1));
  EXPECT_NO_THROW(ROVE_CHECK_EQ(a, 3));
  EXPECT_NO_THROW(ROVE_CHECK_NE(a, b));
  EXPECT_NO_THROW(ROVE_CHECK_LT(a, b));
  EXPECT_NO_THROW(ROVE_CHECK_LE(a, a));
  EXPECT_NO_THROW(ROVE_CHECK_GT(b, a));
  EXPECT_NO_THROW(ROVE_CHECK_GE(b, b));
  EXPECT_NO_THROW(ROVE_CHECK_FINITE(1.5));
}

TEST(Check, PlainCheckNamesTheExpression) {
  const int count = 0;
  const std::string m = check_message([&] { ROVE_CHECK(count > 0); });
  EXPECT_TRUE(contains(m, "check failed: count > 0")) << m;
}

TEST(Check, MessageCheckAppendsFormattedText) {
  const double norm = 0.0;
  const std::string m =
      check_message([&] { ROVE_CHECK_MSG(norm > 0, "quaternion norm is {:.1f}", norm); });
  EXPECT_TRUE(contains(m, "norm > 0")) << m;
  EXPECT_TRUE(contains(m, "quaternion norm is 0.0")) << m;
}

TEST(Check, EveryComparisonReportsExpressionAndBothValues) {
  const int lhs = 7;
  const int rhs = 9;
  struct Case {
    std::string message;
    std::string op;
  };
  const Case cases[] = {
      {check_message([&] { ROVE_CHECK_EQ(lhs, rhs); }), "=="},
      {check_message([&] { ROVE_CHECK_NE(lhs, lhs + 0); }), "!="},
      {check_message([&] { ROVE_CHECK_LT(rhs, lhs); }), "<"},
      {check_message([&] { ROVE_CHECK_LE(rhs, lhs); }), "<="},
      {check_message([&] { ROVE_CHECK_GT(lhs, rhs); }), ">"},
      {check_message([&] { ROVE_CHECK_GE(lhs, rhs); }), ">="},
  };
  EXPECT_TRUE(contains(cases[0].message, "lhs == rhs")) << cases[0].message;
  EXPECT_TRUE(contains(cases[0].message, "lhs = 7, rhs = 9")) << cases[0].message;
  EXPECT_TRUE(contains(cases[1].message, "lhs != lhs + 0")) << cases[1].message;
  EXPECT_TRUE(contains(cases[1].message, "lhs = 7, lhs + 0 = 7")) << cases[1].message;
  EXPECT_TRUE(contains(cases[2].message, "rhs < lhs")) << cases[2].message;
  EXPECT_TRUE(contains(cases[2].message, "rhs = 9, lhs = 7")) << cases[2].message;
  EXPECT_TRUE(contains(cases[3].message, "rhs <= lhs")) << cases[3].message;
  EXPECT_TRUE(contains(cases[3].message, "rhs = 9, lhs = 7")) << cases[3].message;
  EXPECT_TRUE(contains(cases[4].message, "lhs > rhs")) << cases[4].message;
  EXPECT_TRUE(contains(cases[4].message, "lhs = 7, rhs = 9")) << cases[4].message;
  EXPECT_TRUE(contains(cases[5].message, "lhs >= rhs")) << cases[5].message;
  EXPECT_TRUE(contains(cases[5].message, "lhs = 7, rhs = 9")) << cases[5].message;
}

TEST(Check, OperandsAreEvaluatedOnce) {
  int calls = 0;
  auto next = [&] { return ++calls; };
  EXPECT_NO_THROW(ROVE_CHECK_EQ(next(), 1));
  EXPECT_EQ(calls, 1);
}

TEST(Check, FiniteCheckReportsTheValue) {
  const double x = std::numeric_limits<double>::quiet_NaN();
  const std::string m = check_message([&] { ROVE_CHECK_FINITE(x); });
  EXPECT_TRUE(contains(m, "isfinite(x)")) << m;
  EXPECT_TRUE(contains(m, "x = nan")) << m;
  const float y = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(contains(check_message([&] { ROVE_CHECK_FINITE(y); }), "y = inf"));
}

TEST(Check, FailureRecordsTheCallSite) {
  int line = 0;
  try {
    line = __LINE__ + 1;
    ROVE_CHECK_EQ(1, 2);
  } catch (const InvalidArgument& e) {
    ASSERT_EQ(e.trace().size(), 1u);
    EXPECT_EQ(e.trace()[0].line, line);
    EXPECT_TRUE(contains(e.trace()[0].file, "error_test.cpp"));
    EXPECT_TRUE(contains(e.what(), "error_test.cpp:" + std::to_string(line)));
    return;
  }
  FAIL() << "no exception";
}

// Three nested functions, each with a trace block.
void innermost(int v) {
  ROVE_TRACE_BEGIN
  ROVE_CHECK_GT(v, 0);
  ROVE_TRACE_END
}
void middle(int v) {
  ROVE_TRACE_BEGIN
  innermost(v);
  ROVE_TRACE_END
}
void outermost(int v) {
  ROVE_TRACE_BEGIN
  middle(v);
  ROVE_TRACE_END
}

TEST(Trace, FramesAccumulateInnermostFirst) {
  try {
    outermost(-1);
  } catch (const InvalidArgument& e) {
    // The check's own frame, then one frame per trace block on the way out.
    ASSERT_EQ(e.trace().size(), 4u);
    EXPECT_EQ(e.trace()[0].function, "innermost");
    EXPECT_EQ(e.trace()[1].function, "innermost");
    EXPECT_EQ(e.trace()[2].function, "middle");
    EXPECT_EQ(e.trace()[3].function, "outermost");
    const std::string w = e.what();
    const auto p_inner = w.find("at innermost");
    const auto p_middle = w.find("at middle");
    const auto p_outer = w.find("at outermost");
    ASSERT_NE(p_inner, std::string::npos);
    EXPECT_LT(p_inner, p_middle);
    EXPECT_LT(p_middle, p_outer);
    EXPECT_TRUE(contains(w, "v = -1")) << w;
    return;
  }
  FAIL() << "no exception";
}

void throws_std() {
  ROVE_TRACE_BEGIN
  throw std::out_of_range("index 5 >= size 3");
  ROVE_TRACE_END
}
void calls_throws_std() {
  ROVE_TRACE_BEGIN
  throws_std();
  ROVE_TRACE_END
}

TEST(Trace, StdExceptionBecomesRoveErrorQuotingIt) {
  try {
    calls_throws_std();
  } catch (const rove::Error& e) {
    EXPECT_EQ(typeid(e), typeid(rove::Error));
    EXPECT_EQ(e.message(), "index 5 >= size 3");
    ASSERT_EQ(e.trace().size(), 2u);
    EXPECT_EQ(e.trace()[0].function, "throws_std");
    EXPECT_EQ(e.trace()[1].function, "calls_throws_std");
    return;
  }
  FAIL() << "no rove::Error";
}

TEST(Trace, RoveErrorKeepsItsType) {
  auto f = [] {
    ROVE_TRACE_BEGIN
    throw rove::NumericError("matrix not positive definite");
    ROVE_TRACE_END
  };
  EXPECT_THROW(f(), rove::NumericError);
}

TEST(Trace, NonStdExceptionPassesUnchanged) {
  auto f = [] {
    ROVE_TRACE_BEGIN
    throw 42;
    ROVE_TRACE_END
  };
  EXPECT_THROW(f(), int);
}

TEST(ParseError, NamesFileLineAndField) {
  const rove::ParseError e({"maps/demo.ini", 12, std::nullopt, "resolution"}, "expected a number");
  const std::string w = e.what();
  EXPECT_TRUE(contains(w, "maps/demo.ini:12")) << w;
  EXPECT_TRUE(contains(w, "[resolution]")) << w;
  EXPECT_TRUE(contains(w, "expected a number")) << w;
  EXPECT_EQ(e.location().source, "maps/demo.ini");
  EXPECT_EQ(e.location().line, 12u);
  EXPECT_EQ(e.location().field, "resolution");
  EXPECT_EQ(e.problem(), "expected a number");
}

TEST(ParseError, NamesByteOffsetForBinaryFormats) {
  const rove::ParseError e({"log.rawlog", std::nullopt, 4096, "CObservation2DRangeScan"},
                           "unknown version 99");
  const std::string w = e.what();
  EXPECT_TRUE(contains(w, "log.rawlog (byte offset 4096)")) << w;
  EXPECT_TRUE(contains(w, "[CObservation2DRangeScan]")) << w;
  EXPECT_TRUE(contains(w, "unknown version 99")) << w;
}

TEST(ConfigError, NamesFileSectionAndKey) {
  const rove::ConfigError e("icp.ini", "ICP", "maxIterations", "'abc' is not an int");
  EXPECT_EQ(std::string(e.what()), "icp.ini: [ICP] maxIterations: 'abc' is not an int");
  EXPECT_EQ(e.file(), "icp.ini");
  EXPECT_EQ(e.section(), "ICP");
  EXPECT_EQ(e.key(), "maxIterations");
}

TEST(IoError, NamesThePath) {
  const rove::IoError e("/nonexistent/x.bin", "cannot open");
  EXPECT_EQ(std::string(e.what()), "/nonexistent/x.bin: cannot open");
  EXPECT_EQ(e.path(), "/nonexistent/x.bin");
}

}  // namespace
