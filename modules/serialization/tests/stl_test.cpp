#include "rove/serialization/stl.h"

#include <gtest/gtest.h>

#include <string>

#include "rove/core/error.h"
#include "test_util.h"

namespace rove {
namespace {

using test::bytes_of;
using test::from_hex;
using test::load_from;
using test::round_trip;
using test::to_hex;

TEST(Stl, SequencesRoundTrip) {
  const std::vector<double> vd{1.0, -2.5, 1e300};
  EXPECT_EQ(round_trip(vd), vd);
  const std::vector<std::int16_t> vi(70000, -7);  // more than one bulk chunk
  EXPECT_EQ(round_trip(vi), vi);
  const std::vector<bool> vb{true, false, true, true};
  EXPECT_EQ(round_trip(vb), vb);
  const std::vector<std::string> vs{"a", "", "ccc"};
  EXPECT_EQ(round_trip(vs), vs);
  const std::list<std::int32_t> l{3, 1, 2};
  EXPECT_EQ(round_trip(l), l);
  const std::deque<std::uint64_t> d{5, 6};
  EXPECT_EQ(round_trip(d), d);
  const std::vector<std::vector<float>> nested{{1.f}, {}, {2.f, 3.f}};
  EXPECT_EQ(round_trip(nested), nested);
  EXPECT_EQ(round_trip(std::vector<std::uint8_t>{}), std::vector<std::uint8_t>{});
}

TEST(Stl, AssociativeContainersRoundTrip) {
  const std::set<std::string> s{"x", "y"};
  EXPECT_EQ(round_trip(s), s);
  const std::multiset<std::int32_t> ms{1, 1, 2};
  EXPECT_EQ(round_trip(ms), ms);
  const std::unordered_set<std::int64_t> us{4, 5, 6};
  EXPECT_EQ(round_trip(us), us);
  const std::map<std::string, std::vector<double>> m{{"a", {1.0}}, {"b", {}}};
  EXPECT_EQ(round_trip(m), m);
  const std::multimap<std::int32_t, std::string> mm{{1, "one"}, {1, "uno"}, {2, "two"}};
  EXPECT_EQ(round_trip(mm), mm);
  const std::unordered_map<std::uint32_t, bool> um{{1, true}, {7, false}};
  EXPECT_EQ(round_trip(um), um);
}

TEST(Stl, ProductTypesRoundTrip) {
  const std::pair<std::int8_t, std::string> p{-3, "p"};
  EXPECT_EQ(round_trip(p), p);
  const std::tuple<double, std::uint16_t, std::vector<bool>> t{0.5, 9, {false}};
  EXPECT_EQ(round_trip(t), t);
  const std::array<float, 3> a{1.f, 2.f, 3.f};
  EXPECT_EQ(round_trip(a), a);
  const std::optional<std::string> some = "v";
  EXPECT_EQ(round_trip(some), some);
  const std::optional<std::int32_t> none;
  EXPECT_EQ(round_trip(none), none);
}

// Pinned layouts of containers.
TEST(Stl, FrozenContainerLayouts) {
  EXPECT_EQ(to_hex(bytes_of(std::vector<std::uint16_t>{1, 0x0203})), "02 00 00 00 01 00 03 02");
  EXPECT_EQ(to_hex(bytes_of(std::vector<bool>{true, false})), "02 00 00 00 01 00");
  EXPECT_EQ(to_hex(bytes_of(std::map<std::uint8_t, std::int16_t>{{2, -1}, {1, 5}})),
            "02 00 00 00 01 05 00 02 ff ff");
  EXPECT_EQ(to_hex(bytes_of(std::optional<std::uint8_t>{7})), "01 07");
  EXPECT_EQ(to_hex(bytes_of(std::optional<std::uint8_t>{})), "00");
  EXPECT_EQ(to_hex(bytes_of(std::array<std::uint8_t, 2>{9, 8})), "02 00 00 00 09 08");
  EXPECT_EQ(to_hex(bytes_of(std::pair<std::uint8_t, std::string>{1, "a"})),
            "01 01 00 00 00 61");

  const auto m = load_from<std::map<std::uint8_t, std::int16_t>>(
      from_hex("02 00 00 00 01 05 00 02 ff ff"));
  EXPECT_EQ(m, (std::map<std::uint8_t, std::int16_t>{{1, 5}, {2, -1}}));
}

TEST(Stl, DuplicateKeysAreRejectedWithTheirOffset) {
  const auto bytes = from_hex("02 00 00 00 01 05 00 01 06 00");
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  std::map<std::uint8_t, std::int16_t> m;
  try {
    ar >> m;
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 7u);
    EXPECT_EQ(e.location().field, "map");
  }
  EXPECT_THROW(load_from<std::set<std::uint8_t>>(from_hex("02 00 00 00 04 04")), ParseError);
  // A multiset keeps them.
  EXPECT_EQ(load_from<std::multiset<std::uint8_t>>(from_hex("02 00 00 00 04 04")).size(), 2u);
}

TEST(Stl, ArrayWithAnotherStoredSizeIsRejected) {
  EXPECT_THROW((load_from<std::array<std::uint8_t, 3>>(from_hex("02 00 00 00 09 08"))),
               ParseError);
}

TEST(Stl, HugeDeclaredCountsAreRejectedBeforeAllocating) {
  // 2^32-1 doubles declared, 8 bytes present.
  const auto bytes = from_hex("ff ff ff ff 00 00 00 00 00 00 f0 3f");
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in, ArchiveLimits{.max_length = ~std::uint64_t{0}});
  std::vector<double> v;
  try {
    ar >> v;
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 0u);
    EXPECT_EQ(e.location().field, "vector");
  }
  // Nested: every inner vector needs at least its 4-byte count.
  EXPECT_THROW(load_from<std::vector<std::vector<double>>>(from_hex("03 00 00 00 00 00 00 00")),
               ParseError);
  // Map entries need at least key + value bytes.
  EXPECT_THROW((load_from<std::map<std::uint64_t, double>>(from_hex("01 00 00 00 01 02 03"))),
               ParseError);
}

TEST(Stl, EveryTruncationOfANestedStreamIsAParseError) {
  const std::map<std::string, std::vector<std::optional<double>>> value{
      {"alpha", {1.0, std::nullopt}}, {"b", {}}, {"c", {std::nullopt, -3.0}}};
  const auto bytes = bytes_of(value);
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    MemoryInStream in(std::span<const std::byte>(bytes.data(), k), "cut.bin");
    InArchive ar(in);
    std::map<std::string, std::vector<std::optional<double>>> back;
    try {
      ar >> back;
      ADD_FAILURE() << "prefix of " << k << " bytes loaded";
    } catch (const ParseError& e) {
      ASSERT_TRUE(e.location().offset.has_value());
      EXPECT_LE(*e.location().offset, k);
    }
  }
  EXPECT_EQ(load_from<std::remove_const_t<decltype(value)>>(bytes), value);
}

}  // namespace
}  // namespace rove
