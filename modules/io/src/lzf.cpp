#include "rove/io/lzf.h"

#include <algorithm>
#include <cstring>
#include <string>

#include <fmt/format.h>

#include "rove/core/error.h"

namespace rove {

namespace {
[[noreturn]] void lzf_error(std::string_view source, std::uint64_t offset, std::string problem) {
  throw ParseError({std::string(source), std::nullopt, offset, "lzf"}, std::move(problem));
}
}  // namespace

void lzf_decompress(std::span<const std::uint8_t> in, std::span<std::uint8_t> out,
                    std::string_view source, std::uint64_t base_offset) {
  std::size_t ip = 0, op = 0;
  const std::size_t in_end = in.size(), out_end = out.size();
  while (ip < in_end) {
    const std::size_t chunk_at = ip;
    const unsigned ctrl = in[ip++];
    if (ctrl < 32) {
      const std::size_t len = ctrl + 1;
      if (len > in_end - ip)
        lzf_error(source, base_offset + chunk_at,
                  fmt::format("literal run of {} bytes is cut off by the end of the compressed data", len));
      if (len > out_end - op)
        lzf_error(source, base_offset + chunk_at,
                  fmt::format("data decompresses to more than the declared {} bytes", out_end));
      std::memcpy(out.data() + op, in.data() + ip, len);
      ip += len;
      op += len;
    } else {
      std::size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_end) lzf_error(source, base_offset + chunk_at, "back reference is cut off");
        len += in[ip++];
      }
      len += 2;
      if (ip >= in_end) lzf_error(source, base_offset + chunk_at, "back reference is cut off");
      const std::size_t back = ((static_cast<std::size_t>(ctrl & 31u) << 8) | in[ip++]) + 1;
      if (back > op)
        lzf_error(source, base_offset + chunk_at,
                  fmt::format("back reference {} bytes back, but only {} bytes were produced", back, op));
      if (len > out_end - op)
        lzf_error(source, base_offset + chunk_at,
                  fmt::format("data decompresses to more than the declared {} bytes", out_end));
      std::uint8_t* dst = out.data() + op;
      const std::uint8_t* src = dst - back;
      if (back >= len) {
        std::memcpy(dst, src, len);
      } else {
        for (std::size_t k = 0; k < len; ++k) dst[k] = src[k];  // overlapping run
      }
      op += len;
    }
  }
  if (op != out_end)
    lzf_error(source, base_offset + in_end,
              fmt::format("data decompresses to {} bytes, {} declared", op, out_end));
}

std::vector<std::uint8_t> lzf_compress(std::span<const std::uint8_t> in) {
  constexpr std::size_t kMaxLiteral = 32, kMaxBack = 8192, kMaxLen = 264;
  constexpr unsigned kHashBits = 14;
  const std::size_t n = in.size();
  std::vector<std::uint8_t> out;
  out.reserve(n + n / kMaxLiteral + 1);
  std::vector<std::uint32_t> table(std::size_t{1} << kHashBits, 0);  // position + 1, 0 = none

  std::size_t lit_start = 0;
  auto flush_literals = [&](std::size_t end) {
    while (lit_start < end) {
      const std::size_t len = std::min(kMaxLiteral, end - lit_start);
      out.push_back(static_cast<std::uint8_t>(len - 1));
      out.insert(out.end(), in.begin() + static_cast<std::ptrdiff_t>(lit_start),
                 in.begin() + static_cast<std::ptrdiff_t>(lit_start + len));
      lit_start += len;
    }
  };
  auto hash_at = [&](std::size_t i) {
    const std::uint32_t v = (std::uint32_t{in[i]} << 16) | (std::uint32_t{in[i + 1]} << 8) | in[i + 2];
    return static_cast<std::size_t>((v * 2654435761u) >> (32 - kHashBits));
  };

  std::size_t i = 0;
  while (i + 2 < n) {
    const std::size_t h = hash_at(i);
    const std::uint32_t cand = table[h];
    table[h] = static_cast<std::uint32_t>(i + 1);
    if (cand != 0) {
      const std::size_t ref = cand - 1;
      const std::size_t back = i - ref;
      if (back <= kMaxBack && in[ref] == in[i] && in[ref + 1] == in[i + 1] && in[ref + 2] == in[i + 2]) {
        const std::size_t max_len = std::min(kMaxLen, n - i);
        std::size_t len = 3;
        while (len < max_len && in[ref + len] == in[i + len]) ++len;
        flush_literals(i);
        const std::size_t l = len - 2, off = back - 1;
        if (l < 7) {
          out.push_back(static_cast<std::uint8_t>((l << 5) | (off >> 8)));
        } else {
          out.push_back(static_cast<std::uint8_t>((7u << 5) | (off >> 8)));
          out.push_back(static_cast<std::uint8_t>(l - 7));
        }
        out.push_back(static_cast<std::uint8_t>(off & 0xffu));
        // Remember the positions inside the match, so later data can refer to them.
        const std::size_t end = i + len;
        for (std::size_t k = i + 1; k < end && k + 2 < n; ++k)
          table[hash_at(k)] = static_cast<std::uint32_t>(k + 1);
        i = end;
        lit_start = i;
        continue;
      }
    }
    ++i;
  }
  flush_literals(n);
  return out;
}

}  // namespace rove
