#include "rove/maps/point_cloud_sampling.h"

#include <algorithm>
#include <random>
#include <unordered_set>
#include <vector>

#include "rove/core/check.h"

namespace rove {

PointCloud random_downsample(const PointCloud& cloud, std::size_t count, std::uint64_t seed) {
  const std::size_t n = cloud.size();
  if (count >= n) return cloud;
  // Partial Fisher-Yates over an index permutation: the first `count`
  // entries are a uniform sample without replacement.
  std::mt19937_64 rng(seed);
  std::vector<std::size_t> perm(n);
  for (std::size_t i = 0; i < n; ++i) perm[i] = i;
  for (std::size_t i = 0; i < count; ++i) {
    std::uniform_int_distribution<std::size_t> pick(i, n - 1);
    std::swap(perm[i], perm[pick(rng)]);
  }
  perm.resize(count);
  std::sort(perm.begin(), perm.end());
  return cloud.select(perm);
}

PointCloud uniform_downsample(const PointCloud& cloud, std::size_t step) {
  ROVE_CHECK_GE(step, std::size_t{1});
  std::vector<std::size_t> keep;
  keep.reserve(cloud.size() / step + 1);
  for (std::size_t i = 0; i < cloud.size(); i += step) keep.push_back(i);
  return cloud.select(keep);
}

}  // namespace rove
