#pragma once
/// \file
/// Place recognition on binary descriptors without a trained vocabulary:
/// locality-sensitive hashing of ORB descriptors by bit sampling (Indyk and
/// Motwani, STOC 1998; the scheme FLANN's LSH index uses for binary
/// features). Each of `tables` hash tables keys a descriptor by `bits` of
/// its 256 bits, drawn at random once; two descriptors of the same scene
/// point (Hamming distance d) share a key in one table with probability
/// (1 − d/256)^bits, unrelated ones (d ≈ 128) with 2^−bits. A query votes,
/// for each of its descriptors, once for every place that shares a key with
/// it in any table; places are ranked by their votes over the geometric
/// mean of the two descriptor counts (a place with many descriptors gets
/// no advantage from its size alone).
///
///   rove::BinaryPlaceIndex index;                 // 12 tables of 20 bits
///   index.add(0, keyframe0.descriptors);
///   auto best = index.query(frame.descriptors, 3); // places by score
///
/// Not thread-safe for add(); query() is const.

#include <cstddef>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "rove/vision/orb.h"

namespace rove {

/// Options of BinaryPlaceIndex.
struct BinaryPlaceOptions {
  int tables = 12;          ///< hash tables (1–64)
  int bits = 20;            ///< sampled bits per key (1–32)
  std::uint64_t seed = 7;   ///< the bits' draw
  /// Throws InvalidArgument for values out of range.
  void check() const;
};

/// A place and how much a query resembles it.
struct PlaceCandidate {
  std::size_t place = 0;     ///< the id given to add()
  std::size_t votes = 0;     ///< query descriptors that met one of the place's in some table
  double score = 0.0;        ///< votes / √(query size × place size), in [0, 1]
};

/// An index of places (e.g. keyframes), each a set of binary descriptors.
class BinaryPlaceIndex {
 public:
  explicit BinaryPlaceIndex(const BinaryPlaceOptions& options = {});

  /// Adds place `id` (ids need not be contiguous; adding one twice is an
  /// InvalidArgument).
  void add(std::size_t id, std::span<const OrbDescriptor> descriptors);

  /// The `max_results` places with the highest scores (ties by smaller
  /// id), at least `min_votes` votes each. An empty query gives none.
  std::vector<PlaceCandidate> query(std::span<const OrbDescriptor> descriptors, std::size_t max_results,
                                    std::size_t min_votes = 1) const;

  /// Places added.
  std::size_t size() const noexcept { return place_sizes_.size(); }

 private:
  std::uint32_t key(const OrbDescriptor& d, int table) const noexcept;

  BinaryPlaceOptions options_;
  std::vector<std::vector<std::uint8_t>> bit_of_;  // per table: the sampled bit positions (0–255)
  std::vector<std::unordered_map<std::uint32_t, std::vector<std::uint32_t>>> buckets_;  // key → slots
  std::vector<std::size_t> place_ids_;             // slot → id
  std::vector<std::size_t> place_sizes_;           // slot → descriptors
  std::unordered_map<std::size_t, std::uint32_t> slot_of_;
};

}  // namespace rove
