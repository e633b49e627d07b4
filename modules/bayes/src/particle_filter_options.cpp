#include "rove/bayes/particle_filter_options.h"

#include <cmath>

#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {

std::string_view mrpt_name(ParticleFilterAlgorithm algorithm) {
  switch (algorithm) {
    case ParticleFilterAlgorithm::StandardProposal: return "pfStandardProposal";
    case ParticleFilterAlgorithm::AuxiliaryPFStandard: return "pfAuxiliaryPFStandard";
    case ParticleFilterAlgorithm::OptimalProposal: return "pfOptimalProposal";
    case ParticleFilterAlgorithm::AuxiliaryPFOptimal: return "pfAuxiliaryPFOptimal";
  }
  ROVE_CHECK_MSG(false, "unknown ParticleFilterAlgorithm {}", static_cast<int>(algorithm));
  return {};
}

void ParticleFilterOptions::check() const {
  ROVE_CHECK_MSG(static_cast<int>(algorithm) <= 3, "unknown PF_algorithm {}",
                 static_cast<int>(algorithm));
  ROVE_CHECK_MSG(static_cast<int>(resampling_method) <= 3, "unknown resamplingMethod {}",
                 static_cast<int>(resampling_method));
  ROVE_CHECK_MSG(beta >= 0.0 && beta <= 1.0, "BETA must be in [0, 1], got {}", beta);
  ROVE_CHECK_MSG(sample_size >= 1, "sampleSize must be >= 1, got {}", sample_size);
  ROVE_CHECK_MSG(max_search_samples >= 2,
                 "pfAuxFilterOptimal_MaximumSearchSamples must be >= 2, got {}", max_search_samples);
  ROVE_CHECK_MSG(std::isfinite(pow_factor) && pow_factor > 0.0,
                 "powFactor must be finite and > 0, got {}", pow_factor);
  ROVE_CHECK_MSG(!std::isnan(max_loglikelihood_dyn_range) && max_loglikelihood_dyn_range >= 0.0,
                 "max_loglikelihood_dyn_range must be >= 0, got {}", max_loglikelihood_dyn_range);
  ROVE_CHECK_MSG(!adaptive_sample_size || resampling_method == ResamplingMethod::Multinomial,
                 "adaptiveSampleSize draws ancestors one by one and needs resamplingMethod = "
                 "prMultinomial (MRPT refuses {} too)",
                 mrpt_name(resampling_method));
}

ParticleFilterOptions ParticleFilterOptions::from_config(const ConfigSection& section) {
  ParticleFilterOptions o;
  const IniFile& ini = section.ini();
  const std::string& s = section.name();
  if (ini.has(s, "PF_algorithm")) {
    o.algorithm = ini.get_enum<ParticleFilterAlgorithm>(
        s, "PF_algorithm",
        {{"pfStandardProposal", ParticleFilterAlgorithm::StandardProposal},
         {"pfAuxiliaryPFStandard", ParticleFilterAlgorithm::AuxiliaryPFStandard},
         {"pfOptimalProposal", ParticleFilterAlgorithm::OptimalProposal},
         {"pfAuxiliaryPFOptimal", ParticleFilterAlgorithm::AuxiliaryPFOptimal}});
  }
  if (ini.has(s, "resamplingMethod")) {
    o.resampling_method = ini.get_enum<ResamplingMethod>(
        s, "resamplingMethod",
        {{"prMultinomial", ResamplingMethod::Multinomial},
         {"prResidual", ResamplingMethod::Residual},
         {"prStratified", ResamplingMethod::Stratified},
         {"prSystematic", ResamplingMethod::Systematic}});
  }
  o.beta = ini.get_or<double>(s, "BETA", o.beta);
  o.sample_size = ini.get_or<unsigned>(s, "sampleSize", o.sample_size);
  o.adaptive_sample_size = ini.get_or<bool>(s, "adaptiveSampleSize", o.adaptive_sample_size);
  o.max_search_samples =
      ini.get_or<unsigned>(s, "pfAuxFilterOptimal_MaximumSearchSamples", o.max_search_samples);
  o.pow_factor = ini.get_or<double>(s, "powFactor", o.pow_factor);
  o.max_loglikelihood_dyn_range =
      ini.get_or<double>(s, "max_loglikelihood_dyn_range", o.max_loglikelihood_dyn_range);
  o.first_stage_weights_monte_carlo = ini.get_or<bool>(
      s, "pfAuxFilterStandard_FirstStageWeightsMonteCarlo", o.first_stage_weights_monte_carlo);
  o.aux_optimal_mle = ini.get_or<bool>(s, "pfAuxFilterOptimal_MLE", o.aux_optimal_mle);
  section.check_all_read();
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), s, "", e.message());
  }
  return o;
}

}  // namespace rove
