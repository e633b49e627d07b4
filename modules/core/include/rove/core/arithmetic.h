#pragma once
/// \file
/// The arithmetic an algorithm computes in: rove's own double precision, or
/// a peer's arithmetic reproduced bit for bit. Reproducing MRPT is a named
/// strategy chosen through each algorithm's Options, never a silent default
/// (docs/conventions.md, "MRPT and PCL compatibility"); the code that does it
/// lives in files named `*_mrpt.cpp`, the only files built with
/// -ffp-contract=off.

#include <initializer_list>
#include <string_view>

#include "rove/core/ini.h"

namespace rove {

/// Which arithmetic an algorithm runs in.
enum class Arithmetic {
  /// Double precision in the straightforward order (rove's default): the
  /// most accurate answer the algorithm gives.
  Double,
  /// MRPT 2.5.8's arithmetic to the bit: single precision where MRPT stores
  /// or computes in float, its order of operations, its integer overflows.
  /// Use it to reproduce an MRPT run exactly (a parity test, a comparison);
  /// it is less accurate than Double far from the origin.
  Mrpt,
};

/// The name of `a` as configuration files and the command line spell it:
/// "double" or "mrpt".
constexpr std::string_view to_string(Arithmetic a) noexcept {
  return a == Arithmetic::Mrpt ? "mrpt" : "double";
}

/// The names for IniFile::get_enum and command-line parsers.
inline const std::initializer_list<IniEnumName<Arithmetic>> kArithmeticNames = {
    {"double", Arithmetic::Double}, {"mrpt", Arithmetic::Mrpt}};

}  // namespace rove
