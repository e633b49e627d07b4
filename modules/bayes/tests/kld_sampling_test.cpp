#include "rove/bayes/kld_sampling.h"

#include <cmath>
#include <numbers>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "rove/bayes/distributions.h"
#include "rove/bayes/random.h"
#include "rove/core/error.h"

namespace rove {
namespace {

// Fox's formula written out with z₀.₉₉ = Φ⁻¹(0.99) as a literal (R's
// qnorm(0.99)), independent of rove's quantile code.
double fox_by_hand(double k, double epsilon) {
  const double z = 2.326347874040841;
  const double a = 2.0 / (9.0 * (k - 1.0));
  return (k - 1.0) / (2.0 * epsilon) * std::pow(1.0 - a + std::sqrt(a) * z, 3.0);
}

TEST(Kld, BoundFollowsFoxsFormula) {
  KldOptions o;
  o.delta = 0.01;
  o.epsilon = 0.02;
  EXPECT_EQ(kld_bound(0, o), 0.0);
  EXPECT_EQ(kld_bound(1, o), 0.0);
  for (std::size_t k : {2, 3, 10, 57, 400, 10000})
    EXPECT_NEAR(kld_bound(k, o), fox_by_hand(static_cast<double>(k), 0.02), 1e-9 * kld_bound(k, o))
        << k;
  // Hand-computed: k = 2 → (1/0.04)·(7/9 + √(2/9)·2.3263478740)³ = 164.6443...
  EXPECT_NEAR(kld_bound(2, o), 164.64433, 1e-4);
  o.epsilon = 0.01;  // halving ε doubles the bound
  EXPECT_NEAR(kld_bound(10, o), fox_by_hand(10, 0.01), 1e-9 * fox_by_hand(10, 0.01));
}

TEST(Kld, BoundIsCloseToTheExactChiSquareQuantile) {
  // n = χ²_{k−1, 1−δ} / (2ε) with the exact quantile (R's qchisq): the
  // Wilson–Hilferty value used by Fox and MRPT is within 1 %.
  KldOptions o;
  o.epsilon = 0.02;
  const struct { std::size_t k; double chi2; } table[] = {
      {2, 6.634896601021214}, {3, 9.210340371976184}, {11, 23.209251158954338}};
  for (const auto& row : table) {
    const double exact = row.chi2 / (2 * o.epsilon);
    EXPECT_NEAR(kld_bound(row.k, o), exact, 0.01 * exact) << row.k;
    EXPECT_NEAR(chi_square_quantile(0.99, row.k - 1.0) / (2 * o.epsilon), exact, 1e-8 * exact);
  }
}

TEST(Kld, TargetCountIsClampedByTheLimits) {
  KldOptions o;
  o.min_sample_size = 150;
  o.max_sample_size = 40000;
  o.epsilon = 0.01;
  EXPECT_EQ(kld_target_count(1, 0, o), 150u);
  EXPECT_EQ(kld_target_count(2, 0, o), 329u);  // round(164.644 · 2)
  EXPECT_EQ(kld_target_count(100, 0, o), static_cast<std::size_t>(std::round(fox_by_hand(100, 0.01))));
  EXPECT_EQ(kld_target_count(100000, 0, o), 40000u);
  o.min_samples_per_bin = 2.5;
  EXPECT_EQ(kld_target_count(1, 1000, o), 2500u);
  o.delta = 1.5;
  EXPECT_THROW(kld_target_count(3, 0, o), InvalidArgument);
}

TEST(Kld, BinsRoundAsMrpt) {
  KldOptions o;
  o.bin_size_xy = 0.1;
  o.bin_size_phi = 10.0 * std::numbers::pi / 180.0;
  EXPECT_EQ(kld_bin(0.149, -0.151, 0.0, o), (KldBin{1, -2, 0}));
  EXPECT_EQ(kld_bin(SE2d::exp({0.0, 0.0, 0.1}), o).phi, 1);
  KldBinSet set;
  EXPECT_TRUE(set.insert(kld_bin(0.0, 0.0, 0.0, o)));
  EXPECT_FALSE(set.insert(kld_bin(0.04, 0.04, 0.05, o)));
  EXPECT_TRUE(set.insert(kld_bin(0.06, 0.0, 0.0, o)));
  EXPECT_EQ(set.size(), 2u);
  EXPECT_THROW(kld_bin(std::nan(""), 0.0, 0.0, o), InvalidArgument);
  EXPECT_NO_THROW(kld_bin(1e300, 0.0, 0.0, o));
}

// The open-addressing set against std::set: through several growths, with
// duplicates and colliding neighbours, and after clear().
TEST(Kld, BinSetCountsAsAnOrderedSet) {
  const auto key = [](const KldBin& b) { return std::tuple(b.x, b.y, b.phi); };
  Rng rng(5);
  KldBinSet set;
  for (int round = 0; round < 2; ++round) {
    std::set<std::tuple<std::int64_t, std::int64_t, std::int64_t>> oracle;
    for (int i = 0; i < 30000; ++i) {
      const KldBin b{static_cast<std::int64_t>(rng.uniform_index(60)) - 30,
                     static_cast<std::int64_t>(rng.uniform_index(40)),
                     static_cast<std::int64_t>(rng.uniform_index(72)) - 36};
      ASSERT_EQ(set.insert(b), oracle.insert(key(b)).second) << i;
      ASSERT_EQ(set.size(), oracle.size());
    }
    set.clear();
    EXPECT_EQ(set.size(), 0u);
  }
}

// The KLD options of `section` in the INI text.
KldOptions kld(const std::string& text, const std::string& section = "KLD_options",
               const std::string& file = "<string>") {
  const IniFile ini = IniFile::parse(text, file);
  return KldOptions::from_config(ConfigSection(ini, section));
}

TEST(Kld, LoadsMrptSection) {
  const auto ini = IniFile::parse(
      "[KLD_options]\nKLD_binSize_PHI_deg=10\nKLD_binSize_XY=0.10\nKLD_delta=0.01\n"
      "KLD_epsilon=0.01\nKLD_maxSampleSize=40000\nKLD_minSampleSize=150\n"
      "KLD_minSamplesPerBin=0   \n",
      "demo.ini");
  std::vector<IgnoredConfigKey> ignored;
  const auto o = KldOptions::from_config(ConfigSection(ini, "KLD_options", &ignored));
  EXPECT_EQ(o.bin_size_xy, 0.10);
  EXPECT_NEAR(o.bin_size_phi, 5.0 * std::numbers::pi / 180.0, 1e-15);  // MRPT's default stays
  EXPECT_EQ(o.epsilon, 0.01);
  EXPECT_EQ(o.min_sample_size, 150u);
  EXPECT_EQ(o.max_sample_size, 40000u);
  ASSERT_EQ(ignored.size(), 1u);
  EXPECT_EQ(ignored[0].key, "KLD_binSize_PHI_deg");
  EXPECT_NEAR(kld("[K]\nKLD_binSize_PHI=20\n", "K").bin_size_phi, 20.0 * std::numbers::pi / 180.0,
              1e-15);
  EXPECT_EQ(kld(""), KldOptions{});
}

TEST(Kld, RejectsUnknownAndInvalidKeys) {
  try {
    (void)kld("[KLD_options]\nKLD_binSize_Z=3\n", "KLD_options", "a.ini");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("KLD_binSize_Z"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a.ini"), std::string::npos) << e.what();
  }
  EXPECT_THROW(kld("[KLD_options]\nKLD_epsilon=0\n"), ConfigError);
  EXPECT_THROW(kld("[KLD_options]\nKLD_delta=abc\n"), ConfigError);
  EXPECT_THROW(kld("[KLD_options]\nKLD_minSampleSize=10\nKLD_maxSampleSize=5\n"), ConfigError);
}

}  // namespace
}  // namespace rove
