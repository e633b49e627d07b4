#include "rove/io/lzf.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

std::vector<std::uint8_t> roundtrip(const std::vector<std::uint8_t>& in) {
  const auto packed = lzf_compress(in);
  EXPECT_LE(packed.size(), in.size() + in.size() / 32 + 1);
  std::vector<std::uint8_t> out(in.size());
  lzf_decompress(packed, out);
  return out;
}

TEST(Lzf, RoundTripsRandomRepetitiveAndEmptyData) {
  std::mt19937 rng(7);
  for (std::size_t n : {0u, 1u, 2u, 3u, 4u, 31u, 32u, 33u, 100u, 5000u, 70000u}) {
    std::vector<std::uint8_t> noise(n), runs(n), text(n);
    for (std::size_t i = 0; i < n; ++i) {
      noise[i] = static_cast<std::uint8_t>(rng());
      runs[i] = static_cast<std::uint8_t>((i / 300) % 3);  // long runs: overlapping references
      text[i] = static_cast<std::uint8_t>("abcabcabd"[(i * 7 + i / 11) % 9]);
    }
    EXPECT_EQ(roundtrip(noise), noise) << n;
    EXPECT_EQ(roundtrip(runs), runs) << n;
    EXPECT_EQ(roundtrip(text), text) << n;
  }
  std::vector<std::uint8_t> zeros(100000, 0);
  EXPECT_LT(lzf_compress(zeros).size(), 1300u);  // ~264 bytes per 3-byte reference
}

TEST(Lzf, DecodesAHandWrittenStream) {
  // literal "ab", then a reference 2 back of length 5 (overlapping): "ababababa"? no:
  // ctrl = (5-2)<<5 | 0, offset byte 1 -> back 2, copies "ababa".
  const std::vector<std::uint8_t> in{1, 'a', 'b', (3 << 5) | 0, 1};
  std::vector<std::uint8_t> out(7);
  lzf_decompress(in, out);
  EXPECT_EQ(std::string(out.begin(), out.end()), "abababa");
  // long reference: ctrl top bits 7 plus an extra length byte
  const std::vector<std::uint8_t> in2{0, 'z', (7 << 5) | 0, 3, 0};  // 7+3+2 = 12 bytes, 1 back
  std::vector<std::uint8_t> out2(13);
  lzf_decompress(in2, out2);
  EXPECT_EQ(std::string(out2.begin(), out2.end()), std::string(13, 'z'));
}

TEST(Lzf, RejectsCorruptStreamsWithTheOffset) {
  std::vector<std::uint8_t> out(10);
  auto offset_of = [&](std::vector<std::uint8_t> in, std::size_t out_size) -> std::uint64_t {
    std::vector<std::uint8_t> o(out_size);
    try {
      lzf_decompress(in, o, "blob", 100);
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, "blob");
      EXPECT_EQ(e.location().field, "lzf");
      return *e.location().offset;
    }
    ADD_FAILURE() << "no error";
    return 0;
  };
  EXPECT_EQ(offset_of({5, 'a', 'b'}, 6), 100u);             // literal cut off
  EXPECT_EQ(offset_of({0, 'a', (1 << 5) | 0, 5}, 10), 102u); // reference before the start
  EXPECT_EQ(offset_of({0, 'a', (1 << 5)}, 10), 102u);        // reference cut off
  EXPECT_EQ(offset_of({0, 'a', 0xE0}, 10), 102u);            // long reference cut off
  EXPECT_EQ(offset_of({2, 'a', 'b', 'c'}, 2), 100u);         // output larger than declared
  EXPECT_EQ(offset_of({1, 'a', 'b'}, 3), 103u);              // output smaller than declared
  EXPECT_EQ(offset_of({0, 'a', (6 << 5) | 0, 0}, 5), 102u);  // reference overruns the output
}

TEST(Lzf, RandomGarbageNeverEscapesAsAnythingButParseError) {
  std::mt19937 rng(11);
  for (int t = 0; t < 2000; ++t) {
    std::vector<std::uint8_t> in(rng() % 40);
    for (auto& b : in) b = static_cast<std::uint8_t>(rng());
    std::vector<std::uint8_t> out(rng() % 300);
    try {
      lzf_decompress(in, out);
    } catch (const ParseError&) {
    }
  }
}

}  // namespace
}  // namespace rove
