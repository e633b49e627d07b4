#pragma once
// Helpers shared by the PCD and PLY readers and writers.

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace rove::detail {

/// Numeric element kinds of PCD and PLY columns.
enum class ScalarKind : std::uint8_t { I8, U8, I16, U16, I32, U32, I64, U64, F32, F64 };
std::size_t scalar_size(ScalarKind k) noexcept;

/// Value of one element stored at p (little-endian unless `swap`).
double load_scalar(const std::uint8_t* p, ScalarKind k, bool swap) noexcept;
/// The raw 32 bits of a 4-byte element (rgb fields).
inline std::uint32_t load_u32(const std::uint8_t* p, bool swap) noexcept {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return swap ? __builtin_bswap32(v) : v;
}
inline float load_f32(const std::uint8_t* p, bool swap) noexcept {
  return std::bit_cast<float>(load_u32(p, swap));
}

/// Appends the shortest decimal text that reads back to exactly v.
void append_float(std::string& out, float v);

/// Splits a line into whitespace-separated tokens (space, tab, CR).
void split_tokens(std::string_view line, std::vector<std::string_view>& tokens);

}  // namespace rove::detail
