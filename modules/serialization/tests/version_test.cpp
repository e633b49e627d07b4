#include "rove/serialization/version.h"

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/serialization/stl.h"
#include "test_util.h"

namespace demo {

// A user record in its own namespace, serialized through ADL. Version 1
// stored x, y; version 2 added the stamp and the tags.
struct Odometry {
  double x = 0, y = 0;
  std::int64_t stamp_ns = 0;
  std::vector<std::string> tags;
  bool operator==(const Odometry&) const = default;
};

void save(rove::OutArchive& ar, const Odometry& o) {
  rove::write_version(ar, 2);
  ar << o.x << o.y << o.stamp_ns << o.tags;
}

void load(rove::InArchive& ar, Odometry& o) {
  const auto v = rove::read_version(ar, "Odometry", 2);
  ar >> o.x >> o.y;
  if (v >= 2) {
    ar >> o.stamp_ns >> o.tags;
  } else {
    o.stamp_ns = 0;
    o.tags.clear();
  }
}

}  // namespace demo

namespace rove {
namespace {

using test::bytes_of;
using test::from_hex;
using test::load_from;
using test::round_trip;
using test::to_hex;

TEST(Version, CurrentVersionRoundTrips) {
  const demo::Odometry o{1.5, -2.0, 123456789, {"wheel", "imu"}};
  EXPECT_EQ(round_trip(o), o);
  const std::vector<demo::Odometry> many{o, {}, o};
  EXPECT_EQ(round_trip(many), many);
}

TEST(Version, FrozenVersion2Bytes) {
  const demo::Odometry o{1.0, 2.0, 3, {"a"}};
  EXPECT_EQ(to_hex(bytes_of(o)),
            "02 00 00 00 00 00 00 f0 3f 00 00 00 00 00 00 00 40 03 00 00 00 00 00 00 00 "
            "01 00 00 00 01 00 00 00 61");
}

// A record written by version 1 (frozen bytes) still loads.
TEST(Version, OldVersion1RecordStillLoads) {
  const auto v1 = from_hex("01 00 00 00 00 00 00 f0 3f 00 00 00 00 00 00 00 40");
  const demo::Odometry o = load_from<demo::Odometry>(v1);
  EXPECT_EQ(o, (demo::Odometry{1.0, 2.0, 0, {}}));
}

TEST(Version, NewerVersionIsRejectedNamingTypeVersionAndOffset) {
  const auto bytes = from_hex("aa 03 00 00 00 00 00 00 f0 3f 00 00 00 00 00 00 00 40");
  MemoryInStream in(std::span<const std::byte>(bytes), "odo.bin");
  InArchive ar(in);
  EXPECT_EQ(ar.read_scalar<std::uint8_t>(), 0xaa);
  demo::Odometry o;
  try {
    ar >> o;
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, "odo.bin");
    EXPECT_EQ(e.location().offset, 1u);
    EXPECT_EQ(e.location().field, "Odometry");
    EXPECT_NE(e.problem().find("Odometry version 3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rove
