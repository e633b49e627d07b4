#pragma once
/// \file
/// A small, fast, seedable random engine whose streams can be split by index,
/// so that a parallel algorithm gives the same result for any thread count:
/// work item i draws from `Rng::stream(seed, i)`, never from a shared engine.
///
/// The engine is xoshiro256** (Blackman & Vigna, "Scrambled linear
/// pseudorandom number generators", ACM TOMS 2021), 256 bits of state,
/// period 2²⁵⁶ − 1, seeded through SplitMix64 (Steele, Lea & Flood, "Fast
/// splittable pseudorandom number generators", OOPSLA 2014) so that any
/// 64-bit seed, including 0, gives a well-mixed nonzero state. A stream is the
/// engine seeded with a 64-bit hash of (seed, index); two streams overlap only
/// if their 256-bit states meet within the draws made, which for the sizes a
/// robot filter uses (≤ 2⁴⁰ draws) has probability below 2⁻¹⁷⁰.
///
/// The distributions below are written out here rather than taken from
/// <random> (whose normal_distribution differs between standard libraries),
/// so a seed gives the same numbers with every compiler, given the same libm.
///
/// Thread-safety: an Rng is a plain value; use one per thread or per work item.

#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <numbers>
#include <random>

namespace rove {

/// SplitMix64's output function: a bijective 64-bit mixer with full
/// avalanche. Used for seeding and for deriving stream seeds.
constexpr std::uint64_t splitmix64_mix(std::uint64_t z) noexcept {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// A seed for sub-stream `index` of `seed`: a hash of both, so that
/// derive_seed(s, 0), derive_seed(s, 1), ... and derive_seed(s', i) for
/// other seeds are unrelated. Use it to give each step of a filter its own
/// seed: `derive_seed(run_seed, step_index)`.
constexpr std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t index) noexcept {
  constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ULL;
  return splitmix64_mix(splitmix64_mix(seed + kGolden) ^ splitmix64_mix(index + 2 * kGolden));
}

/// xoshiro256** random engine: a UniformRandomBitGenerator (usable with
/// <random>'s distributions and std::shuffle) with deterministic uniform and
/// normal helpers.
class Rng {
 public:
  /// The type of the raw 64-bit output.
  using result_type = std::uint64_t;

  /// Seeds the state from `seed` through SplitMix64 (any seed is valid).
  explicit constexpr Rng(std::uint64_t seed = 0) noexcept {
    constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ULL;
    for (auto& word : s_) {
      seed += kGolden;
      word = splitmix64_mix(seed);
    }
  }

  /// The engine for work item `index` of a run seeded with `seed`:
  /// Rng(derive_seed(seed, index)). Streams of different indices are
  /// statistically independent; the same (seed, index) always gives the
  /// same numbers.
  static constexpr Rng stream(std::uint64_t seed, std::uint64_t index) noexcept {
    return Rng(derive_seed(seed, index));
  }

  /// Smallest raw output (0).
  static constexpr result_type min() noexcept { return 0; }
  /// Largest raw output (2⁶⁴ − 1).
  static constexpr result_type max() noexcept { return ~result_type{0}; }

  /// The next raw 64-bit output.
  constexpr result_type operator()() noexcept {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, 1), a multiple of 2⁻⁵³ (every such value equally likely).
  constexpr double uniform() noexcept {
    return static_cast<double>((*this)() >> 11) * 0x1.0p-53;
  }
  /// Uniform in [lo, hi). Precondition (unchecked): lo ≤ hi, both finite.
  constexpr double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * uniform(); }
  /// Uniform in (0, 1]: never 0, for logarithms.
  constexpr double uniform_positive() noexcept { return 1.0 - uniform(); }

  /// Uniform integer in [0, n), without bias (rejection of the top partial
  /// range). Precondition (unchecked): n ≥ 1.
  constexpr std::uint64_t uniform_index(std::uint64_t n) noexcept {
    const std::uint64_t threshold = (0 - n) % n;  // 2⁶⁴ mod n
    while (true) {
      const std::uint64_t x = (*this)();
      if (x >= threshold) return x % n;
    }
  }

  /// A standard normal sample (Box–Muller, one output per call:
  /// √(−2 ln u₁) · cos(2π u₂) with u₁ ∈ (0, 1], u₂ ∈ [0, 1)).
  double normal() noexcept {
    const double r = std::sqrt(-2.0 * std::log(uniform_positive()));
    return r * std::cos(2.0 * std::numbers::pi * uniform());
  }
  /// A normal sample with the given mean and standard deviation
  /// (Precondition, unchecked: sigma ≥ 0).
  double normal(double mean, double sigma) noexcept { return mean + sigma * normal(); }
  /// Two independent standard normal samples from one Box–Muller
  /// transform, √(−2 ln u₁) · (cos 2πu₂, sin 2πu₂): half the logarithms
  /// and square roots of two normal() calls. The first is what normal()
  /// would have given.
  std::array<double, 2> normal_pair() noexcept {
    const double r = std::sqrt(-2.0 * std::log(uniform_positive()));
    const double a = 2.0 * std::numbers::pi * uniform();
    return {r * std::cos(a), r * std::sin(a)};
  }

  /// Equality of the full state.
  friend constexpr bool operator==(const Rng&, const Rng&) = default;

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) noexcept {
    return (x << k) | (x >> (64 - k));
  }
  std::array<std::uint64_t, 4> s_{};
};

static_assert(std::uniform_random_bit_generator<Rng>);

}  // namespace rove
