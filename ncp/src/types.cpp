#include "ncp/types.hpp"

namespace ncp {

const char* ToString(NcpFunction f) {
  switch (f) {
    case NcpFunction::kFischerBurmeister:
      return "fb";
    case NcpFunction::kMin:
      return "min";
    case NcpFunction::kPenalizedFischerBurmeister:
      return "penalized-fb";
  }
  return "unknown";
}

const char* ToString(LinearSolverType t) {
  switch (t) {
    case LinearSolverType::kAuto:
      return "auto";
    case LinearSolverType::kDenseLU:
      return "dense";
    case LinearSolverType::kSparseLU:
      return "sparse-lu";
    case LinearSolverType::kUmfpack:
      return "umfpack";
    case LinearSolverType::kKlu:
      return "klu";
    case LinearSolverType::kCholmod:
      return "cholmod";
  }
  return "unknown";
}

const char* ToString(TerminationType t) {
  switch (t) {
    case TerminationType::kNotSolved:
      return "not-solved";
    case TerminationType::kConverged:
      return "converged";
    case TerminationType::kMaxIterations:
      return "max-iterations";
    case TerminationType::kLineSearchFailure:
      return "line-search-failure";
    case TerminationType::kStationaryPoint:
      return "stationary-point";
    case TerminationType::kLinearSolverFailure:
      return "linear-solver-failure";
    case TerminationType::kNonFiniteValues:
      return "non-finite-values";
    case TerminationType::kEvaluationFailure:
      return "evaluation-failure";
    case TerminationType::kUserAbort:
      return "user-abort";
    case TerminationType::kTimeLimit:
      return "time-limit";
    case TerminationType::kInfeasible:
      return "infeasible";
    case TerminationType::kAtRoundoffFloor:
      return "at-roundoff-floor";
  }
  return "unknown";
}

}  // namespace ncp
