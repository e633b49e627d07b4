#include "rove/serialization/archive.h"

#include <fmt/format.h>

#include <algorithm>

#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {

void OutArchive::write_length(std::size_t n, std::string_view field) {
  ROVE_CHECK_MSG(n <= std::numeric_limits<std::uint32_t>::max(),
                 "{} holds {} elements; rove archives store at most 2^32-1", field, n);
  write_scalar(static_cast<std::uint32_t>(n));
}

void InArchive::read_bytes(std::span<std::byte> out, std::string_view field) {
  if (out.empty()) return;
  const std::uint64_t start = offset();
  std::size_t got = 0;
  if (has_pending_) {
    out[0] = pending_;
    has_pending_ = false;
    got = 1;
  }
  while (got < out.size()) {
    const std::size_t n = stream_.read_some(out.subspan(got));
    if (n == 0) break;
    got += n;
  }
  if (got < out.size()) {
    fail_at(start, field,
            fmt::format("unexpected end of data: needed {} bytes, only {} left", out.size(), got));
  }
}

std::uint32_t InArchive::read_length(std::string_view field, std::uint64_t min_bytes_per_element) {
  const std::uint64_t at = offset();
  const auto n = read_scalar<std::uint32_t>(field);
  check_length(n, min_bytes_per_element, field, at);
  return n;
}

void InArchive::check_length(std::uint64_t n, std::uint64_t min_bytes_per_element,
                             std::string_view field, std::uint64_t at_offset) const {
  if (n > limits_.max_length) {
    fail_at(at_offset, field,
            fmt::format("declared length {} exceeds the limit of {}", n, limits_.max_length));
  }
  if (min_bytes_per_element == 0) return;
  if (const auto left = remaining(); left && n > *left / min_bytes_per_element) {
    fail_at(at_offset, field,
            fmt::format("declared length {} needs at least {} bytes but only {} remain", n,
                        n * min_bytes_per_element, *left));
  }
}

bool InArchive::at_end() {
  if (has_pending_) return false;
  std::byte b{};
  if (stream_.read_some(std::span<std::byte>(&b, 1)) == 0) return true;
  pending_ = b;
  has_pending_ = true;
  return false;
}

std::optional<std::uint64_t> InArchive::remaining() const {
  auto r = stream_.remaining();
  if (r && has_pending_) *r += 1;
  return r;
}

void InArchive::fail(std::string_view field, std::string problem) const {
  fail_at(offset(), field, std::move(problem));
}

void InArchive::fail_at(std::uint64_t at_offset, std::string_view field,
                        std::string problem) const {
  throw ParseError({source_name(), std::nullopt, at_offset, std::string(field)},
                   std::move(problem));
}

InArchive::NestingGuard::NestingGuard(InArchive& ar, std::string_view field) : ar_(ar) {
  if (ar_.depth_ >= ar_.limits_.max_nesting) {
    ar_.fail(field, fmt::format("objects nested deeper than the limit of {}",
                                ar_.limits_.max_nesting));
  }
  ++ar_.depth_;
}

void save(OutArchive& ar, const std::string& value) {
  ar.write_length(value.size(), "string");
  ar.write_bytes(std::as_bytes(std::span<const char>(value.data(), value.size())));
}

void load(InArchive& ar, std::string& value) {
  const std::uint32_t n = ar.read_length("string length", 1);
  value.clear();
  // Grow chunk by chunk: a length that no data backs costs at most one chunk.
  constexpr std::size_t kChunk = 65536;
  std::size_t done = 0;
  while (done < n) {
    const std::size_t k = std::min<std::size_t>(n - done, kChunk);
    value.resize(done + k);
    ar.read_bytes(std::as_writable_bytes(std::span<char>(value.data() + done, k)), "string");
    done += k;
  }
}

}  // namespace rove
