#pragma once
/// \file
/// Sequential RANSAC: finds several models in one data set by running
/// ransac() repeatedly, each time removing the inliers of the model found
/// (Vincent, Laganière, "Detecting planar homographies in an image pair",
/// ISPA 2001). The building block of detect_planes() and detect_lines().

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/math/ransac.h"

namespace rove {

/// Options of detect_sequential().
struct SequentialDetectionOptions {
  /// Options of each RANSAC round; round k uses a seed derived from
  /// ransac.seed and k, so the whole detection is deterministic.
  RansacOptions ransac;
  /// A model needs at least this many inliers to be reported, and the search
  /// stops when fewer data remain (≥ the problem's sample size). Default 30.
  std::size_t min_inliers = 30;
  /// Most models reported (≥ 1). Default 10.
  std::size_t max_models = 10;
};

/// Why detect_sequential() stopped.
enum class DetectionTermination {
  MaxModels,     ///< max_models models were found
  TooFewData,    ///< fewer than min_inliers data remained unassigned
  NoSupportedModel,  ///< the best remaining model had fewer than min_inliers
                     ///< inliers, or RANSAC found no model (degenerate data)
};

/// Name of a termination reason ("MaxModels", ...).
std::string_view to_string(DetectionTermination t);

/// One model found by detect_sequential().
template <typename Model>
struct Detection {
  /// The model, refit on its inliers when the problem supports refit().
  Model model;
  /// Indices into the full input of this model's inliers, ascending. Each
  /// datum belongs to at most one detection (the earliest that claimed it).
  std::vector<std::size_t> inliers;
  /// Root mean square of the inliers' distances to the model.
  double rms_distance = 0.0;
  /// Samples RANSAC drew for this model.
  std::size_t ransac_iterations = 0;
  /// How that RANSAC round ended (Converged or MaxIterations).
  RansacTermination ransac_termination = RansacTermination::Converged;
};

/// Outcome of detect_sequential().
template <typename Model>
struct SequentialDetectionResult {
  /// Models in the order found (decreasing support, as a rule).
  std::vector<Detection<Model>> detections;
  /// Indices of the data assigned to no model, ascending.
  std::vector<std::size_t> unassigned;
  /// Why the search stopped.
  DetectionTermination termination = DetectionTermination::TooFewData;
  /// One line explaining the termination.
  std::string message;
};

namespace detail {
/// SplitMix64 finalizer: decorrelated per-round seeds from one user seed.
constexpr std::uint64_t mix_seed(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}
}  // namespace detail

/// Finds up to max_models models of `problem` in `data`: RANSAC on the data
/// not yet assigned, keep the best model if it has ≥ min_inliers inliers,
/// remove them, repeat. Preconditions (InvalidArgument): options valid,
/// min_inliers ≥ sample_size(), max_models ≥ 1.
template <RansacProblem P>
SequentialDetectionResult<typename P::Model> detect_sequential(
    const P& problem, std::span<const typename P::Datum> data,
    const SequentialDetectionOptions& options) {
  using Datum = typename P::Datum;
  detail::check_ransac_options(options.ransac);
  ROVE_CHECK_GE(options.min_inliers, static_cast<std::size_t>(problem.sample_size()));
  ROVE_CHECK_GE(options.max_models, std::size_t{1});

  SequentialDetectionResult<typename P::Model> result;
  std::vector<std::size_t> remaining(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) remaining[i] = i;
  std::vector<Datum> subset;
  std::vector<char> taken;

  bool stopped = false;
  for (std::size_t round = 0; round < options.max_models && !stopped; ++round) {
    if (remaining.size() < options.min_inliers) {
      result.termination = DetectionTermination::TooFewData;
      result.message = fmt::format("{} models found; {} data remain, fewer than min_inliers = {}",
                                   result.detections.size(), remaining.size(),
                                   options.min_inliers);
      stopped = true;
      break;
    }
    subset.clear();
    for (std::size_t i : remaining) subset.push_back(data[i]);
    RansacOptions round_options = options.ransac;
    round_options.seed = detail::mix_seed(options.ransac.seed + round);
    auto found = ransac(problem, std::span<const Datum>(subset), round_options);
    if (!found.model || found.inliers.size() < options.min_inliers) {
      result.termination = DetectionTermination::NoSupportedModel;
      result.message =
          found.model
              ? fmt::format("{} models found; the best next model has {} inliers, fewer than "
                            "min_inliers = {}",
                            result.detections.size(), found.inliers.size(), options.min_inliers)
              : fmt::format("{} models found; no further model: {}", result.detections.size(),
                            found.message);
      stopped = true;
      break;
    }

    Detection<typename P::Model> detection;
    detection.model = *found.model;
    detection.ransac_iterations = found.iterations;
    detection.ransac_termination = found.termination;
    double sum_sq = 0.0;
    taken.assign(remaining.size(), 0);
    detection.inliers.reserve(found.inliers.size());
    for (std::size_t k : found.inliers) {
      const double d = static_cast<double>(problem.distance(detection.model, subset[k]));
      sum_sq += d * d;
      detection.inliers.push_back(remaining[k]);  // ascending: remaining is ascending
      taken[k] = 1;
    }
    detection.rms_distance = std::sqrt(sum_sq / static_cast<double>(found.inliers.size()));
    std::size_t kept = 0;
    for (std::size_t k = 0; k < remaining.size(); ++k) {
      if (!taken[k]) remaining[kept++] = remaining[k];
    }
    remaining.resize(kept);
    result.detections.push_back(std::move(detection));
  }
  if (!stopped) {
    result.termination = DetectionTermination::MaxModels;
    result.message = fmt::format("found max_models = {} models; {} data unassigned",
                                 options.max_models, remaining.size());
  }
  result.unassigned = std::move(remaining);
  return result;
}

}  // namespace rove
