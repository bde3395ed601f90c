#include "step/step_method.hpp"

#include <stdexcept>

namespace contact::internal {

StepMethod ResolveStepMethod(const DynamicModel& model, const DynamicOptions& options) {
  const bool friction = options.friction_coefficient > 0.0;
  if (options.step_method == StepMethod::kSparse && friction &&
      options.friction_formulation == FrictionFormulation::kLaggedBound)
    throw std::invalid_argument("contact::RunDynamics: the sparse step poses friction as implicit Coulomb "
                                "(coulomb-fc) only, not with the lagged bound; use the condensed or full "
                                "step for the lagged bound (lagged-bound)");
  if (options.step_method != StepMethod::kAuto) return options.step_method;
  if (friction && options.friction_formulation == FrictionFormulation::kLaggedBound) return StepMethod::kCondensed;
  // The size of the condensed step's dense system: dim unknowns per contact node with
  // friction, one (the normal) without.
  const size_t unknowns = model.contact_nodes.size() * static_cast<size_t>(friction ? model.dim : 1);
  return unknowns > static_cast<size_t>(kAutoSparseUnknowns) ? StepMethod::kSparse : StepMethod::kCondensed;
}

std::unique_ptr<StepAlgorithm> MakeStepAlgorithm(const DynamicModel& model,
                                                 const DynamicOptions& options,
                                                 MassInverse* mass, double m_max) {
  ncp::Options ncp_options = options.ncp;
  const bool friction = options.friction_coefficient > 0.0;
  switch (ResolveStepMethod(model, options)) {
    case StepMethod::kFull: return MakeFullStep(model, m_max, ncp_options, friction);
    case StepMethod::kCondensed:
      if (friction && options.friction_formulation == FrictionFormulation::kCoulombFc)
        return MakeCoulombFcStep(model, mass, m_max, options);
      // The condensed system's matrix W^-1 is dense: a dense LU beats a sparse one at any size.
      if (ncp_options.linear_solver == ncp::LinearSolverType::kAuto)
        ncp_options.linear_solver = ncp::LinearSolverType::kDenseLU;
      return MakeCondensedStep(model, mass, m_max, ncp_options, friction);
    case StepMethod::kExplicit: return MakeExplicitStep(model, m_max);
    case StepMethod::kSparse: return MakeSparseStep(model, mass, m_max, options);
    case StepMethod::kIpopt: return MakeIpoptStep(model, m_max, options.ncp.tolerance);
    case StepMethod::kAuto: break;  // resolved above
  }
  throw std::invalid_argument("contact::RunDynamics: unknown step method");
}

}  // namespace contact::internal
