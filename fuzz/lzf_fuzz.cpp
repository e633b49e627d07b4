// libFuzzer target for rove's LZF: the first 2 bytes give an output size;
// decompressing the rest must succeed or throw rove::ParseError, and
// compressing any input must decompress back to it.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <span>
#include <vector>

#include "rove/core/error.h"
#include "rove/io/lzf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t out_size = static_cast<std::size_t>(data[0]) << 8 | data[1];
  const std::span<const std::uint8_t> in(data + 2, size - 2);
  std::vector<std::uint8_t> out(out_size);
  try {
    rove::lzf_decompress(in, out);
  } catch (const rove::ParseError&) {
  }
  const std::vector<std::uint8_t> packed = rove::lzf_compress(in);
  std::vector<std::uint8_t> back(in.size());
  rove::lzf_decompress(packed, back);
  if (!std::equal(back.begin(), back.end(), in.begin())) {
    std::fprintf(stderr, "lzf_fuzz: compress/decompress round trip failed\n");
    std::abort();
  }
  return 0;
}
