#pragma once
/// \file
/// The options of a particle filter, with MRPT's names and defaults
/// (CParticleFilter::TParticleFilterOptions, read from a [PF_options]
/// section of MRPT's config files).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rove/bayes/resampling.h"
#include "rove/core/config_section.h"

namespace rove {

/// The particle-filter algorithm (MRPT's TParticleFilterAlgorithm; the
/// underlying values are MRPT's). See rove/bayes/particle_filter.h for what
/// each does.
enum class ParticleFilterAlgorithm : std::uint8_t {
  /// MRPT pfStandardProposal: sequential importance resampling, samples
  /// from the motion model, weights by the observation likelihood.
  StandardProposal = 0,
  /// MRPT pfAuxiliaryPFStandard: auxiliary PF (Pitt & Shephard 1999),
  /// first-stage weights from the likelihood at the predicted mean (or a
  /// Monte-Carlo estimate), standard proposal.
  AuxiliaryPFStandard = 1,
  /// MRPT pfOptimalProposal: samples from p(x_t | x_{t-1}, z_t), here
  /// approximated by importance sampling over motion samples.
  OptimalProposal = 2,
  /// MRPT pfAuxiliaryPFOptimal: auxiliary PF with the optimal proposal drawn
  /// by rejection sampling (Blanco, González & Fernández-Madrigal, ICRA 2008).
  AuxiliaryPFOptimal = 3,
};

/// MRPT's name of the algorithm ("pfStandardProposal", ...).
std::string_view mrpt_name(ParticleFilterAlgorithm algorithm);

/// Particle-filter options (MRPT's TParticleFilterOptions, same defaults).
struct ParticleFilterOptions {
  /// `PF_algorithm`. Default StandardProposal.
  ParticleFilterAlgorithm algorithm = ParticleFilterAlgorithm::StandardProposal;
  /// `resamplingMethod`. Default Multinomial. With adaptive_sample_size the
  /// ancestors are drawn one by one, which only the multinomial scheme can
  /// do: check() refuses another method then, as MRPT does.
  ResamplingMethod resampling_method = ResamplingMethod::Multinomial;
  /// `BETA`: resample when the normalized effective sample size ESS/N falls
  /// below it, in [0, 1] (0 never, 1 always). Default 0.5.
  double beta = 0.5;
  /// `sampleSize`: the initial particle count (≥ 1); the count changes only
  /// with adaptive_sample_size. Default 1 (MRPT's; callers set it).
  std::uint32_t sample_size = 1;
  /// `adaptiveSampleSize`: KLD-sampling (rove/bayes/kld_sampling.h) decides
  /// the particle count at each step. Default false.
  bool adaptive_sample_size = false;
  /// `pfAuxFilterOptimal_MaximumSearchSamples`: motion samples per particle
  /// for the Monte-Carlo estimates of the optimal and auxiliary algorithms
  /// (≥ 2). Default 100.
  std::uint32_t max_search_samples = 100;
  /// `powFactor`: log-likelihoods are multiplied by it (likelihood^powFactor),
  /// in (0, 1] to soften an overconfident sensor model. Default 1.
  double pow_factor = 1.0;
  /// `max_loglikelihood_dyn_range`: in the auxiliary algorithms, a particle
  /// whose first-stage log-likelihood is more than this below the best one
  /// is replaced by a uniformly chosen acceptable particle (≥ 0).
  /// Default 15.
  double max_loglikelihood_dyn_range = 15.0;
  /// `pfAuxFilterStandard_FirstStageWeightsMonteCarlo`: AuxiliaryPFStandard
  /// estimates its first-stage likelihood from max_search_samples motion
  /// samples instead of at the predicted mean. Default false.
  bool first_stage_weights_monte_carlo = false;
  /// `pfAuxFilterOptimal_MLE`: AuxiliaryPFOptimal takes the most likely of
  /// the first-stage motion samples as the first candidate of each
  /// ancestor's first offspring. Default false.
  bool aux_optimal_mle = false;

  /// Throws InvalidArgument naming the first field out of range (with its
  /// MRPT name).
  void check() const;

  /// Defaults overridden by the keys present in `section`: PF_algorithm and
  /// resamplingMethod by MRPT's name (pfStandardProposal, prSystematic, ...)
  /// or number, BETA, sampleSize, adaptiveSampleSize,
  /// pfAuxFilterOptimal_MaximumSearchSamples, powFactor,
  /// max_loglikelihood_dyn_range,
  /// pfAuxFilterStandard_FirstStageWeightsMonteCarlo, pfAuxFilterOptimal_MLE.
  /// Strict: any other key of the section, a malformed value or options
  /// check() rejects are a ConfigError (file, section, key).
  static ParticleFilterOptions from_config(const ConfigSection& section);

  /// Exact equality.
  friend bool operator==(const ParticleFilterOptions&, const ParticleFilterOptions&) = default;
};

}  // namespace rove
