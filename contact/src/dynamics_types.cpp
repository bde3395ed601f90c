// Names of the options of a dynamic run (contact/dynamics_types.hpp), as scene files and
// contact-sim spell them.
#include "contact/dynamics_types.hpp"

namespace contact {

const char* ToString(FrictionFormulation f) {
  switch (f) {
    case FrictionFormulation::kEq94: return "eq94";
    case FrictionFormulation::kCoulombFc: return "coulomb-fc";
  }
  return "unknown";
}

const char* ToString(StepMethod m) {
  switch (m) {
    case StepMethod::kFull: return "full";
    case StepMethod::kCondensed: return "condensed";
    case StepMethod::kExplicit: return "explicit";
    case StepMethod::kSparse: return "sparse";
    case StepMethod::kAuto: return "auto";
  }
  return "unknown";
}

const char* ToString(StepSolver s) {
  switch (s) {
    case StepSolver::kFischerBurmeister: return "fb";
    case StepSolver::kMin: return "min";
    case StepSolver::kPenalizedFischerBurmeister: return "penalized-fb";
    case StepSolver::kIpopt: return "ipopt";
  }
  return "unknown";
}

}  // namespace contact
