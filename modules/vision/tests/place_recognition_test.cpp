// Place recognition by LSH of binary descriptors: a noisy view of a place
// is found among many, random descriptors find nothing, bad use is refused.
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/vision/place_recognition.h"

namespace rove {
namespace {

std::vector<OrbDescriptor> random_descriptors(std::size_t n, std::mt19937& rng) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<OrbDescriptor> out(n);
  for (OrbDescriptor& d : out) {
    for (auto& b : d) b = static_cast<std::uint8_t>(byte(rng));
  }
  return out;
}

// The same scene seen again: each descriptor with `flips` bits flipped, and
// a share `replaced` of them replaced by unrelated ones.
std::vector<OrbDescriptor> revisit(std::vector<OrbDescriptor> d, int flips, double replaced, std::mt19937& rng) {
  std::uniform_int_distribution<int> bit(0, 255);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (OrbDescriptor& x : d) {
    if (u(rng) < replaced) {
      x = random_descriptors(1, rng)[0];
      continue;
    }
    for (int k = 0; k < flips; ++k) {
      const int b = bit(rng);
      x[static_cast<std::size_t>(b >> 3)] ^= static_cast<std::uint8_t>(1u << (b & 7));
    }
  }
  return d;
}

TEST(BinaryPlaceIndex, FindsANoisyRevisitAmongFiftyPlaces) {
  std::mt19937 rng(3);
  BinaryPlaceIndex index;
  std::vector<std::vector<OrbDescriptor>> places;
  for (std::size_t p = 0; p < 50; ++p) {
    places.push_back(random_descriptors(500, rng));
    index.add(100 + p, places.back());
  }
  EXPECT_EQ(index.size(), 50u);
  for (const std::size_t p : {0u, 17u, 49u}) {
    // 12 of 256 bits flipped (ORB's distance between views of one point is
    // often 10-40), 40 % of the features not seen again.
    const auto q = revisit(places[p], 12, 0.4, rng);
    const auto best = index.query(q, 3);
    ASSERT_EQ(best.size(), 3u);
    EXPECT_EQ(best[0].place, 100 + p);
    EXPECT_GT(best[0].score, 5.0 * best[1].score) << best[0].score << " vs " << best[1].score;
    EXPECT_GT(best[0].votes, 100u);
  }
}

TEST(BinaryPlaceIndex, UnrelatedDescriptorsScoreNearZero) {
  std::mt19937 rng(5);
  BinaryPlaceIndex index;
  for (std::size_t p = 0; p < 20; ++p) index.add(p, random_descriptors(500, rng));
  const auto q = random_descriptors(500, rng);
  for (const PlaceCandidate& c : index.query(q, 20)) EXPECT_LT(c.score, 0.05) << c.place;
  EXPECT_TRUE(index.query(q, 20, 50).empty());  // none reaches 50 votes
  EXPECT_TRUE(index.query({}, 5).empty());
}

TEST(BinaryPlaceIndex, RefusesDuplicateIdsAndBadOptions) {
  std::mt19937 rng(9);
  BinaryPlaceIndex index;
  index.add(3, random_descriptors(10, rng));
  EXPECT_THROW(index.add(3, random_descriptors(10, rng)), InvalidArgument);
  BinaryPlaceOptions o;
  o.bits = 0;
  EXPECT_THROW(BinaryPlaceIndex{o}, InvalidArgument);
  o.bits = 20;
  o.tables = 65;
  EXPECT_THROW(BinaryPlaceIndex{o}, InvalidArgument);
}

}  // namespace
}  // namespace rove
