#include "rove/bayes/distributions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "rove/core/check.h"

namespace rove {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Acklam's rational approximation of Φ⁻¹ (relative error < 1.15e-9), the
/// starting point of the Halley refinement.
double acklam_quantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double kLow = 0.02425;
  auto tail = [&](double q) {
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  };
  if (p < kLow) return tail(std::sqrt(-2.0 * std::log(p)));
  if (p > 1.0 - kLow) return -tail(std::sqrt(-2.0 * std::log1p(-p)));
  const double q = p - 0.5;
  const double r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

/// log of the χ²(dof) density at x > 0.
double chi_square_log_pdf(double x, double dof) {
  const double k = 0.5 * dof;
  return (k - 1.0) * std::log(x) - 0.5 * x - k * std::numbers::ln2 - std::lgamma(k);
}

/// Regularized lower incomplete gamma P(a, x) for a > 0, x > 0.
double regularized_gamma_p(double a, double x) {
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  constexpr int kMaxTerms = 100000;
  constexpr double kEps = 1e-16;
  if (x < a + 1.0) {
    // Series: P = e^{-x} x^a / Γ(a+1) Σ x^n / ((a+1)…(a+n)).
    double term = 1.0 / a, sum = term, ap = a;
    for (int n = 0; n < kMaxTerms && std::abs(term) > std::abs(sum) * kEps; ++n) {
      ap += 1.0;
      term *= x / ap;
      sum += term;
    }
    return std::min(1.0, sum * std::exp(log_prefix));
  }
  // Continued fraction for Q = 1 − P (modified Lentz).
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxTerms; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  return std::max(0.0, 1.0 - std::exp(log_prefix) * h);
}

}  // namespace

double normal_cdf(double x) {
  ROVE_CHECK_MSG(!std::isnan(x), "normal_cdf of NaN");
  return 0.5 * std::erfc(-x / std::numbers::sqrt2);
}

double normal_quantile(double p) {
  ROVE_CHECK_MSG(p >= 0.0 && p <= 1.0, "normal_quantile needs 0 <= p <= 1, got {}", p);
  if (p == 0.0) return -kInf;
  if (p == 1.0) return kInf;
  double x = acklam_quantile(p);
  // Halley steps on Φ(x) − p; in the upper tail on the complement, so that
  // p close to 1 keeps its precision.
  for (int it = 0; it < 2; ++it) {
    const double e = p < 0.5 ? normal_cdf(x) - p : (1.0 - p) - 0.5 * std::erfc(x / std::numbers::sqrt2);
    const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
    x -= u / (1.0 + 0.5 * x * u);
  }
  return x;
}

double chi_square_cdf(double x, double dof) {
  ROVE_CHECK_MSG(dof > 0.0 && std::isfinite(dof), "chi-square needs dof > 0, got {}", dof);
  ROVE_CHECK_MSG(!std::isnan(x), "chi_square_cdf of NaN");
  if (x <= 0.0) return 0.0;
  if (x == kInf) return 1.0;
  return regularized_gamma_p(0.5 * dof, 0.5 * x);
}

double chi_square_quantile_wilson_hilferty(double p, double dof) {
  ROVE_CHECK_MSG(p > 0.0 && p < 1.0, "the Wilson-Hilferty quantile needs 0 < p < 1, got {}", p);
  ROVE_CHECK_MSG(dof > 0.0 && std::isfinite(dof), "chi-square needs dof > 0, got {}", dof);
  const double v = 2.0 / (9.0 * dof);
  const double base = 1.0 - v + normal_quantile(p) * std::sqrt(v);
  return base <= 0.0 ? 0.0 : dof * base * base * base;
}

double chi_square_quantile(double p, double dof) {
  ROVE_CHECK_MSG(p >= 0.0 && p <= 1.0, "chi_square_quantile needs 0 <= p <= 1, got {}", p);
  ROVE_CHECK_MSG(dof > 0.0 && std::isfinite(dof), "chi-square needs dof > 0, got {}", dof);
  if (p == 0.0) return 0.0;
  if (p == 1.0) return kInf;
  // Bracket [lo, hi] with cdf(lo) < p ≤ cdf(hi), then Newton steps that fall
  // back to bisection when they leave the bracket.
  double lo = 0.0, hi = std::max(1.0, dof);
  while (chi_square_cdf(hi, dof) < p) {
    lo = hi;
    hi *= 2.0;
  }
  double x = std::clamp(chi_square_quantile_wilson_hilferty(p, dof), lo, hi);
  if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double f = chi_square_cdf(x, dof) - p;
    if (f == 0.0) return x;
    (f < 0.0 ? lo : hi) = x;
    double next = x - f / std::exp(chi_square_log_pdf(x, dof));
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-15 * std::max(1.0, x)) return next;
    x = next;
  }
  return x;
}

}  // namespace rove
