// Place recognition by bit-sampling LSH of binary descriptors.
#include "rove/vision/place_recognition.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "rove/core/check.h"

namespace rove {

void BinaryPlaceOptions::check() const {
  ROVE_CHECK_MSG(tables >= 1 && tables <= 64, "tables must be in 1..64, got {}", tables);
  ROVE_CHECK_MSG(bits >= 1 && bits <= 32, "bits must be in 1..32, got {}", bits);
}

BinaryPlaceIndex::BinaryPlaceIndex(const BinaryPlaceOptions& options) : options_(options) {
  options_.check();
  std::mt19937_64 rng(options_.seed);
  std::vector<std::uint8_t> all(256);
  std::iota(all.begin(), all.end(), std::uint8_t{0});
  for (int t = 0; t < options_.tables; ++t) {
    std::shuffle(all.begin(), all.end(), rng);
    bit_of_.emplace_back(all.begin(), all.begin() + options_.bits);
  }
  buckets_.resize(static_cast<std::size_t>(options_.tables));
}

std::uint32_t BinaryPlaceIndex::key(const OrbDescriptor& d, int table) const noexcept {
  std::uint32_t k = 0;
  for (const std::uint8_t b : bit_of_[static_cast<std::size_t>(table)]) {
    k = (k << 1) | ((d[b >> 3] >> (b & 7)) & 1u);
  }
  return k;
}

void BinaryPlaceIndex::add(std::size_t id, std::span<const OrbDescriptor> descriptors) {
  ROVE_CHECK_MSG(!slot_of_.contains(id), "place {} was added already", id);
  const auto slot = static_cast<std::uint32_t>(place_ids_.size());
  slot_of_.emplace(id, slot);
  place_ids_.push_back(id);
  place_sizes_.push_back(descriptors.size());
  for (int t = 0; t < options_.tables; ++t) {
    auto& table = buckets_[static_cast<std::size_t>(t)];
    for (const OrbDescriptor& d : descriptors) {
      std::vector<std::uint32_t>& bucket = table[key(d, t)];
      if (bucket.empty() || bucket.back() != slot) bucket.push_back(slot);  // once per place
    }
  }
}

std::vector<PlaceCandidate> BinaryPlaceIndex::query(std::span<const OrbDescriptor> descriptors,
                                                    std::size_t max_results, std::size_t min_votes) const {
  std::vector<std::size_t> votes(place_ids_.size(), 0);
  // The last query descriptor that voted for each slot: one vote per
  // descriptor and place, however many tables agree.
  std::vector<std::size_t> voted_by(place_ids_.size(), static_cast<std::size_t>(-1));
  for (std::size_t q = 0; q < descriptors.size(); ++q) {
    for (int t = 0; t < options_.tables; ++t) {
      const auto& table = buckets_[static_cast<std::size_t>(t)];
      const auto it = table.find(key(descriptors[q], t));
      if (it == table.end()) continue;
      for (const std::uint32_t slot : it->second) {
        if (voted_by[slot] == q) continue;
        voted_by[slot] = q;
        ++votes[slot];
      }
    }
  }
  std::vector<PlaceCandidate> out;
  for (std::size_t s = 0; s < place_ids_.size(); ++s) {
    if (votes[s] == 0 || votes[s] < min_votes) continue;
    const double norm = std::sqrt(static_cast<double>(descriptors.size()) * static_cast<double>(place_sizes_[s]));
    out.push_back({place_ids_[s], votes[s], norm > 0.0 ? static_cast<double>(votes[s]) / norm : 0.0});
  }
  std::sort(out.begin(), out.end(), [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.score != b.score ? a.score > b.score : a.place < b.place;
  });
  if (out.size() > max_results) out.resize(max_results);
  return out;
}

}  // namespace rove
