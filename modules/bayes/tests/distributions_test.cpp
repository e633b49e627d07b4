#include "rove/bayes/distributions.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

TEST(Distributions, NormalQuantileMatchesTables) {
  // Reference values of Φ⁻¹ (17 significant digits, e.g. from R's qnorm).
  EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-16);
  EXPECT_NEAR(normal_quantile(0.975), 1.959963984540054, 1e-14);
  EXPECT_NEAR(normal_quantile(0.99), 2.326347874040841, 1e-14);
  EXPECT_NEAR(normal_quantile(0.999), 3.090232306167814, 1e-13);
  EXPECT_NEAR(normal_quantile(0.01), -2.326347874040841, 1e-14);
  EXPECT_NEAR(normal_quantile(1e-10), -6.361340902404056, 1e-11);
  EXPECT_NEAR(normal_quantile(1.0 - 1e-10), 6.361340889697422, 1e-6);
  EXPECT_EQ(normal_quantile(0.0), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(normal_quantile(1.0), std::numeric_limits<double>::infinity());
  for (double p = 0.001; p < 1.0; p += 0.0137)
    EXPECT_NEAR(normal_cdf(normal_quantile(p)), p, 1e-15) << p;
  EXPECT_THROW(normal_quantile(-0.1), InvalidArgument);
  EXPECT_THROW(normal_quantile(std::nan("")), InvalidArgument);
}

TEST(Distributions, ChiSquareQuantileMatchesTables) {
  // Reference quantiles (R's qchisq).
  EXPECT_NEAR(chi_square_quantile(0.99, 1), 6.634896601021214, 1e-10);
  EXPECT_NEAR(chi_square_quantile(0.99, 2), 9.210340371976184, 1e-10);
  EXPECT_NEAR(chi_square_quantile(0.95, 3), 7.814727903251178, 1e-10);
  EXPECT_NEAR(chi_square_quantile(0.5, 3), 2.365973884375338, 1e-10);
  EXPECT_NEAR(chi_square_quantile(0.99, 10), 23.209251158954338, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.99, 100), 135.80672317102673, 1e-7);
  EXPECT_NEAR(chi_square_quantile(0.001, 4), 0.09080403553897727, 1e-9);
  // χ²(2) has the closed form −2 ln(1 − p).
  for (double p : {0.1, 0.5, 0.9, 0.999999})
    EXPECT_NEAR(chi_square_quantile(p, 2), -2.0 * std::log1p(-p), 1e-9 * (1 - 2 * std::log1p(-p)));
  for (double dof : {1.0, 2.5, 7.0, 40.0, 1000.0})
    for (double p : {0.001, 0.05, 0.5, 0.95, 0.999})
      EXPECT_NEAR(chi_square_cdf(chi_square_quantile(p, dof), dof), p, 1e-12) << dof << " " << p;
  EXPECT_EQ(chi_square_quantile(0.0, 3), 0.0);
  EXPECT_THROW(chi_square_quantile(0.5, 0.0), InvalidArgument);
  EXPECT_THROW(chi_square_cdf(1.0, -1.0), InvalidArgument);
}

TEST(Distributions, WilsonHilfertyIsCloseToExactAtHighProbability) {
  // At p = 0.99 (KLD's 1 − δ) the approximation is within 1 % for every dof.
  for (double dof = 1; dof <= 2000; dof = std::ceil(dof * 1.3)) {
    const double exact = chi_square_quantile(0.99, dof);
    EXPECT_NEAR(chi_square_quantile_wilson_hilferty(0.99, dof), exact, 0.01 * exact) << dof;
  }
}

}  // namespace
}  // namespace rove
