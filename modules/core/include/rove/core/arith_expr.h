#pragma once
/// \file
/// Evaluation of the small arithmetic expressions that MRPT config files put
/// inside `$eval{...}` (MRPT hands them to exprtk; rove supports the
/// arithmetic subset that config files use).

#include <functional>
#include <map>
#include <string>
#include <string_view>

namespace rove {

/// Named numeric values an expression may refer to (e.g. `@define`d names).
using ArithVariables = std::map<std::string, double, std::less<>>;

/// Evaluates `expression` and returns its value.
///
/// Grammar: numbers (`3`, `2.5`, `.5`, `1e-3`), variables from `variables`
/// and the constants `pi`, `M_PI`, `epsilon`, `inf` (as exprtk's
/// add_constants()); binary `+ - * / %` and `^` (power, right-associative,
/// binding tighter than unary minus: `-2^2 == -4`), unary `+ -`,
/// parentheses, and the functions abs, sqrt, exp, log, log10, log2, sin,
/// cos, tan, asin, acos, atan, sinh, cosh, tanh, floor, ceil, round, trunc
/// (one argument) and atan2, pow, min, max, hypot, fmod (two arguments).
/// Angles are radians. Names are case-sensitive.
///
/// Throws rove::ParseError (field = the expression, offset = byte position
/// of the problem) on a syntax error, an unknown name, or nesting deeper
/// than 256 levels. Non-finite results are returned as they are; callers
/// decide whether they accept them.
double evaluate_arithmetic(std::string_view expression, const ArithVariables& variables = {});

}  // namespace rove
