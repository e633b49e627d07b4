#pragma once
/// \file
/// Reading MRPT's binary serialization (mrpt::serialization::CArchive), the
/// framing of .rawlog, .simplemap and .gridmap files.
///
/// Object framing, as MRPT writes it since 0.5.5:
///   u8 (0x80 | n), n bytes of class name (n <= 120 accepted, as MRPT),
///   u8 version, payload, u8 end marker 0x88.
/// The null object (MRPT's WriteObject(nullptr)) is the name "nullptr" with
/// no version and no payload, followed by the end marker.
/// Streams written before MRPT 0.5.5 use the older framing, also read here:
///   u32 name length (< 128; its high byte bits are 0), the name,
///   i32 version (0..254), payload, and no end marker.
///
/// Primitives follow MRPT: little-endian scalars, bool as one byte (any
/// nonzero value is true), strings as u32 length + bytes, std::vector of
/// scalars as u32 count + elements, matrices (CMatrixD, CMatrixF payloads) as
/// u32 rows, u32 cols and the coefficients row by row.

#include <Eigen/Core>

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "rove/serialization/archive.h"

namespace rove {

/// The byte MRPT writes after every object's payload.
inline constexpr std::uint8_t kMrptEndMarker = 0x88;

/// The header of one MRPT object record.
struct MrptObjectHeader {
  std::string class_name;      ///< e.g. "CSensoryFrame"; "nullptr" for the null object
  std::uint8_t version = 0;    ///< serialization version of the payload (0 for the null object)
  std::uint64_t offset = 0;    ///< byte offset of the header's first byte
  bool is_null = false;        ///< MRPT's null object: no payload follows
  bool old_format = false;     ///< pre-0.5.5 framing: no end marker follows the payload
};

/// Reads an object header at the current position (see the file comment).
/// Throws rove::ParseError with the offset (and the class, once read) on
/// truncated or malformed data.
MrptObjectHeader read_mrpt_object_header(InArchive& ar);

/// Reads the end marker closing the object of `header`; nothing for the old
/// framing. Throws rove::ParseError naming the class and the marker's offset
/// when it is missing, i.e. when the payload reader read too much or too little.
void expect_mrpt_end_marker(InArchive& ar, const MrptObjectHeader& header);

/// Throws rove::ParseError naming the class, the version and the offset of
/// `header`: for payload readers meeting a version they do not know.
[[noreturn]] void throw_unknown_mrpt_version(const InArchive& ar, const MrptObjectHeader& header);

/// Reads a bool as MRPT stores it (one byte, nonzero is true).
bool read_mrpt_bool(InArchive& ar, std::string_view field);

/// Reads a string as MRPT stores it: u32 length, bytes.
std::string read_mrpt_string(InArchive& ar, std::string_view field);

/// Reads std::vector<std::string> as MRPT stores it: u32 count, strings.
std::vector<std::string> read_mrpt_string_vector(InArchive& ar, std::string_view field);

/// Reads std::vector<bool> as MRPT stores it: u32 count, one byte each.
std::vector<bool> read_mrpt_bool_vector(InArchive& ar, std::string_view field);

/// Reads a std::vector of scalars (and CVectorFloat / CVectorDouble) as MRPT
/// stores them: u32 count, then the elements little-endian.
template <FixedScalar T>
std::vector<T> read_mrpt_vector(InArchive& ar, std::string_view field) {
  const std::uint32_t n = ar.read_length(field, sizeof(T));
  std::vector<T> out;
  ar.append_scalars(out, n, field);
  return out;
}

/// Reads the preamble MRPT's generic STL container serialization writes
/// (stl_serialization.h): the container name (e.g. "std::vector"), then the
/// element type names (e.g. "double"; key and value for maps), then a u32
/// count, which is returned after checking it against the limits at one byte
/// per element. Throws rove::ParseError naming `field` when a name differs
/// from the expected one.
std::uint32_t read_mrpt_container_preamble(InArchive& ar, std::string_view container,
                                           std::initializer_list<std::string_view> type_names,
                                           std::string_view field);

/// Reads a matrix payload as CMatrixD (S = double) and CMatrixF (S = float)
/// write it, version 0: u32 rows, u32 cols, coefficients row-major.
template <FixedScalar S>
Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> read_mrpt_matrix(InArchive& ar,
                                                                  std::string_view field) {
  const std::uint64_t at = ar.offset();
  const auto rows = ar.read_scalar<std::uint32_t>(field);
  const auto cols = ar.read_scalar<std::uint32_t>(field);
  const std::uint64_t n = std::uint64_t{rows} * cols;
  ar.check_length(rows, 0, field, at);
  ar.check_length(cols, 0, field, at);
  ar.check_length(n, sizeof(S), field, at);
  using Dyn = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  if (n == 0) return Dyn(rows, cols);  // no coefficient to touch
  std::vector<S> data;
  ar.append_scalars(data, n, field);
  using RowMajor = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(data.data(), rows, cols);
}

}  // namespace rove
