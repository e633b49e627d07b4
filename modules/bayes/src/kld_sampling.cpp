#include "rove/bayes/kld_sampling.h"

#include <algorithm>
#include <cmath>

#include "rove/bayes/distributions.h"
#include "rove/bayes/random.h"
#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {

void KldOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(bin_size_xy) && bin_size_xy > 0.0,
                 "KLD_binSize_XY must be finite and > 0, got {}", bin_size_xy);
  ROVE_CHECK_MSG(std::isfinite(bin_size_phi) && bin_size_phi > 0.0,
                 "KLD_binSize_PHI must be finite and > 0, got {} rad", bin_size_phi);
  ROVE_CHECK_MSG(delta > 0.0 && delta < 1.0, "KLD_delta must be in (0, 1), got {}", delta);
  ROVE_CHECK_MSG(std::isfinite(epsilon) && epsilon > 0.0,
                 "KLD_epsilon must be finite and > 0, got {}", epsilon);
  ROVE_CHECK_MSG(min_sample_size >= 1, "KLD_minSampleSize must be >= 1, got {}", min_sample_size);
  ROVE_CHECK_MSG(max_sample_size >= min_sample_size,
                 "KLD_maxSampleSize ({}) must be >= KLD_minSampleSize ({})", max_sample_size,
                 min_sample_size);
  ROVE_CHECK_MSG(std::isfinite(min_samples_per_bin) && min_samples_per_bin >= 0.0,
                 "KLD_minSamplesPerBin must be finite and >= 0, got {}", min_samples_per_bin);
}

KldOptions KldOptions::from_config(const ConfigSection& section) {
  KldOptions o;
  const IniFile& ini = section.ini();
  const std::string& s = section.name();
  o.bin_size_xy = ini.get_or<double>(s, "KLD_binSize_XY", o.bin_size_xy);
  o.bin_size_phi = ini.get_or<double>(s, "KLD_binSize_PHI", o.bin_size_phi * 180.0 / std::numbers::pi) *
                   std::numbers::pi / 180.0;
  o.delta = ini.get_or<double>(s, "KLD_delta", o.delta);
  o.epsilon = ini.get_or<double>(s, "KLD_epsilon", o.epsilon);
  o.min_sample_size = ini.get_or<unsigned>(s, "KLD_minSampleSize", o.min_sample_size);
  o.max_sample_size = ini.get_or<unsigned>(s, "KLD_maxSampleSize", o.max_sample_size);
  o.min_samples_per_bin = ini.get_or<double>(s, "KLD_minSamplesPerBin", o.min_samples_per_bin);
  section.ignore({"KLD_binSize_PHI_deg"},
                 "MRPT 2.5 reads KLD_binSize_PHI (degrees), not this key");
  section.check_all_read();
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), s, "", e.message());
  }
  return o;
}

double kld_bound(std::size_t occupied_bins, const KldOptions& options) {
  options.check();
  if (occupied_bins <= 1) return 0.0;
  const double dof = static_cast<double>(occupied_bins - 1);
  return chi_square_quantile_wilson_hilferty(1.0 - options.delta, dof) / (2.0 * options.epsilon);
}

std::size_t kld_target_count(std::size_t occupied_bins, std::size_t previous_bins,
                             const KldOptions& options) {
  const double bound = kld_bound(occupied_bins, options);
  const double per_bin = std::round(options.min_samples_per_bin * static_cast<double>(previous_bins));
  const double lo = std::max(static_cast<double>(options.min_sample_size), per_bin);
  const double target = std::min(std::max(std::round(bound), lo),
                                 static_cast<double>(options.max_sample_size));
  return static_cast<std::size_t>(target);
}

namespace {
std::int64_t bin_index(double v, double size, const char* what) {
  ROVE_CHECK_MSG(std::isfinite(v), "KLD bin of a non-finite {}: {}", what, v);
  // Clamped so that absurd coordinates still give a valid (shared) bin.
  constexpr double kLimit = 4.0e18;
  return static_cast<std::int64_t>(std::clamp(std::round(v / size), -kLimit, kLimit));
}
}  // namespace

KldBin kld_bin(double x, double y, double phi, const KldOptions& options) {
  return {bin_index(x, options.bin_size_xy, "x"), bin_index(y, options.bin_size_xy, "y"),
          bin_index(phi, options.bin_size_phi, "phi")};
}

KldBin kld_bin(const SE2d& pose, const KldOptions& options) {
  return kld_bin(pose.translation().x(), pose.translation().y(), pose.angle(), options);
}

std::size_t KldBinHash::operator()(const KldBin& b) const noexcept {
  std::uint64_t h = splitmix64_mix(static_cast<std::uint64_t>(b.x));
  h = splitmix64_mix(h ^ static_cast<std::uint64_t>(b.y));
  h = splitmix64_mix(h ^ static_cast<std::uint64_t>(b.phi));
  return static_cast<std::size_t>(h);
}

bool KldBinSet::insert(const KldBin& bin) {
  if (2 * (size_ + 1) > slots_.size()) grow();
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = KldBinHash{}(bin) & mask;; i = (i + 1) & mask) {
    if (!used_[i]) {
      slots_[i] = bin;
      used_[i] = 1;
      ++size_;
      return true;
    }
    if (slots_[i] == bin) return false;
  }
}

void KldBinSet::clear() noexcept {
  std::fill(used_.begin(), used_.end(), std::uint8_t{0});
  size_ = 0;
}

void KldBinSet::grow() {
  std::vector<KldBin> old_slots = std::move(slots_);
  std::vector<std::uint8_t> old_used = std::move(used_);
  const std::size_t capacity = old_slots.empty() ? 64 : 2 * old_slots.size();
  slots_.assign(capacity, KldBin{});
  used_.assign(capacity, 0);
  size_ = 0;
  for (std::size_t i = 0; i < old_slots.size(); ++i) {
    if (old_used[i]) insert(old_slots[i]);
  }
}

}  // namespace rove
