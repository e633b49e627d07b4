#pragma once
/// \file
/// LZF compression (Marc Lehmann's liblzf format), as PCD's
/// binary_compressed data uses it. Implemented from the format description:
/// the stream is a sequence of chunks, each starting with a control byte c:
///  - c < 32: a literal run; the next c + 1 bytes are copied to the output;
///  - c >= 32: a back reference of length L = (c >> 5) + 2, where a top
///    value of 7 means one more byte follows and is added to L; then one
///    byte o, and the L bytes are copied from 1 + ((c & 31) << 8 | o) bytes
///    back in the output (the copy may overlap what it produces).
/// So a reference reaches at most 8192 bytes back and copies 3..264 bytes.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace rove {

/// Decompresses `in` into exactly `out.size()` bytes. Throws ParseError
/// (naming `source` and the byte offset base_offset + position in `in`,
/// field "lzf") when the stream is truncated, refers before the start of
/// the output, or produces more or fewer bytes than out.size(). Never reads
/// or writes outside the two spans.
void lzf_decompress(std::span<const std::uint8_t> in, std::span<std::uint8_t> out,
                    std::string_view source = "<lzf>", std::uint64_t base_offset = 0);

/// Compresses `in` into a valid LZF stream (greedy matching with a hash of
/// the next three bytes). The output is at most in.size() + in.size() / 32
/// + 1 bytes. Deterministic.
std::vector<std::uint8_t> lzf_compress(std::span<const std::uint8_t> in);

}  // namespace rove
