#include "rove/vision/binary_matching.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "rove/core/check.h"

namespace rove {

void BinaryMatchOptions::check() const {
  ROVE_CHECK_MSG(ratio == 0.0 || (ratio > 0.0 && ratio <= 1.0),
                 "BinaryMatchOptions: ratio = {} must be 0 (off) or in (0, 1]", ratio);
  ROVE_CHECK_LE(max_distance, 256u);
  ROVE_CHECK_MSG(relative_factor >= 0.0 && std::isfinite(relative_factor),
                 "BinaryMatchOptions: relative_factor = {} must be finite and >= 0",
                 relative_factor);
}

std::uint32_t hamming_distance(const OrbDescriptor& a, const OrbDescriptor& b) noexcept {
  std::uint32_t d = 0;
  for (std::size_t k = 0; k < 32; k += 8) {
    std::uint64_t x = 0, y = 0;
    std::memcpy(&x, a.data() + k, 8);
    std::memcpy(&y, b.data() + k, 8);
    d += static_cast<std::uint32_t>(std::popcount(x ^ y));
  }
  return d;
}

std::vector<DescriptorMatch> match_binary(std::span<const OrbDescriptor> query,
                                          std::span<const OrbDescriptor> train,
                                          const BinaryMatchOptions& options) {
  options.check();
  constexpr std::size_t kMax = std::numeric_limits<std::uint32_t>::max();
  ROVE_CHECK_LT(query.size(), kMax);
  ROVE_CHECK_LT(train.size(), kMax);
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // Best query of each train descriptor (first on ties), for the cross check.
  std::vector<std::uint32_t> train_best_query(train.size(), kNone);
  std::vector<std::uint32_t> train_best_distance(train.size(), kNone);
  std::vector<DescriptorMatch> candidates;
  candidates.reserve(query.size());
  for (std::size_t i = 0; i < query.size(); ++i) {
    std::uint32_t best = kNone, second = kNone, best_j = 0;
    for (std::size_t j = 0; j < train.size(); ++j) {
      const std::uint32_t d = hamming_distance(query[i], train[j]);
      if (d < best) {
        second = best;
        best = d;
        best_j = static_cast<std::uint32_t>(j);
      } else if (d < second) {
        second = d;
      }
      if (d < train_best_distance[j]) {
        train_best_distance[j] = d;
        train_best_query[j] = static_cast<std::uint32_t>(i);
      }
    }
    if (best == kNone || best > options.max_distance) continue;
    // With one train descriptor there is no second best: the ratio test passes.
    if (options.ratio > 0.0 && second != kNone &&
        !(static_cast<double>(best) < options.ratio * static_cast<double>(second))) {
      continue;
    }
    candidates.push_back({static_cast<std::uint32_t>(i), best_j, best});
  }
  std::vector<DescriptorMatch> kept;
  kept.reserve(candidates.size());
  for (const DescriptorMatch& m : candidates) {
    if (options.cross_check && train_best_query[m.train] != m.query) continue;
    kept.push_back(m);
  }
  if (options.relative_factor > 0.0 && !kept.empty()) {
    std::uint32_t smallest = kNone;
    for (const DescriptorMatch& m : kept) smallest = std::min(smallest, m.distance);
    const double limit = options.relative_factor * std::max(10.0, static_cast<double>(smallest));
    std::erase_if(kept, [&](const DescriptorMatch& m) { return !(m.distance < limit); });
  }
  return kept;
}

}  // namespace rove
