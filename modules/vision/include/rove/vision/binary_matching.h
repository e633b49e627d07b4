#pragma once
/// \file
/// Brute-force matching of binary descriptors by Hamming distance, with
/// Lowe's ratio test (Lowe, "Distinctive image features from scale-invariant
/// keypoints", IJCV 2004, Sec. 7.1), a cross (mutual best) check, an
/// absolute distance cap and the RGB-D SLAM tutorial's relative threshold
/// (keep distance < factor · max(smallest distance, 10)).

#include <cstdint>
#include <span>
#include <vector>

#include "rove/vision/orb.h"

namespace rove {

/// One match: query descriptor i ↔ train descriptor j.
struct DescriptorMatch {
  std::uint32_t query = 0;   ///< index into the query descriptors
  std::uint32_t train = 0;   ///< index into the train descriptors
  std::uint32_t distance = 0;///< Hamming distance, bits (0..256)
};

/// Options of match_binary. The tests apply in this order: best train
/// descriptor per query, max_distance, ratio, cross check, relative factor.
struct BinaryMatchOptions {
  /// Keep a match only if best < ratio · second best; 0 disables, else in
  /// (0, 1]. Default 0.8.
  double ratio = 0.8;
  /// Keep a match only if the query is also the train descriptor's best
  /// query. Default true.
  bool cross_check = true;
  /// Largest Hamming distance kept, bits (0..256). Default 64.
  std::uint32_t max_distance = 64;
  /// The tutorial's good_match_threshold: keep distance < factor ·
  /// max(smallest kept distance, 10); 0 disables, else > 0. Default 0.
  double relative_factor = 0.0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Hamming distance of two descriptors, bits.
std::uint32_t hamming_distance(const OrbDescriptor& a, const OrbDescriptor& b) noexcept;

/// Matches each query descriptor to its nearest train descriptor, filtered
/// as the options say; the result is in increasing query order. Empty
/// inputs give no match. Precondition (InvalidArgument): options valid,
/// fewer than 2³² descriptors on each side.
std::vector<DescriptorMatch> match_binary(std::span<const OrbDescriptor> query,
                                          std::span<const OrbDescriptor> train,
                                          const BinaryMatchOptions& options = {});

}  // namespace rove
