#include "pcd_io_common.h"

#include <charconv>

#include "rove/core/error.h"

namespace rove::detail {

std::size_t scalar_size(ScalarKind k) noexcept {
  switch (k) {
    case ScalarKind::I8: case ScalarKind::U8: return 1;
    case ScalarKind::I16: case ScalarKind::U16: return 2;
    case ScalarKind::I32: case ScalarKind::U32: case ScalarKind::F32: return 4;
    case ScalarKind::I64: case ScalarKind::U64: case ScalarKind::F64: return 8;
  }
  return 0;
}

namespace {
template <typename T>
T load_as(const std::uint8_t* p, bool swap) noexcept {
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}
}  // namespace

double load_scalar(const std::uint8_t* p, ScalarKind k, bool swap) noexcept {
  switch (k) {
    case ScalarKind::I8: return load_as<std::int8_t>(p, swap);
    case ScalarKind::U8: return load_as<std::uint8_t>(p, swap);
    case ScalarKind::I16: return load_as<std::int16_t>(p, swap);
    case ScalarKind::U16: return load_as<std::uint16_t>(p, swap);
    case ScalarKind::I32: return load_as<std::int32_t>(p, swap);
    case ScalarKind::U32: return load_as<std::uint32_t>(p, swap);
    case ScalarKind::I64: return static_cast<double>(load_as<std::int64_t>(p, swap));
    case ScalarKind::U64: return static_cast<double>(load_as<std::uint64_t>(p, swap));
    case ScalarKind::F32: return load_as<float>(p, swap);
    case ScalarKind::F64: return load_as<double>(p, swap);
  }
  return 0;
}

void append_float(std::string& out, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, r.ptr);
}

void split_tokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

}  // namespace rove::detail
