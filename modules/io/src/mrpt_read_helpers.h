#pragma once
// Internal: helpers shared by the readers of MRPT object payloads
// (mrpt_objects.cpp, mrpt_sensor_readers.cpp, mrpt_pdf_readers.cpp).

#include <fmt/format.h>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>

#include <Eigen/Core>

#include "rove/io/mrpt_objects.h"
#include "rove/obs/timestamp.h"
#include "rove/serialization/mrpt_class_readers.h"
#include "rove/serialization/mrpt_format.h"
#include "rove/serialization/parse_guard.h"

namespace rove::detail {

/// Name of the MrptObject alternative `index`, for error messages.
const char* mrpt_alternative_name(std::size_t index);

/// Reads a nested object and requires it to be of alternative T.
template <typename T>
T expect_mrpt(InArchive& ar, std::string_view field, const char* what) {
  const std::uint64_t at = ar.offset();
  MrptObject o = read_mrpt_object(ar);
  if (auto* p = std::get_if<T>(&o)) return std::move(*p);
  ar.fail_at(at, field,
             fmt::format("expected {} but found {}", what, mrpt_alternative_name(o.index())));
}

/// An MRPT timestamp (u64 ticks of 100 ns since 1601; 0 = invalid).
inline Timestamp read_mrpt_timestamp(InArchive& ar, std::string_view field) {
  const std::uint64_t at = ar.offset();
  const auto ticks = ar.read_scalar<std::uint64_t>(field);
  return parse_guard(ar, at, field, [&] { return Timestamp::from_mrpt(ticks); });
}

/// MRPT's deserializeSymmetricMatrixFrom: the N diagonal entries, then the
/// strict upper triangle row by row.
template <typename S, int N>
Eigen::Matrix<double, N, N> read_mrpt_symmetric(InArchive& ar, std::string_view field) {
  Eigen::Matrix<double, N, N> m;
  for (int i = 0; i < N; ++i) m(i, i) = static_cast<double>(ar.read_scalar<S>(field));
  for (int r = 0; r < N - 1; ++r) {
    for (int c = r + 1; c < N; ++c) {
      m(r, c) = m(c, r) = static_cast<double>(ar.read_scalar<S>(field));
    }
  }
  return m;
}

/// A nested CMatrixD/CMatrixF object of exactly rows x cols.
Eigen::MatrixXd expect_mrpt_matrix(InArchive& ar, std::string_view field, Eigen::Index rows,
                                   Eigen::Index cols);

/// Registers a reader under the bare class name and under `ns` + name.
using MrptReaderAdder =
    std::function<void(std::string_view ns, const std::string& name,
                       MrptClassReaders<MrptObject>::Reader reader)>;

/// Readers of the pose PDFs beyond the Gaussians (mrpt_pdf_readers.cpp).
void add_mrpt_pdf_readers(const MrptReaderAdder& add);
/// Readers of 3D, lidar, GNSS, image and comment observations and 3D
/// actions (mrpt_sensor_readers.cpp).
void add_mrpt_sensor_readers(const MrptReaderAdder& add);

}  // namespace rove::detail
