#include "rove/registration/termination.h"

namespace rove {

std::string_view to_string(RegistrationTermination t) {
  switch (t) {
    case RegistrationTermination::Converged: return "Converged";
    case RegistrationTermination::MaxIterations: return "MaxIterations";
    case RegistrationTermination::Degenerate: return "Degenerate";
    case RegistrationTermination::TooFewCorrespondences: return "TooFewCorrespondences";
    case RegistrationTermination::InvalidInput: return "InvalidInput";
    case RegistrationTermination::Diverged: return "Diverged";
    case RegistrationTermination::Stalled: return "Stalled";
  }
  return "Unknown";
}

}  // namespace rove
