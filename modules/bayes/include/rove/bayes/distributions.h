#pragma once
/// \file
/// The normal and chi-square distribution functions the filters need:
/// quantiles for KLD-sampling's sample size, Mahalanobis gates and
/// consistency (NEES/NIS) bounds, and the chi-square CDF for tests of fit.
/// Double precision, accurate to a few ulps over the ranges used (the
/// quantiles are refined by Newton/Halley steps on the CDF).

namespace rove {

/// Φ(x): the standard normal CDF, computed as erfc(−x/√2)/2 (accurate in
/// both tails). Precondition (InvalidArgument): x is not NaN.
double normal_cdf(double x);

/// Φ⁻¹(p): the standard normal quantile. Acklam's rational approximation
/// refined by two Halley steps on normal_cdf (relative error ≈ 1e-15).
/// p = 0 gives −inf, p = 1 gives +inf.
/// Precondition (InvalidArgument): 0 ≤ p ≤ 1.
double normal_quantile(double p);

/// P(X ≤ x) for X ~ χ²(dof): the regularized lower incomplete gamma
/// function P(dof/2, x/2) (series below a+1, Lentz's continued fraction
/// above). 0 for x ≤ 0.
/// Preconditions (InvalidArgument): dof > 0 and finite; x not NaN.
double chi_square_cdf(double x, double dof);

/// The exact χ² quantile: the x with chi_square_cdf(x, dof) = p, found by
/// safeguarded Newton iteration from the Wilson–Hilferty value. p = 0 gives
/// 0, p = 1 gives +inf.
/// Preconditions (InvalidArgument): 0 ≤ p ≤ 1; dof > 0 and finite.
double chi_square_quantile(double p, double dof);

/// The Wilson–Hilferty approximation of the χ² quantile,
/// dof · (1 − 2/(9 dof) + z_p · √(2/(9 dof)))³ with z_p = Φ⁻¹(p)
/// (Wilson & Hilferty 1931; the form Fox uses for KLD-sampling and MRPT's
/// math::chi2inv). Within 1 % of the exact quantile for p = 0.99 and
/// dof ≥ 3; poor for small dof at small p. Clamped at 0.
/// Preconditions (InvalidArgument): 0 < p < 1; dof > 0 and finite.
double chi_square_quantile_wilson_hilferty(double p, double dof);

}  // namespace rove
