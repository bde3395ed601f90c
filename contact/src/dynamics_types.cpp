// Names of the options of a dynamic run (contact/dynamics_types.hpp), as scene files and
// contact-sim spell them.
#include "contact/dynamics_types.hpp"

namespace contact {

const char* ToString(FrictionFormulation f) {
  switch (f) {
    case FrictionFormulation::kLaggedBound:
      return "lagged-bound";
    case FrictionFormulation::kCoulombFc:
      return "coulomb-fc";
  }
  return "unknown";
}

const char* ToString(StepMethod m) {
  switch (m) {
    case StepMethod::kFull:
      return "full";
    case StepMethod::kCondensed:
      return "condensed";
    case StepMethod::kExplicit:
      return "explicit";
    case StepMethod::kSparse:
      return "sparse";
    case StepMethod::kIpopt:
      return "ipopt";
    case StepMethod::kAuto:
      return "auto";
  }
  return "unknown";
}

}  // namespace contact
