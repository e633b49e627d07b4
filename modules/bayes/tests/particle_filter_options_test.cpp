#include "rove/bayes/particle_filter_options.h"

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

TEST(ParticleFilterOptions, DefaultsAreMrpts) {
  const ParticleFilterOptions o;
  EXPECT_EQ(o.algorithm, ParticleFilterAlgorithm::StandardProposal);
  EXPECT_EQ(o.resampling_method, ResamplingMethod::Multinomial);
  EXPECT_EQ(o.beta, 0.5);
  EXPECT_EQ(o.sample_size, 1u);
  EXPECT_FALSE(o.adaptive_sample_size);
  EXPECT_EQ(o.max_search_samples, 100u);
  EXPECT_EQ(o.pow_factor, 1.0);
  EXPECT_EQ(o.max_loglikelihood_dyn_range, 15.0);
  EXPECT_NO_THROW(o.check());
}

TEST(ParticleFilterOptions, LoadsMrptNamesAndNumbers) {
  const auto by_number = IniFile::parse(
      "[PF_options]\nPF_algorithm=0\nresamplingMethod=0\nadaptiveSampleSize=1\n"
      "pfAuxFilterOptimal_MaximumSearchSamples=10\nBETA=0.5\nsampleSize=1\n");
  const auto a = ParticleFilterOptions::from_config(ConfigSection(by_number, "PF_options"));
  EXPECT_TRUE(a.adaptive_sample_size);
  EXPECT_EQ(a.max_search_samples, 10u);
  const auto by_name = IniFile::parse(
      "[PF]\nPF_algorithm=pfAuxiliaryPFOptimal\nresamplingMethod=prSystematic\nBETA=0.3\n"
      "sampleSize=500\npowFactor=0.5\nmax_loglikelihood_dyn_range=20\n"
      "pfAuxFilterStandard_FirstStageWeightsMonteCarlo=true\npfAuxFilterOptimal_MLE=1\n");
  const auto b = ParticleFilterOptions::from_config(ConfigSection(by_name, "PF"));
  EXPECT_EQ(b.algorithm, ParticleFilterAlgorithm::AuxiliaryPFOptimal);
  EXPECT_EQ(b.resampling_method, ResamplingMethod::Systematic);
  EXPECT_EQ(b.beta, 0.3);
  EXPECT_EQ(b.sample_size, 500u);
  EXPECT_EQ(b.pow_factor, 0.5);
  EXPECT_EQ(b.max_loglikelihood_dyn_range, 20.0);
  EXPECT_TRUE(b.first_stage_weights_monte_carlo);
  EXPECT_TRUE(b.aux_optimal_mle);
  const auto c = IniFile::parse("[PF_options]\nPF_algorithm=3\n");
  EXPECT_EQ(ParticleFilterOptions::from_config(ConfigSection(c, "PF_options")).algorithm,
            ParticleFilterAlgorithm::AuxiliaryPFOptimal);
  EXPECT_EQ(mrpt_name(ParticleFilterAlgorithm::OptimalProposal), "pfOptimalProposal");
}

TEST(ParticleFilterOptions, NamesTheBadKey) {
  auto message = [](const char* text) {
    try {
      const IniFile ini = IniFile::parse(text, "pf.ini");
      (void)ParticleFilterOptions::from_config(ConfigSection(ini, "PF_options"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("[PF_options]\nBETTA=0.5\n").find("BETTA"), std::string::npos);
  EXPECT_NE(message("[PF_options]\nPF_algorithm=pfMagic\n").find("PF_algorithm"), std::string::npos);
  EXPECT_NE(message("[PF_options]\nPF_algorithm=7\n").find("PF_algorithm"), std::string::npos);
  EXPECT_NE(message("[PF_options]\nBETA=1.5\n").find("BETA"), std::string::npos);
  EXPECT_NE(message("[PF_options]\nsampleSize=0\n").find("sampleSize"), std::string::npos);
  EXPECT_NE(message("[PF_options]\npowFactor=nan\n").find("powFactor"), std::string::npos);
  EXPECT_NE(message("[PF_options]\nadaptiveSampleSize=1\nresamplingMethod=prSystematic\n")
                .find("prMultinomial"),
            std::string::npos);
  EXPECT_NE(message("[PF_options]\nfoo=1\n").find("foo"), std::string::npos);
}

}  // namespace
}  // namespace rove
