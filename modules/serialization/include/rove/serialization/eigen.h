#pragma once
/// \file
/// Eigen matrices and vectors in archives.
///
/// Encoding, for fixed and dynamic sizes alike: u32 rows, u32 cols, then the
/// rows*cols coefficients in column-major order (whatever the storage order
/// of the matrix type). Scalars must be FixedScalar types. Loading a
/// fixed-size matrix rejects other stored dimensions with rove::ParseError;
/// loading a dynamic one checks the declared size against the limits before
/// allocating.

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "rove/serialization/archive.h"

namespace rove {

/// Dimensions plus, for fixed sizes, the coefficients.
template <typename S, int R, int C, int O, int MR, int MC>
struct SerializedMinSize<Eigen::Matrix<S, R, C, O, MR, MC>> {
  /// Two u32 dimensions and the fixed coefficients.
  static constexpr std::uint64_t value =
      8 + (R > 0 && C > 0 ? static_cast<std::uint64_t>(R) * static_cast<std::uint64_t>(C) * sizeof(S)
                          : 0);
};

/// Writes a matrix: u32 rows, u32 cols, coefficients column-major.
template <FixedScalar S, int R, int C, int O, int MR, int MC>
void save(OutArchive& ar, const Eigen::Matrix<S, R, C, O, MR, MC>& m) {
  ar.write_length(static_cast<std::size_t>(m.rows()), "matrix rows");
  ar.write_length(static_cast<std::size_t>(m.cols()), "matrix cols");
  if constexpr (!(O & Eigen::RowMajor) || R == 1 || C == 1) {
    ar.write_scalars(std::span<const S>(m.data(), static_cast<std::size_t>(m.size())));
  } else {
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      for (Eigen::Index i = 0; i < m.rows(); ++i) ar.write_scalar(m(i, j));
    }
  }
}

/// Reads a matrix written by save.
template <FixedScalar S, int R, int C, int O, int MR, int MC>
void load(InArchive& ar, Eigen::Matrix<S, R, C, O, MR, MC>& m) {
  const std::uint64_t at = ar.offset();
  const auto rows = ar.read_scalar<std::uint32_t>("matrix rows");
  const auto cols = ar.read_scalar<std::uint32_t>("matrix cols");
  const auto dims_ok = [](std::uint32_t n, int fixed, int max) {
    if (fixed != Eigen::Dynamic) return n == static_cast<std::uint32_t>(fixed);
    return max == Eigen::Dynamic || n <= static_cast<std::uint32_t>(max);
  };
  if (!dims_ok(rows, R, MR) || !dims_ok(cols, C, MC) ||
      rows > static_cast<std::uint64_t>(Eigen::NumTraits<Eigen::Index>::highest()) ||
      cols > static_cast<std::uint64_t>(Eigen::NumTraits<Eigen::Index>::highest())) {
    ar.fail_at(at, "matrix",
               "stored size " + std::to_string(rows) + "x" + std::to_string(cols) +
                   " does not fit the matrix type");
  }
  const std::uint64_t n = std::uint64_t{rows} * cols;
  ar.check_length(rows, 0, "matrix rows", at);
  ar.check_length(cols, 0, "matrix cols", at);
  ar.check_length(n, sizeof(S), "matrix", at);
  if (n == 0) {
    // Nothing to read; resizing touches no coefficient (an assignment would
    // still loop over a huge empty dimension).
    m.resize(rows, cols);
    return;
  }
  if (!ar.remaining()) {
    // Unknown remaining size (compressed stream): read through a buffer that
    // grows only as data actually arrives.
    std::vector<S> buf;
    ar.append_scalars(buf, n, "matrix");
    m.resize(rows, cols);
    m = Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>>(buf.data(), rows, cols);
    return;
  }
  m.resize(rows, cols);
  if constexpr (!(O & Eigen::RowMajor) || R == 1 || C == 1) {
    ar.read_scalars(std::span<S>(m.data(), static_cast<std::size_t>(n)), "matrix");
  } else {
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      for (Eigen::Index i = 0; i < m.rows(); ++i) m(i, j) = ar.read_scalar<S>("matrix");
    }
  }
}

}  // namespace rove
