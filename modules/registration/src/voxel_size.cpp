#include "rove/registration/voxel_size.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "rove/core/check.h"

namespace rove {

std::size_t count_occupied_voxels(std::span<const Eigen::Vector3f> points, double leaf) {
  ROVE_CHECK_MSG(std::isfinite(leaf) && leaf > 0, "leaf must be finite and > 0, got {}", leaf);
  std::vector<std::uint64_t> keys;
  keys.reserve(points.size());
  const double inv = 1.0 / leaf;
  // 21 bits per axis: voxels further than 2^20 leaves from the origin share
  // keys, which only lowers the count of absurdly large scenes.
  constexpr std::int64_t kHalf = std::int64_t{1} << 20;
  constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double c = std::clamp(std::floor(static_cast<double>(p[a]) * inv),
                                  static_cast<double>(-kHalf), static_cast<double>(kHalf - 1));
      key = (key << 21) | (static_cast<std::uint64_t>(static_cast<std::int64_t>(c) + kHalf) & kMask);
    }
    keys.push_back(key);
  }
  std::sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

double suggest_voxel_size(std::span<const Eigen::Vector3f> points, std::size_t max_voxels) {
  ROVE_CHECK_GE(max_voxels, std::size_t{1});
  const auto finite = static_cast<std::size_t>(
      std::count_if(points.begin(), points.end(), [](const Eigen::Vector3f& p) { return p.allFinite(); }));
  if (finite <= max_voxels) return 0.0;
  static constexpr double kLadder[] = {0.01, 0.02, 0.025, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 2.5, 5.0};
  // The count falls as the leaf grows: find the first leaf that qualifies by
  // bisection over the ladder (four or five counts).
  std::size_t lo = 0, hi = std::size(kLadder) - 1;
  if (count_occupied_voxels(points, kLadder[hi]) > max_voxels) return kLadder[hi];
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (count_occupied_voxels(points, kLadder[mid]) <= max_voxels) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  return kLadder[lo];
}

}  // namespace rove
