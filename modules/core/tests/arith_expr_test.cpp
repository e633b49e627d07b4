// Tests of rove::evaluate_arithmetic against values computed by hand.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "rove/core/arith_expr.h"
#include "rove/core/error.h"

namespace {

using rove::evaluate_arithmetic;

TEST(ArithExpr, NumbersAndPrecedence) {
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("42"), 42.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic(" .5 "), 0.5);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("1e-3*2"), 0.002);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("1 + 2 * 3"), 7.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("(1 + 2) * 3"), 9.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("10 - 4 - 3"), 3.0);  // left-associative
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("2 / 4 / 2"), 0.25);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("7 % 4"), 3.0);
}

TEST(ArithExpr, PowerIsRightAssociativeAndBindsTighterThanUnaryMinus) {
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("2^3^2"), 512.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("-2^2"), -4.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("2^-1"), 0.5);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("--3"), 3.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("+3 * -2"), -6.0);
}

TEST(ArithExpr, ConstantsFunctionsAndVariables) {
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("pi"), std::numbers::pi);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("M_PI/2"), std::numbers::pi / 2);
  EXPECT_TRUE(std::isinf(evaluate_arithmetic("inf")));
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("sqrt(16) + abs(-2)"), 6.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("atan2(1, 1)"), std::numbers::pi / 4);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("max(3, min(10, 7))"), 7.0);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("floor(2.7) + ceil(2.1) + round(2.5)"), 8.0);
  EXPECT_NEAR(evaluate_arithmetic("cos(pi) + sin(pi/2)"), 0.0, 1e-15);
  const rove::ArithVariables vars{{"W", 60.0}, {"v_max", 1.5}};
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("W*pi/180", vars), std::numbers::pi / 3);
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("2*v_max", vars), 3.0);
  // A variable shadows a constant of the same name.
  EXPECT_DOUBLE_EQ(evaluate_arithmetic("pi", {{"pi", 3.0}}), 3.0);
}

// Returns the ParseError of a failing evaluation.
rove::ParseError error_of(const std::string& expr) {
  try {
    evaluate_arithmetic(expr);
  } catch (const rove::ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "no ParseError for " << expr;
  return rove::ParseError({}, "");
}

TEST(ArithExpr, ErrorsNameTheProblemAndOffset) {
  auto e = error_of("1 + foo");
  EXPECT_EQ(e.problem(), "unknown name 'foo'");
  EXPECT_EQ(e.location().offset, 4u);
  EXPECT_EQ(e.location().field, "1 + foo");
  EXPECT_EQ(error_of("(1 + 2").problem(), "expected ')'");
  EXPECT_EQ(error_of("1 +").problem(), "unexpected end of expression");
  EXPECT_EQ(error_of("2 3").problem(), "unexpected '3'");
  EXPECT_EQ(error_of("1.2.3").problem(), "unexpected '.'");
  EXPECT_EQ(error_of("3x").problem(), "malformed number");
  EXPECT_EQ(error_of("sqrt(1, 2)").problem(), "unknown function 'sqrt' with 2 argument(s)");
  EXPECT_EQ(error_of("max(1, 2, 3)").problem(), "too many arguments to 'max'");
  EXPECT_EQ(error_of("").problem(), "unexpected end of expression");
}

TEST(ArithExpr, DeepNestingIsRejectedNotACrash) {
  EXPECT_EQ(error_of(std::string(100000, '(') + "1").problem(), "expression nested too deeply");
  EXPECT_EQ(error_of(std::string(100000, '-') + "1").problem(), "expression nested too deeply");
  // Within the limit it works.
  EXPECT_DOUBLE_EQ(evaluate_arithmetic(std::string(100, '(') + "1" + std::string(100, ')')), 1.0);
}

}  // namespace
