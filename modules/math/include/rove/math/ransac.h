#pragma once
/// \file
/// Generic RANSAC (Fischler, Bolles, "Random sample consensus", CACM 1981)
/// with the adaptive number of iterations of Hartley & Zisserman, "Multiple
/// View Geometry", 2nd ed., Sec. 4.7.1, Eq. (4.18): N = log(1−p) / log(1−wˢ).
///
/// The problem is a type satisfying RansacProblem: it names its Model and
/// Datum, its minimal sample size, fits 0..k models to a minimal sample and
/// measures the distance of a datum to a model. Optionally it rejects
/// degenerate samples before fitting and refits a model to all its inliers.
/// ransac() is deterministic for a given seed (std::mt19937_64 and a
/// portable bounded-integer draw, so results agree across standard
/// libraries).

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {

/// What a RANSAC problem provides (all members const):
///  - `Model`, `Datum` types;
///  - `sample_size()`: the minimal number of data to fit a model (≥ 1);
///  - `fit(std::span<const Datum> sample, std::vector<Model>& models)`:
///    appends 0..k models through the minimal sample (none when it has no
///    well-defined fit);
///  - `distance(const Model&, const Datum&) -> double`: a datum is an inlier
///    when its distance is ≤ the threshold; NaN is never an inlier.
/// Optional members, used when present:
///  - `is_degenerate(std::span<const Datum> sample) -> bool`: skip a sample
///    before fitting;
///  - `refit(std::span<const Datum> inliers, Model& model) -> bool`: least
///    squares on the inliers, returns false when it cannot refit.
template <typename P>
concept RansacProblem =
    requires(const P& p, std::span<const typename P::Datum> sample,
             std::vector<typename P::Model>& models, const typename P::Model& m,
             const typename P::Datum& d) {
      { p.sample_size() } -> std::convertible_to<std::size_t>;
      p.fit(sample, models);
      { p.distance(m, d) } -> std::convertible_to<double>;
    };

/// Options of ransac(). Defaults are documented per field.
struct RansacOptions {
  /// Inlier threshold on the problem's distance (its units; > 0). No default
  /// fits every problem: 0.05 suits metric point-to-model distances in m.
  double distance_threshold = 0.05;
  /// Probability p ∈ (0, 1) that at least one sample is outlier-free when the
  /// adaptive iteration count is reached. Default 0.99.
  double success_probability = 0.99;
  /// Hard cap on the number of samples drawn (≥ 1). Default 1000.
  std::size_t max_iterations = 1000;
  /// Samples always drawn, even if the adaptive count is lower
  /// (≤ max_iterations). Default 0.
  std::size_t min_iterations = 0;
  /// Seed of the std::mt19937_64 that draws the samples.
  std::uint64_t seed = 42;
  /// Rounds of (refit on inliers, recount inliers) after sampling, each kept
  /// only if it does not lose inliers; used when the problem has refit().
  /// Default 3; 0 disables refitting.
  int max_refit_rounds = 3;
};

/// Why ransac() stopped.
enum class RansacTermination {
  Converged,      ///< the adaptive iteration count for p was reached
  MaxIterations,  ///< the cap was hit before the adaptive count; best model kept
  NotEnoughData,  ///< fewer data than the minimal sample size; no model
  Degenerate,     ///< every sample was degenerate or gave no model; no model
};

/// Name of a termination reason ("Converged", ...).
std::string_view to_string(RansacTermination t);

/// Outcome of ransac().
template <typename Model>
struct RansacResult {
  /// Best model; empty when termination is NotEnoughData or Degenerate.
  std::optional<Model> model;
  /// Indices into the data of the model's inliers, ascending.
  std::vector<std::size_t> inliers;
  /// Number of minimal samples drawn.
  std::size_t iterations = 0;
  /// Why the search stopped.
  RansacTermination termination = RansacTermination::NotEnoughData;
  /// One line explaining the termination.
  std::string message;
};

/// Number of samples N = ⌈log(1−p) / log(1−wˢ)⌉ that draws, with probability
/// p, at least one sample of s inliers when a fraction w of the data are
/// inliers (Hartley & Zisserman, Eq. (4.18)). Returns 0 for w = 1 and
/// SIZE_MAX when no finite N exists (w = 0 or wˢ below double precision).
/// Preconditions: w ∈ [0, 1], s ≥ 1, p ∈ (0, 1).
std::size_t ransac_required_iterations(double inlier_ratio, std::size_t sample_size,
                                       double success_probability);

namespace detail {

/// Uniform integer in [0, n) from a 64-bit engine, by rejection sampling
/// (same sequence on every standard library, unlike
/// std::uniform_int_distribution). Precondition: n ≥ 1.
inline std::size_t uniform_index(std::mt19937_64& rng, std::size_t n) {
  const std::uint64_t range = static_cast<std::uint64_t>(n);
  // Largest multiple of range that fits: reject draws at or above it.
  const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() -
                              std::numeric_limits<std::uint64_t>::max() % range;
  std::uint64_t v = rng();
  while (v >= limit) v = rng();
  return static_cast<std::size_t>(v % range);
}

/// Checks the options shared by every RANSAC-based algorithm.
void check_ransac_options(const RansacOptions& options);

template <typename P>
concept HasDegeneracyCheck = requires(const P& p, std::span<const typename P::Datum> s) {
  { p.is_degenerate(s) } -> std::convertible_to<bool>;
};

template <typename P>
concept HasRefit = requires(const P& p, std::span<const typename P::Datum> s,
                            typename P::Model& m) {
  { p.refit(s, m) } -> std::convertible_to<bool>;
};

/// Inliers of `model` (ascending indices) and the sum of their distances.
template <RansacProblem P>
std::size_t collect_inliers(const P& problem, const typename P::Model& model,
                            std::span<const typename P::Datum> data, double threshold,
                            std::vector<std::size_t>& inliers, double& distance_sum) {
  inliers.clear();
  distance_sum = 0.0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double d = static_cast<double>(problem.distance(model, data[i]));
    if (d <= threshold) {  // false for NaN
      inliers.push_back(i);
      distance_sum += d;
    }
  }
  return inliers.size();
}

}  // namespace detail

/// Robustly fits one model of `problem` to `data`.
///
/// Draws minimal samples without replacement; a model's score is its inlier
/// count, ties broken by the smaller sum of inlier distances. After each
/// improvement the needed count N (ransac_required_iterations with the best
/// inlier ratio so far) is updated; sampling stops after
/// max(N, min_iterations) samples or max_iterations, whichever comes first.
/// Degenerate samples count as iterations. If the problem has refit(), the
/// best model is then refit on its inliers (see RansacOptions).
/// Preconditions (InvalidArgument): options valid, sample_size() ≥ 1.
template <RansacProblem P>
RansacResult<typename P::Model> ransac(const P& problem,
                                       std::span<const typename P::Datum> data,
                                       const RansacOptions& options) {
  using Model = typename P::Model;
  using Datum = typename P::Datum;
  detail::check_ransac_options(options);
  const std::size_t s = static_cast<std::size_t>(problem.sample_size());
  ROVE_CHECK_GE(s, std::size_t{1});

  RansacResult<Model> result;
  const std::size_t n = data.size();
  if (n < s) {
    result.termination = RansacTermination::NotEnoughData;
    result.message = fmt::format("{} data, fewer than the minimal sample of {}", n, s);
    return result;
  }

  std::mt19937_64 rng(options.seed);
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::vector<Datum> sample(s);
  std::vector<Model> models;
  std::vector<std::size_t> inliers;
  double best_distance_sum = std::numeric_limits<double>::infinity();
  std::size_t needed = options.max_iterations;
  std::size_t degenerate = 0;

  std::size_t it = 0;
  while (it < options.max_iterations && it < std::max(needed, options.min_iterations)) {
    ++it;
    // Partial Fisher-Yates: the first s entries become a uniform sample
    // without replacement, whatever permutation `order` held before.
    for (std::size_t k = 0; k < s; ++k) {
      const std::size_t j = k + detail::uniform_index(rng, n - k);
      std::swap(order[k], order[j]);
      sample[k] = data[order[k]];
    }
    const std::span<const Datum> sample_span(sample);
    if constexpr (detail::HasDegeneracyCheck<P>) {
      if (problem.is_degenerate(sample_span)) {
        ++degenerate;
        continue;
      }
    }
    models.clear();
    problem.fit(sample_span, models);
    if (models.empty()) {
      ++degenerate;
      continue;
    }
    for (const Model& m : models) {
      double distance_sum = 0.0;
      const std::size_t count = detail::collect_inliers(problem, m, data,
                                                        options.distance_threshold, inliers,
                                                        distance_sum);
      const std::size_t best = result.inliers.size();
      if (!result.model || count > best || (count == best && distance_sum < best_distance_sum)) {
        result.model = m;
        result.inliers.swap(inliers);
        best_distance_sum = distance_sum;
        const double w = static_cast<double>(result.inliers.size()) / static_cast<double>(n);
        needed = ransac_required_iterations(w, s, options.success_probability);
      }
    }
  }
  result.iterations = it;

  if (!result.model) {
    result.termination = RansacTermination::Degenerate;
    result.message = fmt::format("all {} samples were degenerate or gave no model", it);
    return result;
  }

  if constexpr (detail::HasRefit<P>) {
    std::vector<Datum> inlier_data;
    for (int round = 0; round < options.max_refit_rounds; ++round) {
      inlier_data.clear();
      for (std::size_t i : result.inliers) inlier_data.push_back(data[i]);
      Model refined = *result.model;
      if (!problem.refit(std::span<const Datum>(inlier_data), refined)) break;
      double distance_sum = 0.0;
      const std::size_t count = detail::collect_inliers(
          problem, refined, data, options.distance_threshold, inliers, distance_sum);
      if (count < result.inliers.size()) break;
      const bool changed = inliers != result.inliers;
      result.model = refined;
      result.inliers.swap(inliers);
      if (!changed) break;
    }
  }

  const bool converged = it >= std::max(needed, options.min_iterations);
  result.termination = converged ? RansacTermination::Converged : RansacTermination::MaxIterations;
  const double ratio = static_cast<double>(result.inliers.size()) / static_cast<double>(n);
  if (converged) {
    result.message = fmt::format("{} inliers of {} ({:.1f}%) after {} samples ({} degenerate)",
                                 result.inliers.size(), n, 100.0 * ratio, it, degenerate);
  } else {
    result.message = fmt::format(
        "stopped at the cap of {} samples ({} degenerate); best model has {} inliers of {} "
        "({:.1f}%), p = {} would need {}",
        it, degenerate, result.inliers.size(), n, 100.0 * ratio, options.success_probability,
        needed == std::numeric_limits<std::size_t>::max() ? std::string("unboundedly many")
                                                          : fmt::format("{}", needed));
  }
  return result;
}

/// ransac() on a std::vector of data.
template <RansacProblem P>
RansacResult<typename P::Model> ransac(const P& problem,
                                       const std::vector<typename P::Datum>& data,
                                       const RansacOptions& options) {
  return ransac(problem, std::span<const typename P::Datum>(data), options);
}

}  // namespace rove
