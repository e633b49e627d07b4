// Frozen bytes of version-1 records, written out by hand from the documented
// encoding (little-endian; strings and vectors as u32 count + elements). They
// pin the on-disk format: a change that breaks reading old files fails here.

#include <gtest/gtest.h>

#include <cstddef>
#include <string_view>
#include <vector>

#include "rove/obs/obs_registry.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/angle.h"
#include "rove/serialization/memory_stream.h"
#include "rove/serialization/object_io.h"

namespace rove {
namespace {

std::vector<std::byte> from_hex(std::string_view hex) {
  std::vector<std::byte> out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    const auto digit = [](char c) { return c <= '9' ? c - '0' : c - 'a' + 10; };
    out.push_back(static_cast<std::byte>(digit(hex[i]) * 16 + digit(hex[i + 1])));
  }
  return out;
}

// RangeScan2D v1: timestamp 1000 ns, label "L", identity sensor pose,
// ranges {1.5, 2}, valid {1, 0}, no intensity, aperture π, right to left,
// max_range 80, std_error 0.01, beam_aperture 0.25°.
constexpr std::string_view kScanV1 =
    "0b00000052616e67655363616e32440101e803000000000000010000004c0000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000200"
    "00000000c03f0000004002000000010000000000182d4454fb210940010000a0"
    "420ad7233c35fa8e3b88";

// OdometryObservation v1: invalid timestamp, empty label, identity pose,
// odometry (1, 2, 0.5), encoder ticks {-7, 12}, no velocity.
constexpr std::string_view kOdometryV1 =
    "130000004f646f6d657472794f62736572766174696f6e010100000000000000"
    "8000000000000000000000f03f00000000000000000000000000000000000000"
    "0000000000000000000000f03f00000000000000000000000000000000000000"
    "0000000000000000000000f03f00000000000000000000000000000000000000"
    "0000000000000000000000f03f0000000000000040000000000000e03f0101f9"
    "ffffff0c0000000088";

template <typename T>
void expect_frozen(const T& expected, std::string_view hex) {
  register_obs_classes();
  const std::vector<std::byte> bytes = from_hex(hex);
  MemoryInStream in(bytes, "frozen");
  InArchive ia(in);
  const std::unique_ptr<T> read = read_object_as<T>(ia);
  EXPECT_TRUE(ia.at_end());
  EXPECT_TRUE(*read == expected);
  MemoryOutStream out;
  OutArchive oa(out);
  write_object(oa, expected);
  EXPECT_TRUE(out.data() == bytes);  // the writer still produces the frozen bytes
}

TEST(FrozenFormat, RangeScan2DVersion1) {
  RangeScan2D s;
  s.timestamp = Timestamp::from_ns(1000);
  s.sensor_label.push_back('L');  // (GCC 12 flags `= "L"` with a false -Wrestrict under ASan)
  s.ranges = {1.5f, 2.0f};
  s.valid = {true, false};
  s.aperture = kPi;
  expect_frozen(s, kScanV1);
}

TEST(FrozenFormat, OdometryObservationVersion1) {
  OdometryObservation o;
  o.odometry = Pose2(1.0, 2.0, 0.5);
  o.encoder_ticks = EncoderTicks{-7, 12};
  expect_frozen(o, kOdometryV1);
}

}  // namespace
}  // namespace rove
