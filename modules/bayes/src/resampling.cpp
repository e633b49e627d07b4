#include "rove/bayes/resampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"
#include "rove/math/statistics.h"

namespace rove {

namespace {

/// Adds to `counts` one copy for each point of the nondecreasing sequence
/// produced by `point(k)`, k in [0, n): the particle whose cumulative-weight
/// interval holds the point. The walk never passes the last particle of
/// positive weight, so points rounded up to 1 still land on a valid one.
template <typename Point>
void count_points(std::span<const double> w, std::size_t n, std::vector<std::uint32_t>& counts,
                  Point&& point) {
  std::size_t last = w.size() - 1;
  while (last > 0 && !(w[last] > 0.0)) --last;
  std::size_t j = 0;
  double c = w[0];
  for (std::size_t k = 0; k < n; ++k) {
    const double u = point(k);
    while (u >= c && j < last) c += w[++j];
    ++counts[j];
  }
}

/// n multinomial draws from the normalized weights `w`, as n sorted uniforms
/// made from exponential spacings: with Eₖ ~ Exp(1) and Sₖ = E₁ + … + Eₖ,
/// (S₁, …, Sₙ)/Sₙ₊₁ are distributed as the order statistics of n uniforms
/// (Devroye, "Non-Uniform Random Variate Generation", 1986, V.2).
void multinomial_counts(std::span<const double> w, std::size_t n, Rng& rng,
                        std::vector<std::uint32_t>& counts) {
  std::vector<double> s(n + 1);
  double acc = 0.0;
  for (auto& v : s) v = (acc += -std::log(rng.uniform_positive()));
  const double inv_total = 1.0 / acc;
  count_points(w, n, counts, [&](std::size_t k) { return s[k] * inv_total; });
}

void check_n_out(std::size_t n_out) {
  ROVE_CHECK_MSG(n_out >= 1 && n_out < (std::size_t{1} << 32),
                 "resampling needs 1 <= n_out < 2^32, got {}", n_out);
}

}  // namespace

std::string_view mrpt_name(ResamplingMethod method) {
  switch (method) {
    case ResamplingMethod::Multinomial: return "prMultinomial";
    case ResamplingMethod::Residual: return "prResidual";
    case ResamplingMethod::Stratified: return "prStratified";
    case ResamplingMethod::Systematic: return "prSystematic";
  }
  ROVE_CHECK_MSG(false, "unknown ResamplingMethod {}", static_cast<int>(method));
  return {};
}

std::vector<std::uint32_t> resampling_counts(ResamplingMethod method,
                                             std::span<const double> log_weights,
                                             std::size_t n_out, Rng& rng) {
  check_n_out(n_out);
  const std::vector<double> w = weights_from_log_weights(log_weights);
  std::vector<std::uint32_t> counts(w.size(), 0);
  const double n = static_cast<double>(n_out);
  switch (method) {
    case ResamplingMethod::Multinomial:
      multinomial_counts(w, n_out, rng, counts);
      break;
    case ResamplingMethod::Residual: {
      std::vector<double> residual(w.size());
      std::size_t fixed = 0;
      for (std::size_t i = 0; i < w.size(); ++i) {
        const double copies = std::floor(n * w[i]);
        counts[i] = static_cast<std::uint32_t>(copies);
        fixed += counts[i];
        residual[i] = n * w[i] - copies;
      }
      ROVE_CHECK_LE(fixed, n_out);
      const std::size_t rest = n_out - fixed;
      if (rest > 0) {
        double sum = 0.0;
        for (const double r : residual) sum += r;
        // The residuals sum to `rest` up to rounding; renormalize them.
        for (auto& r : residual) r /= sum;
        multinomial_counts(residual, rest, rng, counts);
      }
      break;
    }
    case ResamplingMethod::Stratified:
      count_points(w, n_out, counts,
                   [&](std::size_t k) { return (static_cast<double>(k) + rng.uniform()) / n; });
      break;
    case ResamplingMethod::Systematic: {
      const double u = rng.uniform();
      count_points(w, n_out, counts,
                   [&](std::size_t k) { return (static_cast<double>(k) + u) / n; });
      break;
    }
    default:
      ROVE_CHECK_MSG(false, "unknown ResamplingMethod {}", static_cast<int>(method));
  }
  return counts;
}

std::vector<std::size_t> indices_from_counts(std::span<const std::uint32_t> counts) {
  std::size_t total = 0;
  for (const auto c : counts) total += c;
  std::vector<std::size_t> out;
  out.reserve(total);
  for (std::size_t i = 0; i < counts.size(); ++i) out.insert(out.end(), counts[i], i);
  return out;
}

std::vector<std::size_t> resample_indices(ResamplingMethod method,
                                          std::span<const double> log_weights,
                                          std::size_t n_out, Rng& rng) {
  return indices_from_counts(resampling_counts(method, log_weights, n_out, rng));
}

std::vector<double> cumulative_weights(std::span<const double> log_weights) {
  std::vector<double> c = weights_from_log_weights(log_weights);
  std::size_t last = c.size() - 1;
  while (last > 0 && !(c[last] > 0.0)) --last;
  for (std::size_t i = 1; i < c.size(); ++i) c[i] += c[i - 1];
  std::fill(c.begin() + static_cast<std::ptrdiff_t>(last), c.end(), 1.0);
  return c;
}

std::size_t draw_from_cumulative(std::span<const double> cumulative, double u) {
  ROVE_CHECK_MSG(!cumulative.empty(), "no weights to draw from");
  // First entry with cᵢ > u: particle i's interval [cᵢ₋₁, cᵢ) holds u; zero
  // weights have empty intervals and are skipped. The last entry is 1 > u.
  const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
  return std::min(static_cast<std::size_t>(it - cumulative.begin()), cumulative.size() - 1);
}

CumulativeSampler::CumulativeSampler(std::span<const double> log_weights)
    : cumulative_(cumulative_weights(log_weights)) {
  const std::size_t n = cumulative_.size();
  ROVE_CHECK_MSG(n < (std::size_t{1} << 32), "{} weights: at most 2^32 - 1", n);
  guide_.resize(n);
  std::size_t i = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const double start = static_cast<double>(j) / static_cast<double>(n);
    while (i + 1 < n && cumulative_[i] <= start) ++i;
    guide_[j] = static_cast<std::uint32_t>(i);
  }
}

std::size_t CumulativeSampler::draw(double u) const {
  ROVE_CHECK_MSG(u >= 0.0 && u < 1.0, "a draw needs u in [0, 1), got {}", u);
  const std::size_t n = cumulative_.size();
  const auto slices = static_cast<double>(n);
  std::size_t j = std::min(static_cast<std::size_t>(u * slices), n - 1);
  // u · N may round up to the next slice; the slice's start must not pass u
  // (the same expression as in the constructor, so the comparison is exact).
  while (j > 0 && static_cast<double>(j) / slices > u) --j;
  std::size_t i = guide_[j];
  while (i + 1 < n && cumulative_[i] <= u) ++i;
  return i;
}

}  // namespace rove
