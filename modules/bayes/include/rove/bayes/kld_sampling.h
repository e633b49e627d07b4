#pragma once
/// \file
/// KLD-sampling: the adaptive particle count of Fox, "Adapting the sample
/// size in particle filters through KLD-sampling" (IJRR 22(12), 2003).
/// Particles are drawn one at a time and dropped into bins of a grid over the
/// state space; with k bins occupied, enough samples for the
/// Kullback–Leibler distance between the sample-based and the true
/// (binned) posterior to stay below ε with probability 1 − δ is (Fox 2003,
/// eq. 7, with the Wilson–Hilferty approximation of the χ² quantile)
///
///   n = (k − 1)/(2ε) · (1 − 2/(9(k − 1)) + √(2/(9(k − 1))) · z₁₋δ)³
///     = χ²_{k−1, 1−δ} / (2ε),
///
/// and drawing stops once n (but at least KLD_minSampleSize, at most
/// KLD_maxSampleSize) samples exist. The options carry MRPT's names
/// (TKLDParams, read from a [KLD_options] section).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/math/se2.h"

namespace rove {

/// KLD-sampling parameters (MRPT's TKLDParams, same defaults).
struct KldOptions {
  /// `KLD_binSize_XY`: bin size in x and y, meters (> 0). Default 0.2.
  double bin_size_xy = 0.2;
  /// `KLD_binSize_PHI`: bin size in heading, radians (> 0); the INI key is
  /// in degrees, as MRPT. Default 5°.
  double bin_size_phi = 5.0 * std::numbers::pi / 180.0;
  /// `KLD_delta`: probability that the KL bound fails, in (0, 1).
  /// Default 0.01.
  double delta = 0.01;
  /// `KLD_epsilon`: bound on the KL distance, > 0. Default 0.02.
  double epsilon = 0.02;
  /// `KLD_minSampleSize`: fewest particles, ≥ 1. Default 250.
  std::uint32_t min_sample_size = 250;
  /// `KLD_maxSampleSize`: most particles, ≥ min_sample_size. Default 100000.
  std::uint32_t max_sample_size = 100000;
  /// `KLD_minSamplesPerBin`: the minimum count is also at least this times
  /// the bins the previous particle set occupies, ≥ 0. Default 0.
  double min_samples_per_bin = 0.0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;

  /// Defaults overridden by the keys present in `section` (MRPT's keys:
  /// KLD_binSize_XY, KLD_binSize_PHI (degrees), KLD_delta, KLD_epsilon,
  /// KLD_minSampleSize, KLD_maxSampleSize, KLD_minSamplesPerBin).
  /// `KLD_binSize_PHI_deg`, which MRPT's own pf-localization files carry,
  /// is read by MRPT 2.5 as no key at all (it reads `KLD_binSize_PHI`, in
  /// degrees): rove accepts it without effect, as MRPT, and records it
  /// through ConfigSection::ignore so a caller can warn. Strict: any other
  /// key of the section, a malformed value or options check() rejects are a
  /// ConfigError (file, section, key).
  static KldOptions from_config(const ConfigSection& section);

  /// Exact equality.
  friend bool operator==(const KldOptions&, const KldOptions&) = default;
};

/// Fox's bound for k occupied bins: χ²_{k−1, 1−δ} / (2ε) with the
/// Wilson–Hilferty quantile (the formula above), as a real number; 0 for
/// k ≤ 1. Precondition (InvalidArgument): options.check() passes.
double kld_bound(std::size_t occupied_bins, const KldOptions& options);

/// The particle count the sampling loop must reach with k bins occupied:
/// min(max(round(kld_bound(k)), min_count), max_sample_size) where
/// min_count = max(min_sample_size, round(min_samples_per_bin ·
/// previous_bins)). `previous_bins` is the number of bins the particle set
/// before the step occupied (0 to ignore KLD_minSamplesPerBin).
/// Precondition (InvalidArgument): options.check() passes.
std::size_t kld_target_count(std::size_t occupied_bins, std::size_t previous_bins,
                             const KldOptions& options);

/// A bin of the KLD grid over (x, y, heading): MRPT's TPoseBin2D,
/// round(x / bin_size_xy), round(y / bin_size_xy), round(phi / bin_size_phi).
struct KldBin {
  std::int64_t x = 0;    ///< bin index along x
  std::int64_t y = 0;    ///< bin index along y
  std::int64_t phi = 0;  ///< bin index along the heading
  /// Equality.
  friend bool operator==(const KldBin&, const KldBin&) = default;
};

/// The bin of a planar pose (x, y in meters, phi in radians) as MRPT bins
/// it. Precondition (InvalidArgument): x, y, phi finite.
KldBin kld_bin(double x, double y, double phi, const KldOptions& options);

/// The bin of an SE2 pose (its translation and angle).
KldBin kld_bin(const SE2d& pose, const KldOptions& options);

/// Hash of a KldBin, for unordered containers.
struct KldBinHash {
  /// A 64-bit mix of the three indices.
  std::size_t operator()(const KldBin& b) const noexcept;
};

/// The set of occupied bins, counting k for Fox's formula: an
/// open-addressing table (linear probing, at most half full), so that
/// marking the bins of tens of thousands of particles per step allocates
/// a few times instead of once per bin.
class KldBinSet {
 public:
  /// Marks `bin` occupied; true if it was not before.
  bool insert(const KldBin& bin);
  /// Occupied bins k.
  std::size_t size() const noexcept { return size_; }
  /// Forgets every bin.
  void clear() noexcept;

 private:
  void grow();

  std::vector<KldBin> slots_;
  std::vector<std::uint8_t> used_;  // 1 where slots_ holds a bin
  std::size_t size_ = 0;
};

}  // namespace rove
