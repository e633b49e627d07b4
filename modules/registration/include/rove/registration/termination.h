#pragma once
/// \file
/// Why a registration algorithm stopped. Every solver of rove::registration
/// returns one of these with a one-line message; only `Converged` means the
/// estimate is a trustworthy local optimum.

#include <string_view>

namespace rove {

/// Termination reason of a registration (closed form, ICP, GICP, NDT).
enum class RegistrationTermination {
  Converged,              ///< the convergence criterion was met on well-constrained geometry
  MaxIterations,          ///< the iteration cap was hit first; the last estimate is returned
  Degenerate,             ///< the geometry does not constrain every degree of freedom
                          ///< (a corridor, a single plane, collinear pairs); the estimate is
                          ///< arbitrary along the unconstrained directions
  TooFewCorrespondences,  ///< fewer matched pairs than the minimum; the estimate is the last
                          ///< one that had enough (the initial guess if none)
  InvalidInput,           ///< empty clouds or no finite point; the estimate is the initial guess
  Diverged,               ///< the cost or the estimate became non-finite, or the update grew
                          ///< without bound; the estimate is the last finite one
  Stalled,                ///< no step lowered the cost although the solver's step was still
                          ///< above the tolerances (a search direction that does not descend,
                          ///< a flat or noisy cost); the estimate is the last one that lowered
                          ///< it (the initial guess if none)
};

/// Name of a termination reason ("Converged", ...).
std::string_view to_string(RegistrationTermination t);

/// True only for RegistrationTermination::Converged.
constexpr bool succeeded(RegistrationTermination t) noexcept {
  return t == RegistrationTermination::Converged;
}

}  // namespace rove
