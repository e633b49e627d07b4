#include "rove/math/robust_kernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rove/core/error.h"

namespace rove {
namespace {

const std::vector<RobustKernel>& all_kernels() {
  static const std::vector<RobustKernel> kernels = {
      RobustKernel(),
      RobustKernel(RobustKernelType::Huber),
      RobustKernel(RobustKernelType::Huber, 0.3),
      RobustKernel(RobustKernelType::Cauchy),
      RobustKernel(RobustKernelType::Cauchy, 0.5),
      RobustKernel(RobustKernelType::Tukey),
      RobustKernel(RobustKernelType::Tukey, 1.5),
      RobustKernel(RobustKernelType::GemanMcClure),
      RobustKernel(RobustKernelType::GemanMcClure, 3.0),
      RobustKernel(RobustKernelType::Dcs),
      RobustKernel(RobustKernelType::Dcs, 4.0),
  };
  return kernels;
}

// Squared errors where the kernel is smooth (away from its threshold).
std::vector<double> smooth_points(const RobustKernel& k) {
  std::vector<double> s = {1e-3, 0.05, 0.3, 0.9, 1.7, 2.6, 4.4, 7.0, 12.0, 30.0, 100.0, 1e3};
  double threshold = -1.0;
  switch (k.type()) {
    case RobustKernelType::Huber:
    case RobustKernelType::Tukey: threshold = k.parameter() * k.parameter(); break;
    case RobustKernelType::Dcs: threshold = k.parameter(); break;
    default: break;
  }
  std::vector<double> out;
  for (double v : s) {
    if (threshold < 0 || std::abs(v - threshold) > 1e-3 * threshold) out.push_back(v);
  }
  return out;
}

double threshold_of(const RobustKernel& k) {
  switch (k.type()) {
    case RobustKernelType::Huber:
    case RobustKernelType::Tukey: return k.parameter() * k.parameter();
    case RobustKernelType::Dcs: return k.parameter();
    default: return -1.0;
  }
}

TEST(RobustKernel, ZeroErrorHasZeroCostAndUnitWeight) {
  for (const auto& k : all_kernels()) {
    SCOPED_TRACE(k.to_string());
    const KernelValues v = k.evaluate(0.0);
    EXPECT_EQ(v.rho, 0.0);
    EXPECT_DOUBLE_EQ(v.d1, 1.0);
  }
}

TEST(RobustKernel, FirstAndSecondDerivativesMatchCentralDifferences) {
  for (const auto& k : all_kernels()) {
    for (double s : smooth_points(k)) {
      SCOPED_TRACE(k.to_string() + " at s = " + std::to_string(s));
      const double h = 1e-5 * s;
      const KernelValues v = k.evaluate(s);
      const double d1_num = (k.rho(s + h) - k.rho(s - h)) / (2 * h);
      const double d2_num = (k.evaluate(s + h).d1 - k.evaluate(s - h).d1) / (2 * h);
      EXPECT_NEAR(v.d1, d1_num, 1e-6 * std::max(1.0, std::abs(v.d1)));
      EXPECT_NEAR(v.d2, d2_num, 1e-5 * std::max(std::abs(v.d2), 1e-6 / s));
    }
  }
}

TEST(RobustKernel, CostAndWeightAreContinuousAtTheThreshold) {
  for (const auto& k : all_kernels()) {
    const double t = threshold_of(k);
    if (t < 0) continue;
    SCOPED_TRACE(k.to_string());
    const KernelValues below = k.evaluate(t * (1 - 1e-12));
    const KernelValues at = k.evaluate(t);
    const KernelValues above = k.evaluate(t * (1 + 1e-12));
    EXPECT_NEAR(below.rho, above.rho, 1e-9 * t);
    EXPECT_NEAR(at.rho, above.rho, 1e-9 * t);
    EXPECT_NEAR(below.d1, above.d1, 1e-9);
  }
}

TEST(RobustKernel, CostIsNonDecreasingAndWeightNonIncreasing) {
  for (const auto& k : all_kernels()) {
    SCOPED_TRACE(k.to_string());
    double prev_rho = -1.0;
    double prev_w = 2.0;
    for (double s = 0.0; s < 200.0; s += 0.01) {
      const KernelValues v = k.evaluate(s);
      EXPECT_GE(v.rho, prev_rho) << "s = " << s;
      EXPECT_LE(v.d1, prev_w + 1e-15) << "s = " << s;
      EXPECT_GE(v.d1, 0.0);
      EXPECT_LE(v.rho, s + 1e-12) << "a robust cost never exceeds least squares";
      prev_rho = v.rho;
      prev_w = v.d1;
    }
  }
}

TEST(RobustKernel, SmallErrorsReduceToLeastSquares) {
  for (const auto& k : all_kernels()) {
    SCOPED_TRACE(k.to_string());
    for (double s : {1e-8, 1e-6, 1e-4}) {
      // rho(s) = s + O(s²) with rho'' bounded near 0.
      EXPECT_NEAR(k.rho(s), s, 10.0 * s * s);
      EXPECT_NEAR(k.weight(s), 1.0, 10.0 * s);
    }
  }
}

TEST(RobustKernel, ClosedFormValues) {
  // Huber δ = 2 at |r| = 3: 2·2·3 − 4 = 8, weight 2/3.
  const HuberKernel huber(2.0);
  EXPECT_DOUBLE_EQ(huber.rho(9.0), 8.0);
  EXPECT_DOUBLE_EQ(huber.weight(9.0), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(huber.rho(3.0), 3.0);
  // Cauchy: at |r| = c the weight is ½ and the cost c² log 2.
  const CauchyKernel cauchy(1.5);
  EXPECT_DOUBLE_EQ(cauchy.weight(2.25), 0.5);
  EXPECT_DOUBLE_EQ(cauchy.rho(2.25), 2.25 * std::log(2.0));
  // Tukey: constant c²/3 and zero weight beyond c.
  const TukeyKernel tukey(2.0);
  EXPECT_DOUBLE_EQ(tukey.rho(4.0), 4.0 / 3.0);
  EXPECT_DOUBLE_EQ(tukey.rho(50.0), 4.0 / 3.0);
  EXPECT_EQ(tukey.weight(50.0), 0.0);
  EXPECT_DOUBLE_EQ(tukey.weight(2.0), 0.25);  // (1 − 2/4)²
  // Geman–McClure: c² s / (c² + s).
  const GemanMcClureKernel gm(2.0);
  EXPECT_DOUBLE_EQ(gm.rho(4.0), 2.0);
  EXPECT_DOUBLE_EQ(gm.weight(4.0), 0.25);
}

TEST(RobustKernel, DcsWeightIsTheSquaredScalingOfAgarwalEq14) {
  for (double phi : {0.5, 1.0, 5.0}) {
    const DcsKernel dcs(phi);
    for (double s : {0.0, 0.1, 0.49, 0.5, 0.9, 1.0, 2.0, 10.0, 1e4}) {
      const double scale = std::min(1.0, 2.0 * phi / (phi + s));
      EXPECT_NEAR(dcs.weight(s), scale * scale, 1e-15) << "phi " << phi << " s " << s;
    }
    // The integral of the weight: 3Φ − 4Φ²/(Φ + s) beyond Φ.
    EXPECT_NEAR(dcs.rho(3.0 * phi), 3.0 * phi - 4.0 * phi * phi / (4.0 * phi), 1e-14);
  }
}

TEST(RobustKernel, InfiniteErrorGivesTheKernelsLimit) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(TukeyKernel(2.0).rho(inf), 4.0 / 3.0);
  EXPECT_EQ(GemanMcClureKernel(2.0).rho(inf), 4.0);
  EXPECT_EQ(DcsKernel(2.0).rho(inf), 6.0);
  EXPECT_EQ(HuberKernel(2.0).rho(inf), inf);
  EXPECT_EQ(CauchyKernel(2.0).rho(inf), inf);
  for (const auto& k : all_kernels()) {
    if (k.type() == RobustKernelType::Trivial) continue;
    EXPECT_EQ(k.weight(inf), 0.0) << k.to_string();
  }
}

TEST(RobustKernel, RejectsNegativeOrNanSquaredError) {
  for (const auto& k : all_kernels()) {
    EXPECT_THROW(k.evaluate(-1e-12), InvalidArgument) << k.to_string();
    EXPECT_THROW(k.evaluate(std::numeric_limits<double>::quiet_NaN()), InvalidArgument);
  }
}

TEST(RobustKernel, RejectsNonPositiveParameters) {
  EXPECT_THROW(HuberKernel(0.0), InvalidArgument);
  EXPECT_THROW(CauchyKernel(-1.0), InvalidArgument);
  EXPECT_THROW(TukeyKernel(std::numeric_limits<double>::infinity()), InvalidArgument);
  EXPECT_THROW(GemanMcClureKernel(std::numeric_limits<double>::quiet_NaN()), InvalidArgument);
  EXPECT_THROW(DcsKernel(-2.0), InvalidArgument);
  EXPECT_THROW(RobustKernel(RobustKernelType::Huber, 0.0), InvalidArgument);
  EXPECT_THROW(RobustKernel(static_cast<RobustKernelType>(99), 1.0), InvalidArgument);
}

TEST(RobustKernel, RunTimeKernelMatchesCompileTimeStruct) {
  const RobustKernel k(RobustKernelType::Cauchy, 0.7);
  const CauchyKernel c(0.7);
  for (double s : {0.0, 0.2, 3.0, 40.0}) {
    EXPECT_EQ(k.evaluate(s).rho, c.evaluate(s).rho);
    EXPECT_EQ(k.evaluate(s).d1, c.evaluate(s).d1);
    EXPECT_EQ(k.evaluate(s).d2, c.evaluate(s).d2);
  }
  // visit hands over the concrete struct with the same parameter.
  const double total = k.visit([](const auto& kernel) {
    double sum = 0.0;
    for (int i = 0; i < 10; ++i) sum += kernel.rho(0.5 * i);
    return sum;
  });
  double expected = 0.0;
  for (int i = 0; i < 10; ++i) expected += c.rho(0.5 * i);
  EXPECT_EQ(total, expected);
}

TEST(RobustKernelParse, NamesAndParameters) {
  EXPECT_EQ(parse_robust_kernel("huber"), RobustKernel(RobustKernelType::Huber));
  EXPECT_DOUBLE_EQ(parse_robust_kernel("huber").parameter(), 1.345);
  EXPECT_EQ(parse_robust_kernel("cauchy:2.0"), RobustKernel(RobustKernelType::Cauchy, 2.0));
  EXPECT_EQ(parse_robust_kernel("  Tukey : 3.5 "), RobustKernel(RobustKernelType::Tukey, 3.5));
  EXPECT_EQ(parse_robust_kernel("GM:1e-1"), RobustKernel(RobustKernelType::GemanMcClure, 0.1));
  EXPECT_EQ(parse_robust_kernel("geman_mcclure"), RobustKernel(RobustKernelType::GemanMcClure));
  EXPECT_EQ(parse_robust_kernel("dcs:5"), RobustKernel(RobustKernelType::Dcs, 5.0));
  EXPECT_EQ(parse_robust_kernel("none"), RobustKernel());
  EXPECT_EQ(parse_robust_kernel("L2"), RobustKernel());
}

TEST(RobustKernelParse, ToStringRoundTrips) {
  for (const auto& k : all_kernels()) {
    EXPECT_EQ(parse_robust_kernel(k.to_string()), k) << k.to_string();
  }
  const RobustKernel odd(RobustKernelType::Huber, 0.1 + 0.2);
  EXPECT_EQ(parse_robust_kernel(odd.to_string()), odd);
}

TEST(RobustKernelParse, MalformedTextThrowsParseErrorNamingTheField) {
  for (const char* bad : {"", "  ", "foo", "huber:", "huber:abc", "huber:1.0x", "huber:-1",
                          "huber:0", "cauchy:inf", "cauchy:nan", "none:1", ":2", "huber:1:2"}) {
    SCOPED_TRACE(std::string("'") + bad + "'");
    try {
      parse_robust_kernel(bad, "config.ini");
      ADD_FAILURE() << "no exception";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, "config.ini");
      EXPECT_EQ(e.location().field, "robust kernel");
      EXPECT_FALSE(e.problem().empty());
    }
  }
  try {
    parse_robust_kernel("hubr:1");
    ADD_FAILURE() << "no exception";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown kernel 'hubr'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rove
