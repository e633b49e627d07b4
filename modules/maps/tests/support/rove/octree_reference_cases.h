#pragma once
// The random query points and rays of the OctoMap reference files
// (data/reference/octomap/), generated the same way by the reference tool
// (tools/octomap_reference, which links OctoMap) and by rove's tests, so the
// files hold only OctoMap's answers. Integer arithmetic (SplitMix64) and
// exactly specified float operations: the same inputs on every machine.
// Plain C++: the tool includes it without rove.
#include <cstddef>
#include <cstdint>

namespace rove::octree_reference {

/// Bumped whenever the generation below changes (the files record it).
inline constexpr std::uint32_t kCasesVersion = 1;

/// SplitMix64 (Steele, Lea, Flood 2014).
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// A float in [0, 1): 24 random bits, exact.
  float unit() { return static_cast<float>(next() & 0xFFFFFFu) / 16777216.0f; }
};

/// An axis-aligned box, float as OctoMap's points.
struct Box {
  float lo[3];
  float hi[3];
};

/// A point drawn uniformly in `b`.
inline void random_point(SplitMix64& g, const Box& b, float out[3]) {
  for (int k = 0; k < 3; ++k) {
    const float t = g.unit();
    out[k] = b.lo[k] + t * (b.hi[k] - b.lo[k]);
  }
}

/// One castRay case.
struct RayCase {
  float origin[3];
  float direction[3];
  bool ignore_unknown;
  double max_range;
};

/// Ray i: origin uniform in `b`, direction uniform in [-1, 1)^3 (every 50th
/// along ±y, every 50th offset by 13 along ±x), ignore_unknown and
/// max_range (−1, 2 or 10 m; ignore_unknown rays without a range limit are
/// one in 16, as they run to the edge of the tree) from further draws.
inline RayCase random_ray(SplitMix64& g, const Box& b, std::size_t i) {
  RayCase c{};
  random_point(g, b, c.origin);
  for (float& d : c.direction) d = 2.0f * g.unit() - 1.0f;
  if (i % 50 == 7) c.direction[0] = 0.0f, c.direction[1] = (i % 100 == 7) ? 1.0f : -1.0f, c.direction[2] = 0.0f;
  if (i % 50 == 13) c.direction[0] = (i % 100 == 13) ? 1.0f : -1.0f, c.direction[1] = 0.0f, c.direction[2] = 0.0f;
  const std::uint64_t r = g.next();
  c.ignore_unknown = (r & 1u) != 0;
  const std::uint64_t sel = (r >> 8) % 16;
  if (c.ignore_unknown) {
    c.max_range = sel == 0 ? -1.0 : (sel < 8 ? 2.0 : 10.0);
  } else {
    c.max_range = sel < 5 ? -1.0 : (sel < 10 ? 2.0 : 10.0);
  }
  return c;
}

}  // namespace rove::octree_reference
