#include "step/step_method.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace contact::internal {
namespace {

// Rates and counts of the cost model of StepMethod::kAuto (PredictStepCost). The rates: a
// solve with M's CHOLMOD factor took 0.23-0.29 ms for 4 x 1.3e5 flops on the rocker
// (examples/scenes/rocker_incline_3d.toml), the products and load of its steps 0.13 ms.
// The counts per step: fitted to the time of each method on every example scene in an
// earlier run of benchmarks/results/contact/step_cost/ (docs/contact-steps.md:
// the fit that kept auto closest to the fastest method on all of them); measured there,
// the sparse step takes 1.5-2x the Newton steps of the condensed one (it runs
// Alart-Curnier alone) and 4-10 solves with M per Newton step.
constexpr double kSparseFlopRate =
    2.0e9;  // [flop/s] sparse products and triangular solves
constexpr double kDenseProductRate = 2.0e9;  // [flop/s] products with W (memory bound)
constexpr double kDenseLuRate = 5.0e9;  // [flop/s] dense LU (blocked, n in the hundreds)
constexpr double kCondensedNewtonPerStep = 0.3;  // Newton steps per time step, condensed
constexpr double kSparseNewtonPerStep = 0.8;     // Newton steps per time step, sparse
constexpr double kKrylovPerNewton =
    8.0;  // GMRES iterations per Newton step (sparse step)
constexpr double kCoupledFraction =
    0.3;  // contacts in a Newton step's dense LU (condensed)
constexpr double kDenseProductsPerStep = 2.0;  // products with W per step (condensed)
constexpr double kDensePassesPerNewton =
    20.0;  // passes over W per Newton step (condensed)
// [s] set-up of the sparse step's matrix-free Newton per Newton step, whatever its size:
// block_drop_2d (22 unknowns, lumped M) took ~0.4 ms per sparse Newton step, the
// condensed step 0.05 ms.
constexpr double kSparseNewtonSetup = 1e-4;

bool Friction(const DynamicOptions& options) {
  return options.friction_coefficient > 0.0;
}

}  // namespace

StepCostPrediction PredictStepCost(const DynamicModel& model,
                                   const DynamicOptions& options,
                                   const MassInverse& mass) {
  StepCostPrediction p;
  const bool friction = Friction(options);
  const bool lagged =
      friction && options.friction_formulation == FrictionFormulation::kLaggedBound;
  const double n_c = static_cast<double>(model.contact_nodes.size()), dim = model.dim;
  // Every method: the products M du and K u^{k+1}, the load and the accuracy check (~20
  // N).
  const double common = 2.0 *
                            static_cast<double>(model.M.nonZeros() + model.K.nonZeros()) /
                            kSparseFlopRate +
                        20.0 * static_cast<double>(model.M.rows()) / kSparseFlopRate;
  // The explicit step: node by node, in closed form; the same step as the others only
  // with a lumped M (the same mass in every component of a contact node) and friction (if
  // any) as the lagged bound.
  if (mass.diagonal() && (!friction || lagged) &&
      UnequalLumpedMassNode(model.dim, model.M.diagonal(), model.contact_nodes) < 0)
    p.explicit_seconds = common;
  const double solve =
      4.0 * mass.factor_nonzeros() / kSparseFlopRate;  // one solve with M
  const double steps =
      std::max(1.0, std::floor((options.end_time - options.start_time) / options.dt));
  // Condensed: n_u contact unknowns; W formed by n_u solves with M once (and inverted
  // once, n_u^3, frictionless), per step two solves with M and a few products with the
  // dense W (2 n_u^2 each), per Newton step a dense LU over the coupled contacts.
  const double n_u = friction ? dim * n_c : n_c;
  const double coupled = kCoupledFraction * n_u;
  p.condensed_seconds =
      common + 2.0 * solve + kDenseProductsPerStep * 2.0 * n_u * n_u / kDenseProductRate +
      kCondensedNewtonPerStep * (2.0 / 3.0 * coupled * coupled * coupled / kDenseLuRate +
                                 kDensePassesPerNewton * n_u * n_u / kDenseProductRate) +
      (n_u * solve + (friction ? 0.0 : n_u * n_u * n_u / kDenseLuRate)) / steps;
  // Sparse (implicit Coulomb only): per step two solves with M, per Newton step GMRES
  // iterations + 2 products with W, each one solve with M.
  if (!lagged)
    p.sparse_seconds =
        common + 2.0 * solve +
        kSparseNewtonPerStep * ((kKrylovPerNewton + 2.0) * solve + kSparseNewtonSetup);
  // The cheapest that applies; condensed when nothing else does.
  p.choice = StepMethod::kCondensed;
  double best = p.condensed_seconds;
  if (p.sparse_seconds >= 0.0 && p.sparse_seconds < best) {
    p.choice = StepMethod::kSparse;
    best = p.sparse_seconds;
  }
  if (p.explicit_seconds >= 0.0 && p.explicit_seconds < best)
    p.choice = StepMethod::kExplicit;
  return p;
}

StepMethod ResolveStepMethod(const DynamicModel& model, const DynamicOptions& options,
                             const MassInverse& mass) {
  const bool friction = Friction(options);
  if (options.step_method == StepMethod::kSparse && friction &&
      options.friction_formulation == FrictionFormulation::kLaggedBound)
    throw std::invalid_argument(
        "contact::RunDynamics: the sparse step poses friction as implicit Coulomb "
        "(coulomb-fc) only, not with the lagged bound; use the condensed or full "
        "step for the lagged bound (lagged-bound)");
  if (options.step_method != StepMethod::kAuto) return options.step_method;
  return PredictStepCost(model, options, mass).choice;
}

std::unique_ptr<StepAlgorithm> MakeStepAlgorithm(const DynamicModel& model,
                                                 const DynamicOptions& options,
                                                 MassInverse* mass, double m_max) {
  ncp::Options ncp_options = options.ncp;
  const bool friction = Friction(options);
  switch (ResolveStepMethod(model, options, *mass)) {
    case StepMethod::kFull:
      return MakeFullStep(model, m_max, ncp_options, friction);
    case StepMethod::kCondensed:
      if (friction && options.friction_formulation == FrictionFormulation::kCoulombFc)
        return MakeCoulombFcStep(model, mass, m_max, options);
      // The condensed system's matrix W^-1 is dense: a dense LU beats a sparse one at any
      // size.
      if (ncp_options.linear_solver == ncp::LinearSolverType::kAuto)
        ncp_options.linear_solver = ncp::LinearSolverType::kDenseLU;
      return MakeCondensedStep(model, mass, m_max, ncp_options, friction);
    case StepMethod::kExplicit:
      return MakeExplicitStep(model, m_max);
    case StepMethod::kSparse:
      return MakeSparseStep(model, mass, m_max, options);
    case StepMethod::kIpopt:
      return MakeIpoptStep(model, m_max, options.ncp.tolerance);
    case StepMethod::kAuto:
      break;  // resolved above
  }
  throw std::invalid_argument("contact::RunDynamics: unknown step method");
}

}  // namespace contact::internal
