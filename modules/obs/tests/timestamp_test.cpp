#include "rove/obs/timestamp.h"

#include <cmath>

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

TEST(Timestamp, MrptEpochOffsetIsThe1601To1970Span) {
  // 369 years, 89 of them leap years: (369·365 + 89) days · 86400 s.
  const std::uint64_t seconds = (369ULL * 365 + 89) * 86400ULL;
  EXPECT_EQ(seconds, 11644473600ULL);
  EXPECT_EQ(Timestamp::from_mrpt(seconds * 10000000ULL).ns, 0);
}

TEST(Timestamp, MrptTicksRoundTrip) {
  // 2010-01-01T00:00:00.1234567 UTC: 1262304000 s after 1970.
  const std::uint64_t ticks = 116444736000000000ULL + 1262304000ULL * 10000000ULL + 1234567ULL;
  const Timestamp t = Timestamp::from_mrpt(ticks);
  EXPECT_EQ(t.ns, 1262304000LL * 1000000000LL + 123456700LL);
  EXPECT_EQ(t.to_mrpt(), ticks);
  EXPECT_NEAR(t.to_seconds(), 1262304000.1234567, 1e-6);
}

TEST(Timestamp, InvalidMapsToMrptZero) {
  EXPECT_FALSE(Timestamp::from_mrpt(0).valid());
  EXPECT_EQ(Timestamp::invalid().to_mrpt(), 0u);
  EXPECT_THROW((void)Timestamp::invalid().to_seconds(), InvalidArgument);
  EXPECT_LT(Timestamp::invalid(), Timestamp::from_ns(-5));
}

TEST(Timestamp, ToMrptFloorsToWholeTicks) {
  EXPECT_EQ(Timestamp::from_ns(199).to_mrpt(), 116444736000000000ULL + 1);
  EXPECT_EQ(Timestamp::from_ns(-1).to_mrpt(), 116444736000000000ULL - 1);
  EXPECT_EQ(Timestamp::from_ns(-100).to_mrpt(), 116444736000000000ULL - 1);
}

TEST(Timestamp, PreEpochTicks) {
  // 1900-01-01: 2208988800 s before 1970.
  const std::uint64_t ticks = 116444736000000000ULL - 2208988800ULL * 10000000ULL;
  EXPECT_EQ(Timestamp::from_mrpt(ticks).ns, -2208988800LL * 1000000000LL);
  EXPECT_EQ(Timestamp::from_mrpt(ticks).to_mrpt(), ticks);
}

TEST(Timestamp, UnrepresentableMrptTicksAreRejected) {
  EXPECT_THROW((void)Timestamp::from_mrpt(1), InvalidArgument);  // year 1601
  EXPECT_THROW((void)Timestamp::from_mrpt(~0ULL), InvalidArgument);  // year 60056
}

TEST(Timestamp, Seconds) {
  const Timestamp t = Timestamp::from_seconds(1.5);
  EXPECT_EQ(t.ns, 1500000000);
  EXPECT_EQ(Timestamp::from_seconds(-0.25).ns, -250000000);
  EXPECT_DOUBLE_EQ(seconds_between(Timestamp::from_ns(1000), Timestamp::from_ns(2500001000)),
                   2.5);
  EXPECT_THROW((void)Timestamp::from_seconds(std::nan("")), InvalidArgument);
  EXPECT_THROW((void)Timestamp::from_seconds(1e12), InvalidArgument);
  EXPECT_THROW((void)seconds_between(Timestamp::invalid(), t), InvalidArgument);
}

}  // namespace
}  // namespace rove
