#include "step_method.hpp"

#include <stdexcept>

namespace contact::internal {
namespace {

ncp::NcpFunction FunctionOf(StepSolver s) {
  switch (s) {
    case StepSolver::kMin: return ncp::NcpFunction::kMin;
    case StepSolver::kPenalizedFischerBurmeister: return ncp::NcpFunction::kPenalizedFischerBurmeister;
    default: return ncp::NcpFunction::kFischerBurmeister;
  }
}

}  // namespace

std::unique_ptr<StepAlgorithm> MakeStepAlgorithm(const DynamicModel& model,
                                                 const DynamicOptions& options,
                                                 MassInverse* mass, double m_max) {
  if (options.solver == StepSolver::kIpopt) return MakeIpoptStep(model, m_max, options.ncp.tolerance);
  ncp::Options ncp_options = options.ncp;
  ncp_options.ncp_function = FunctionOf(options.solver);
  const bool friction = options.friction_coefficient > 0.0;
  switch (options.step_method) {
    case StepMethod::kFull: return MakeFullStep(model, m_max, ncp_options, friction);
    case StepMethod::kCondensed:
      if (friction && options.friction_formulation == FrictionFormulation::kCoulombFc)
        return MakeCoulombFcStep(model, mass, m_max, options);
      // The condensed system's matrix W^-1 is dense: a dense LU beats a sparse one at any size.
      if (ncp_options.linear_solver == ncp::LinearSolverType::kAuto)
        ncp_options.linear_solver = ncp::LinearSolverType::kDenseLU;
      return MakeCondensedStep(model, mass, m_max, ncp_options, friction);
    case StepMethod::kExplicit: return MakeExplicitStep(model, m_max);
  }
  throw std::invalid_argument("contact::RunDynamics: unknown step method");
}

}  // namespace contact::internal
