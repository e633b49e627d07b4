#pragma once
/// \file
/// The machinery of particle_filter_step (rove/bayes/particle_filter.h);
/// include that header, not this one.
///
/// Random streams of a step with seed s, all Rng::stream(derive_seed(s, d), i):
/// d = 1 the offspring i's proposal, d = 2 old particle i's first-stage
/// samples, d = 3 the ancestor of offspring i (KLD), d = 4 the replacement
/// of a discarded ancestor of offspring i, d = 5 the resampling (i = 0).

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace rove::detail {

template <typename State, typename Model>
class ParticleFilterStepRunner {
 public:
  ParticleFilterStepRunner(ParticleSet<State>& particles, const Model& model,
                           const ParticleFilterOptions& options, const KldOptions& kld,
                           const ParticleFilterStepInput& input, ThreadTeam& team)
      : particles_(particles), model_(model), options_(options), kld_(kld), input_(input),
        team_(team) {}

  ParticleFilterStepResult run() {
    check_inputs();
    const std::size_t m = particles_.size();
    result_.particles_before = m;
    prev_w_ = particles_.log_weights;
    normalize_log_weights(prev_w_);
    algorithm_ = input_.has_observation ? options_.algorithm : ParticleFilterAlgorithm::StandardProposal;
    if (auxiliary() && !first_stage()) {
      // No particle explains the observation even at the first stage: fall
      // back to the standard proposal for this step.
      algorithm_ = ParticleFilterAlgorithm::StandardProposal;
      first_stage_note_ = "; every first-stage likelihood was zero, standard proposal used";
    }
    if (options_.adaptive_sample_size) {
      adaptive();
    } else {
      fixed_size();
    }
    return finish();
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr int kMaxRejectionTries = 10000;

  void check_inputs() const {
    ROVE_CHECK_MSG(particles_.size() > 0, "particle_filter_step needs at least one particle");
    ROVE_CHECK_MSG(particles_.log_weights.size() == particles_.size(),
                   "{} log-weights for {} particles", particles_.log_weights.size(),
                   particles_.size());
    options_.check();
    if (options_.adaptive_sample_size) {
      kld_.check();
      ROVE_CHECK_MSG(has_kld_bin(),
                     "adaptiveSampleSize needs the model's kld_bin(state) (built in for SE2d)");
    }
    if (input_.has_observation && input_.has_motion &&
        options_.algorithm == ParticleFilterAlgorithm::AuxiliaryPFStandard &&
        !options_.first_stage_weights_monte_carlo) {
      ROVE_CHECK_MSG(has_predicted_mean(),
                     "pfAuxiliaryPFStandard needs the model's predicted_mean(state), or "
                     "pfAuxFilterStandard_FirstStageWeightsMonteCarlo = true");
    }
  }

  static constexpr bool has_model_kld_bin() {
    return requires(const Model& m, const State& x) {
      { m.kld_bin(x) } -> std::convertible_to<KldBin>;
    };
  }
  static constexpr bool has_kld_bin() { return has_model_kld_bin() || std::is_same_v<State, SE2d>; }
  static constexpr bool has_predicted_mean() {
    return requires(const Model& m, const State& x) {
      { m.predicted_mean(x) } -> std::convertible_to<State>;
    };
  }

  KldBin bin_of(const State& x) const {
    if constexpr (has_model_kld_bin()) {
      return static_cast<KldBin>(model_.kld_bin(x));
    } else if constexpr (std::is_same_v<State, SE2d>) {
      return kld_bin(x, kld_);
    } else {
      ROVE_CHECK_MSG(false, "no KLD bin for this state type");
      return {};
    }
  }

  bool auxiliary() const {
    return algorithm_ == ParticleFilterAlgorithm::AuxiliaryPFStandard ||
           algorithm_ == ParticleFilterAlgorithm::AuxiliaryPFOptimal;
  }

  /// A motion sample from x (x itself in a step without motion).
  State move(const State& x, Rng& rng) const {
    if (!input_.has_motion) return x;
    return static_cast<State>(model_.sample_motion(x, rng));
  }

  /// The model's log-likelihood at x, checked.
  double loglik(const State& x, std::size_t particle) const {
    const double l = static_cast<double>(model_.log_likelihood(x));
    ROVE_CHECK_MSG(!std::isnan(l) && l != kInf,
                   "the model's log_likelihood returned {} for particle {} (-inf is a zero "
                   "likelihood; NaN and +inf are not likelihoods)",
                   l, particle);
    return l;
  }

  Rng stream(std::uint64_t domain, std::size_t index) const {
    return Rng::stream(derive_seed(input_.seed, domain), index);
  }

  /// First stage of the auxiliary algorithms over the old particles:
  /// fs_raw_[i] = log p̂(z | xᵢ) (at the predicted mean or the Monte-Carlo
  /// average), max_lik_[i] and best_[i] for the rejection sampler, the
  /// acceptable ancestors, and the selection log-weights λ. False if every
  /// estimate is −inf.
  bool first_stage() {
    const std::size_t m = particles_.size();
    const bool monte_carlo = algorithm_ == ParticleFilterAlgorithm::AuxiliaryPFOptimal ||
                             options_.first_stage_weights_monte_carlo;
    fs_raw_.assign(m, -kInf);
    max_lik_.assign(m, -kInf);
    const bool keep_best =
        algorithm_ == ParticleFilterAlgorithm::AuxiliaryPFOptimal && options_.aux_optimal_mle;
    if (keep_best) best_.assign(particles_.states.begin(), particles_.states.end());
    parallel_for(m, team_, [&](std::size_t i) {
      if (prev_w_[i] == -kInf) return;  // never an ancestor
      const State& x = particles_.states[i];
      if (!input_.has_motion) {
        fs_raw_[i] = max_lik_[i] = loglik(x, i);
        return;
      }
      if (!monte_carlo) {
        if constexpr (has_predicted_mean()) {
          fs_raw_[i] = max_lik_[i] = loglik(static_cast<State>(model_.predicted_mean(x)), i);
        }
        return;
      }
      Rng rng = stream(2, i);
      double log_sum = -kInf;
      for (std::uint32_t k = 0; k < options_.max_search_samples; ++k) {
        State xk = move(x, rng);
        const double l = loglik(xk, i);
        log_sum = log_add_exp(log_sum, l);
        if (l > max_lik_[i]) {
          max_lik_[i] = l;
          if (keep_best) best_[i] = std::move(xk);
        }
      }
      fs_raw_[i] = log_sum - std::log(static_cast<double>(options_.max_search_samples));
    });
    double best = -kInf;
    for (const double f : fs_raw_) best = std::max(best, f);
    if (best == -kInf) return false;
    acceptable_.clear();
    accepted_.assign(m, 0);
    sel_w_.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      sel_w_[i] = prev_w_[i] + options_.pow_factor * fs_raw_[i];
      if (std::isfinite(fs_raw_[i]) && fs_raw_[i] >= best - options_.max_loglikelihood_dyn_range &&
          prev_w_[i] > -kInf) {
        acceptable_.push_back(i);
        accepted_[i] = 1;
      }
    }
    // The best particle is acceptable, so acceptable_ is not empty.
    return true;
  }

  /// MRPT's dynamic-range safeguard: an unacceptable ancestor of offspring n
  /// is replaced by a uniformly drawn acceptable one. Only when ancestors
  /// are drawn by weight: without selection a particle's own weight already
  /// accounts for its first-stage likelihood.
  std::size_t guard_ancestor(std::size_t n, std::size_t a) {
    if (!auxiliary() || !selected_ || accepted_[a]) return a;
    discarded_[n] = 1;
    Rng rng = stream(4, n);
    return acceptable_[rng.uniform_index(acceptable_.size())];
  }

  /// Marks, in index order, the first offspring of each ancestor in [begin, end).
  void mark_first_offspring(std::size_t begin, std::size_t end) {
    if (seen_.size() != particles_.size()) seen_.assign(particles_.size(), 0);
    first_.resize(end);
    for (std::size_t n = begin; n < end; ++n) {
      first_[n] = seen_[ancestors_[n]] ? 0 : 1;
      seen_[ancestors_[n]] = 1;
    }
  }

  void resize_outputs(std::size_t n) {
    states_.resize(n, particles_.states.front());
    log_w_.resize(n, -kInf);
    discarded_.resize(n, 0);
    timeouts_.resize(n, 0);
  }

  void fixed_size() {
    const std::size_t m = particles_.size();
    ancestors_.resize(m);
    resize_outputs(m);
    selected_ = false;
    if (auxiliary() && prev_normalized_ess() < options_.beta) {
      Rng rng = stream(5, 0);
      ancestors_ = resample_indices(options_.resampling_method, sel_w_, m, rng);
      selected_ = true;
    } else {
      for (std::size_t n = 0; n < m; ++n) ancestors_[n] = n;
    }
    for (std::size_t n = 0; n < m; ++n) ancestors_[n] = guard_ancestor(n, ancestors_[n]);
    mark_first_offspring(0, m);
    generate(0, m);
  }

  double prev_normalized_ess() const { return summarize_log_weights(prev_w_).normalized_ess; }

  /// KLD-sampling: offspring in chunks up to the count the sequential rule
  /// certainly reaches, then binned in order (see the header's comment).
  void adaptive() {
    selected_ = true;
    const std::vector<double>& weights = auxiliary() ? sel_w_ : prev_w_;
    const CumulativeSampler sampler(weights);
    std::size_t previous_bins = 0;
    if (kld_.min_samples_per_bin > 0.0) {
      KldBinSet old;
      for (const State& x : particles_.states) old.insert(bin_of(x));
      previous_bins = old.size();
    }
    KldBinSet bins;
    std::size_t done = 0;
    std::size_t target = kld_target_count(0, previous_bins, kld_);
    while (done < target) {
      ancestors_.resize(target);
      resize_outputs(target);
      for (std::size_t n = done; n < target; ++n) {
        Rng rng = stream(3, n);
        ancestors_[n] = guard_ancestor(n, sampler.draw(rng.uniform()));
      }
      mark_first_offspring(done, target);
      generate(done, target);
      for (std::size_t n = done; n < target; ++n) bins.insert(offspring_bins_[n]);
      done = target;
      target = kld_target_count(bins.size(), previous_bins, kld_);
    }
    result_.kld_bins = bins.size();
  }

  /// Makes offspring [begin, end) from their ancestors, in parallel (with
  /// KLD-sampling also their bins).
  void generate(std::size_t begin, std::size_t end) {
    const bool bins = options_.adaptive_sample_size;
    if (bins) offspring_bins_.resize(end);
    parallel_for(end - begin, team_, [&](std::size_t k) {
      propose(begin + k);
      if (bins) offspring_bins_[begin + k] = bin_of(states_[begin + k]);
    });
  }

  /// Offspring n of ancestor ancestors_[n]: its state and unnormalized
  /// log-weight.
  void propose(std::size_t n) {
    const std::size_t a = ancestors_[n];
    const State& x = particles_.states[a];
    Rng rng = stream(1, n);
    const double base = selected_ ? 0.0 : prev_w_[a];
    const double pow = options_.pow_factor;
    switch (algorithm_) {
      case ParticleFilterAlgorithm::StandardProposal:
        states_[n] = move(x, rng);
        log_w_[n] = input_.has_observation ? base + pow * loglik(states_[n], n) : base;
        return;
      case ParticleFilterAlgorithm::OptimalProposal:
        log_w_[n] = base + optimal_draw(x, n, rng);
        return;
      case ParticleFilterAlgorithm::AuxiliaryPFStandard: {
        states_[n] = move(x, rng);
        const double l = pow * loglik(states_[n], n);
        log_w_[n] = selected_ ? l - pow * fs_raw_[a] : prev_w_[a] + l;
        return;
      }
      case ParticleFilterAlgorithm::AuxiliaryPFOptimal:
        if (fs_raw_[a] == -kInf) {
          // Zero predictive likelihood (only without selection): the weight
          // is zero whatever the draw, and rejection sampling has no bound.
          states_[n] = move(x, rng);
        } else {
          rejection_draw(x, n, a, rng);
        }
        log_w_[n] = selected_ ? 0.0 : prev_w_[a] + pow * fs_raw_[a];
        return;
    }
  }

  /// OptimalProposal: K motion samples, one kept with probability ∝ exp(ℓ)
  /// (a weighted reservoir of size one), states_[n] set; returns the log
  /// predictive likelihood estimate log (1/K) Σ exp(ℓₖ).
  double optimal_draw(const State& x, std::size_t n, Rng& rng) {
    double log_sum = -kInf;
    bool have = false;
    for (std::uint32_t k = 0; k < options_.max_search_samples; ++k) {
      State xk = move(x, rng);
      const double l = options_.pow_factor * loglik(xk, n);
      log_sum = log_add_exp(log_sum, l);
      // Keep xk with probability exp(l) / Σ_{j≤k} exp(lⱼ): the survivor is
      // distributed ∝ exp(l). With every l so far −inf, keep the first.
      const double u = rng.uniform();
      if (!have || (log_sum > -kInf && u < std::exp(l - log_sum))) {
        states_[n] = std::move(xk);
        have = true;
      }
    }
    return log_sum - std::log(static_cast<double>(options_.max_search_samples));
  }

  /// AuxiliaryPFOptimal: rejection sampling of p(z | x)^pow p(x | x_a)
  /// against the first-stage maximum (raised when a candidate exceeds it).
  void rejection_draw(const State& x, std::size_t n, std::size_t a, Rng& rng) {
    double bound = max_lik_[a];
    double best_l = -kInf;
    bool use_mle = options_.aux_optimal_mle && first_[n];
    for (int attempt = 0; attempt < kMaxRejectionTries; ++attempt) {
      State candidate = use_mle ? best_[a] : move(x, rng);
      use_mle = false;
      const double l = loglik(candidate, n);
      const bool better = attempt == 0 || l > best_l;
      if (l > bound) bound = l;
      if (l > -kInf && rng.uniform() < std::exp(options_.pow_factor * (l - bound))) {
        states_[n] = std::move(candidate);
        return;
      }
      if (better) {
        best_l = l;
        states_[n] = std::move(candidate);
      }
    }
    timeouts_[n] = 1;  // states_[n] holds the best candidate
  }

  ParticleFilterStepResult finish() {
    const std::size_t n = states_.size();
    ParticleFilterStepResult& r = result_;
    r.particles_after = n;
    r.resampled = selected_;
    for (std::size_t i = 0; i < n; ++i) {
      r.discarded_ancestors += discarded_[i];
      r.rejection_timeouts += timeouts_[i];
    }
    const double log_total = log_sum_exp(log_w_);
    r.termination = input_.has_observation ? ParticleFilterTermination::Updated
                                           : ParticleFilterTermination::Predicted;
    if (log_total == -kInf) {
      // Zero likelihood everywhere: keep the prior weights.
      for (std::size_t i = 0; i < n; ++i) log_w_[i] = selected_ ? 0.0 : prev_w_[ancestors_[i]];
      r.termination = ParticleFilterTermination::Degenerate;
      r.log_evidence = -kInf;
      normalize_log_weights(log_w_);
    } else {
      if (input_.has_observation) {
        const double selection_norm = selected_ && auxiliary() ? log_sum_exp(sel_w_) : 0.0;
        r.log_evidence = selected_ ? selection_norm + log_total - std::log(static_cast<double>(n))
                                   : log_total;
      }
      for (double& w : log_w_) w -= log_total;  // normalized: −inf stays −inf
    }
    r.ess_before_resampling = summarize_log_weights(log_w_).normalized_ess;
    const bool may_resample = !options_.adaptive_sample_size && !auxiliary();
    if (may_resample && r.ess_before_resampling < options_.beta) {
      Rng rng = stream(5, 0);
      const std::vector<std::size_t> idx = resample_indices(options_.resampling_method, log_w_, n, rng);
      std::vector<State> resampled;
      resampled.reserve(n);
      for (const std::size_t i : idx) resampled.push_back(states_[i]);
      states_ = std::move(resampled);
      log_w_.assign(n, -std::log(static_cast<double>(n)));
      r.resampled = true;
    }
    particles_.states = std::move(states_);
    particles_.log_weights = std::move(log_w_);
    r.message = fmt::format("{}: {} -> {} particles, ESS/N {:.3f}{}{}{}", mrpt_name(algorithm_),
                            r.particles_before, r.particles_after, r.ess_before_resampling,
                            r.resampled ? ", resampled" : "",
                            r.termination == ParticleFilterTermination::Degenerate
                                ? ", every likelihood zero: observation ignored"
                                : "",
                            first_stage_note_);
    return r;
  }

  ParticleSet<State>& particles_;
  const Model& model_;
  const ParticleFilterOptions& options_;
  const KldOptions& kld_;
  const ParticleFilterStepInput& input_;
  ThreadTeam& team_;
  ParticleFilterAlgorithm algorithm_ = ParticleFilterAlgorithm::StandardProposal;
  ParticleFilterStepResult result_;
  std::string first_stage_note_;
  std::vector<double> prev_w_;    // normalized old log-weights
  std::vector<double> fs_raw_;    // first-stage log p̂(z | xᵢ), untempered
  std::vector<double> max_lik_;   // largest first-stage log-likelihood
  std::vector<State> best_;       // its sample (pfAuxFilterOptimal_MLE)
  std::vector<double> sel_w_;     // selection log-weights λ
  std::vector<std::size_t> acceptable_;
  std::vector<char> accepted_;
  bool selected_ = false;         // ancestors drawn by weight
  std::vector<std::size_t> ancestors_;
  std::vector<char> first_, seen_;
  std::vector<State> states_;
  std::vector<double> log_w_;
  std::vector<char> discarded_, timeouts_;
  std::vector<KldBin> offspring_bins_;  // KLD bin of each offspring (adaptive)
};

}  // namespace rove::detail
