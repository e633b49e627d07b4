#include "rove/serialization/archive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "rove/core/error.h"
#include "rove/serialization/memory_stream.h"
#include "test_util.h"

namespace rove {
namespace {

using test::bytes_of;
using test::from_hex;
using test::round_trip;
using test::to_hex;

template <typename T>
void expect_scalar_round_trips() {
  for (const T v : {std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max(),
                    std::numeric_limits<T>::min(), T{0}, T{1}}) {
    EXPECT_EQ(round_trip(v), v);
    EXPECT_EQ(bytes_of(v).size(), sizeof(T));
  }
}

TEST(Archive, EveryScalarTypeRoundTrips) {
  expect_scalar_round_trips<std::int8_t>();
  expect_scalar_round_trips<std::uint8_t>();
  expect_scalar_round_trips<std::int16_t>();
  expect_scalar_round_trips<std::uint16_t>();
  expect_scalar_round_trips<std::int32_t>();
  expect_scalar_round_trips<std::uint32_t>();
  expect_scalar_round_trips<std::int64_t>();
  expect_scalar_round_trips<std::uint64_t>();
  expect_scalar_round_trips<float>();
  expect_scalar_round_trips<double>();
  EXPECT_EQ(round_trip(true), true);
  EXPECT_EQ(round_trip(false), false);
}

TEST(Archive, FloatSpecialValuesKeepTheirBits) {
  for (const double v : {-0.0, std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::denorm_min()}) {
    const double back = round_trip(v);
    EXPECT_EQ(std::memcmp(&back, &v, sizeof v), 0);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(round_trip(nan)));
  const float fnan = std::numeric_limits<float>::signaling_NaN();
  const float fback = round_trip(fnan);
  EXPECT_EQ(std::memcmp(&fback, &fnan, sizeof fnan), 0);
}

// The layout of every scalar, pinned: these bytes must load forever.
TEST(Archive, FrozenScalarLayoutIsLittleEndian) {
  MemoryOutStream out;
  OutArchive ar(out);
  ar << std::int8_t{-2} << std::uint8_t{0xab} << std::int16_t{-1} << std::uint16_t{0x1234}
     << std::int32_t{-5} << std::uint32_t{0xdeadbeef} << std::int64_t{-2}
     << std::uint64_t{0x0102030405060708} << 1.5f << -2.25 << true << false << std::string("hi")
     << std::string();
  const std::string expected =
      "fe ab ff ff 34 12 fb ff ff ff ef be ad de fe ff ff ff ff ff ff ff "
      "08 07 06 05 04 03 02 01 00 00 c0 3f 00 00 00 00 00 00 02 c0 01 00 "
      "02 00 00 00 68 69 00 00 00 00";
  EXPECT_EQ(to_hex(out.data()), expected);

  const auto bytes = from_hex(expected);
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ia(in);
  EXPECT_EQ(ia.read_scalar<std::int8_t>(), -2);
  EXPECT_EQ(ia.read_scalar<std::uint8_t>(), 0xab);
  EXPECT_EQ(ia.read_scalar<std::int16_t>(), -1);
  EXPECT_EQ(ia.read_scalar<std::uint16_t>(), 0x1234);
  EXPECT_EQ(ia.read_scalar<std::int32_t>(), -5);
  EXPECT_EQ(ia.read_scalar<std::uint32_t>(), 0xdeadbeefu);
  EXPECT_EQ(ia.read_scalar<std::int64_t>(), -2);
  EXPECT_EQ(ia.read_scalar<std::uint64_t>(), 0x0102030405060708u);
  EXPECT_EQ(ia.read_scalar<float>(), 1.5f);
  EXPECT_EQ(ia.read_scalar<double>(), -2.25);
  EXPECT_TRUE(ia.read_scalar<bool>());
  EXPECT_FALSE(ia.read_scalar<bool>());
  std::string s, empty = "x";
  ia >> s >> empty;
  EXPECT_EQ(s, "hi");
  EXPECT_EQ(empty, "");
  EXPECT_EQ(ia.offset(), bytes.size());
  EXPECT_TRUE(ia.at_end());
}

TEST(Archive, StringsWithAnyBytesRoundTrip) {
  std::string s("a\0b\xff", 4);
  s += std::string(100000, 'z');  // longer than one read chunk
  EXPECT_EQ(round_trip(s), s);
}

TEST(Archive, BoolOtherThanZeroOrOneIsRejectedWithOffset) {
  const auto bytes = from_hex("01 02");
  MemoryInStream in(std::span<const std::byte>(bytes), "flags.bin");
  InArchive ar(in);
  EXPECT_TRUE(ar.read_scalar<bool>("first"));
  try {
    (void)ar.read_scalar<bool>("second");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, "flags.bin");
    EXPECT_EQ(e.location().offset, 1u);
    EXPECT_EQ(e.location().field, "second");
  }
}

TEST(Archive, ReadingPastTheEndNamesTheOffset) {
  const auto bytes = from_hex("01 02 03 04 05 06");
  MemoryInStream in(std::span<const std::byte>(bytes), "short.bin");
  InArchive ar(in);
  EXPECT_EQ(ar.read_scalar<std::uint32_t>(), 0x04030201u);
  try {
    (void)ar.read_scalar<std::uint32_t>("count");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 4u);
    EXPECT_EQ(e.location().field, "count");
    EXPECT_NE(std::string(e.what()).find("short.bin"), std::string::npos);
  }
}

TEST(Archive, AtEndLooksAheadWithoutLosingTheByte) {
  const auto bytes = from_hex("2a");
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  EXPECT_FALSE(ar.at_end());
  EXPECT_EQ(ar.offset(), 0u);
  EXPECT_EQ(ar.remaining(), 1u);
  EXPECT_EQ(ar.read_scalar<std::uint8_t>(), 42);
  EXPECT_TRUE(ar.at_end());
  EXPECT_EQ(ar.offset(), 1u);
}

TEST(Archive, StringLengthBeyondTheDataIsRejectedBeforeAllocating) {
  // Declares a 4 GiB - 1 string with 3 bytes behind it.
  const auto bytes = from_hex("ff ff ff ff 61 62 63");
  MemoryInStream in(std::span<const std::byte>(bytes), "hostile.bin");
  InArchive ar(in, ArchiveLimits{.max_length = ~std::uint64_t{0}});
  std::string s;
  try {
    ar >> s;
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 0u);
    EXPECT_EQ(e.location().field, "string length");
    EXPECT_NE(e.problem().find("4294967295"), std::string::npos) << e.what();
  }
}

TEST(Archive, LengthAboveTheConfiguredCapIsRejected) {
  const auto bytes = bytes_of(std::string(11, 'q'));
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in, ArchiveLimits{.max_length = 10});
  std::string s;
  try {
    ar >> s;
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 0u);
    EXPECT_NE(e.problem().find("limit of 10"), std::string::npos) << e.what();
  }
  MemoryInStream in2{std::span<const std::byte>(bytes)};
  InArchive ar2(in2, ArchiveLimits{.max_length = 11});
  ar2 >> s;
  EXPECT_EQ(s, std::string(11, 'q'));
}

TEST(Archive, WriteLengthRejectsCountsAbove32Bits) {
  MemoryOutStream out;
  OutArchive ar(out);
  EXPECT_THROW(ar.write_length(std::size_t{1} << 32, "vector"), InvalidArgument);
  EXPECT_NO_THROW(ar.write_length(0xffffffffu, "vector"));
}

}  // namespace
}  // namespace rove
