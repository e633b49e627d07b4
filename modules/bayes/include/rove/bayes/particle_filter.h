#pragma once
/// \file
/// One predict–update–resample step of a particle filter over any state
/// type, with MRPT's four algorithms and its resampling and KLD options.
///
/// The user describes the system by a model object (the ParticleFilterModel
/// concept): `sample_motion(x, rng)` draws x_t ~ p(x_t | x_{t−1} = x, u_t),
/// `log_likelihood(x)` gives log p(z_t | x_t = x). Both are called
/// concurrently from the step's threads and must be thread-safe (const, no
/// shared mutable state); every random number they need comes from the
/// `rng` passed in, which is a per-particle stream, so the result depends on
/// the step's seed and not on the thread count.
///
/// Optional model members, used when present:
/// - `predicted_mean(x)` → State: the mean of the motion from x, needed by
///   AuxiliaryPFStandard unless first_stage_weights_monte_carlo is set;
/// - `kld_bin(x)` → KldBin: the KLD bin of a state, needed by
///   adaptive_sample_size unless State is SE2d (whose bin is MRPT's
///   (x, y, phi) bin, rove/bayes/kld_sampling.h).
///
/// What each algorithm does in one step (N particles, normalized weights
/// w̄ᵢ, tempered likelihood ℓ(x) = powFactor · log p(z | x)):
/// - StandardProposal (SIR): xᵢ' ~ p(x | xᵢ), log wᵢ' = log w̄ᵢ + ℓ(xᵢ');
///   then resample when ESS/N < BETA.
/// - OptimalProposal: K = max_search_samples motion samples of xᵢ; one is
///   kept with probability ∝ exp(ℓ) (importance sampling of the optimal
///   proposal p(x | xᵢ, z) ∝ p(z | x)^powFactor p(x | xᵢ)); the weight is
///   multiplied by the predictive likelihood estimate (1/K) Σ exp(ℓₖ)
///   (Doucet, Godsill & Andrieu 2000, eq. 4–5); then resample when
///   ESS/N < BETA.
/// - AuxiliaryPFStandard (Pitt & Shephard 1999): first-stage weights
///   λᵢ = w̄ᵢ · exp(ℓ(μᵢ)) with μᵢ the predicted mean (or the Monte-Carlo
///   average over K motion samples); when ESS/N < BETA ancestors are drawn
///   by λ with the resampling method and the offspring x' ~ p(x | x_a) gets
///   log w' = ℓ(x') − ℓ(μ_a); otherwise each particle keeps its own
///   ancestor and log w' = log w̄ᵢ + ℓ(x').
/// - AuxiliaryPFOptimal (Blanco et al., ICRA 2008): first stage as above with
///   the Monte-Carlo estimate; the offspring is drawn from the optimal
///   proposal by rejection sampling against the largest of the K
///   first-stage likelihoods (raised when exceeded; at most 10,000 tries,
///   then the best candidate); weights equal after ancestor selection,
///   log w̄ᵢ + (first-stage estimate) otherwise.
/// In both auxiliary algorithms, when ancestors are drawn by weight, an
/// ancestor whose first-stage log-likelihood is more than
/// max_loglikelihood_dyn_range below the best is replaced by a uniformly
/// drawn acceptable one (MRPT's safeguard, which keeps the rejection
/// sampler from running on hopeless particles; it biases the weights
/// slightly, as in MRPT).
///
/// With adaptive_sample_size, every algorithm draws ancestors one at a time
/// from the (first-stage) weights, multinomially (CumulativeSampler, one
/// uniform of its own stream per offspring), and stops by Fox's KLD
/// rule (rove/bayes/kld_sampling.h); the weights then carry only the
/// algorithm's second-stage factor, and no further ESS resampling is done
/// (as MRPT). Offspring are made in parallel in chunks that the sequential
/// rule would certainly keep, so the set is exactly the sequential one.
///
/// A step without observation (has_observation = false) only moves the
/// particles with the standard proposal (and redraws them by KLD when
/// adaptive); a step without motion keeps each state where it is.
///
/// Differences from MRPT, each deliberate: weights are log-weights and are
/// normalized after every step; AuxiliaryPFStandard without ancestor
/// selection weights by log w̄ᵢ + ℓ(x') (MRPT also subtracts the first-stage
/// term, which biases the weights); powFactor tempers the first stage too;
/// the dynamic-range safeguard applies only when ancestors are drawn by
/// weight; the rejection bound is raised per offspring, not shared between the
/// offspring of one ancestor (that would make the result depend on the
/// order of the threads); KLD applies to all four algorithms with one rule;
/// the OptimalProposal of a generic model is the Monte-Carlo approximation
/// above (MRPT implements it only for some map types).

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rove/bayes/kld_sampling.h"
#include "rove/bayes/log_weights.h"
#include "rove/bayes/particle_filter_options.h"
#include "rove/bayes/random.h"
#include "rove/bayes/resampling.h"
#include "rove/core/check.h"
#include "rove/core/parallel.h"

namespace rove {

/// A weighted set of particles: states[i] has weight exp(log_weights[i]).
/// A plain value.
template <typename State>
struct ParticleSet {
  /// The particle states.
  std::vector<State> states;
  /// Their log-weights (same size; need not be normalized on input;
  /// particle_filter_step leaves them normalized: log Σ exp = 0).
  std::vector<double> log_weights;

  /// N particles.
  std::size_t size() const noexcept { return states.size(); }
  /// The states with equal weights −log N. Precondition (InvalidArgument):
  /// states non-empty.
  static ParticleSet uniform(std::vector<State> states) {
    ROVE_CHECK_MSG(!states.empty(), "a particle set needs at least one particle");
    ParticleSet p;
    p.log_weights.assign(states.size(), -std::log(static_cast<double>(states.size())));
    p.states = std::move(states);
    return p;
  }
};

/// What a model must provide to particle_filter_step (see the file comment
/// for the optional members). Both calls must be thread-safe.
template <typename M, typename State>
concept ParticleFilterModel = std::copy_constructible<State> && requires(const M& m, const State& x, Rng& rng) {
  { m.sample_motion(x, rng) } -> std::convertible_to<State>;
  { m.log_likelihood(x) } -> std::convertible_to<double>;
};

/// Per-step inputs of particle_filter_step.
struct ParticleFilterStepInput {
  /// Seed of this step's random streams. Use derive_seed(run_seed,
  /// step_index) so every step draws different numbers and a run is
  /// reproduced by its run seed.
  std::uint64_t seed = 0;
  /// false: no action this step; states stay where they are.
  bool has_motion = true;
  /// false: no observation this step; only the prediction runs.
  bool has_observation = true;
};

/// How a step ended.
enum class ParticleFilterTermination : std::uint8_t {
  /// Predicted and weighted by the observation.
  Updated,
  /// Predicted only (no observation given).
  Predicted,
  /// Every particle had zero likelihood (log-likelihood −inf): the
  /// observation was ignored and the particles keep their prior weights.
  Degenerate,
};

/// What a step did.
struct ParticleFilterStepResult {
  /// How the step ended.
  ParticleFilterTermination termination = ParticleFilterTermination::Updated;
  /// One line about the step (algorithm, counts, resampling).
  std::string message;
  /// Particles before and after the step (they differ only with KLD).
  std::size_t particles_before = 0, particles_after = 0;
  /// ESS/N of the weights after the update, before any resampling (MRPT's
  /// ESS_beforeResample), in (0, 1].
  double ess_before_resampling = 1.0;
  /// True if the particles were resampled after the update (Standard and
  /// Optimal proposals, fixed size) or their ancestors were drawn by weight
  /// (auxiliary algorithms, KLD).
  bool resampled = false;
  /// Bins the new set occupies (adaptive_sample_size only, else 0).
  std::size_t kld_bins = 0;
  /// The step's estimate of log p(z_t | z_{1:t−1}) with the tempered
  /// likelihood: the log of the weighted average likelihood, Thrun's w_avg
  /// for augmented MCL (slow/fast averages). −inf when Degenerate, 0
  /// without observation.
  double log_evidence = 0.0;
  /// Auxiliary algorithms: ancestors replaced because their first-stage
  /// likelihood was below the dynamic range.
  std::size_t discarded_ancestors = 0;
  /// AuxiliaryPFOptimal: offspring whose rejection sampling ran out of tries
  /// (the best candidate was taken).
  std::size_t rejection_timeouts = 0;
  /// True unless Degenerate.
  bool ok() const noexcept { return termination != ParticleFilterTermination::Degenerate; }
};

}  // namespace rove

#include "rove/bayes/detail/particle_filter_step.h"

namespace rove {

/// Runs one step of options.algorithm on `particles` (replaced by the new
/// set, log-weights normalized), on `team`'s threads. Create the team once
/// per run: `ThreadTeam team(resolve_thread_count(num_threads))`.
///
/// The result is a function of (particles, model, options, kld, input) only:
/// the same with any team size. Preconditions (InvalidArgument):
/// particles non-empty with as many log-weights as states, log-weights not
/// NaN or +inf and not all −inf; options.check() and (if adaptive)
/// kld.check() pass; the model provides what the options need (see the file
/// comment). A log_likelihood that returns NaN or +inf throws
/// InvalidArgument naming the particle (−inf is a zero likelihood).
template <typename State, ParticleFilterModel<State> Model>
ParticleFilterStepResult particle_filter_step(ParticleSet<State>& particles, const Model& model,
                                              const ParticleFilterOptions& options,
                                              const KldOptions& kld,
                                              const ParticleFilterStepInput& input,
                                              ThreadTeam& team) {
  detail::ParticleFilterStepRunner<State, Model> runner(particles, model, options, kld, input, team);
  return runner.run();
}

}  // namespace rove
