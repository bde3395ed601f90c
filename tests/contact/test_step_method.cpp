// The step methods behind internal::StepAlgorithm (contact/src/step/step_method.hpp),
// each solving the same step through the interface: every result is checked against the
// step's equations, recomputed here from the model (S du + q = contact forces, Signorini,
// Tresca), and the methods against each other. A new step method joins the GENERATE lists
// below.
#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "block_on_floor.hpp"
#include "contact/scene.hpp"
#include "mass_inverse.hpp"
#include "step/step_method.hpp"
#include "step_accuracy.hpp"

namespace {

using namespace contact;

// A 2 x 1 m steel block of 8 x 4 Q4, lumped mass, resting on the floor y >= 0 (gap 0) and
// moving with v = (1, -1) m/s into it: every bottom node presses and slides.
SceneModel PressedBlock() {
  const Scene scene = testing::SteelBlockOnFloor(MassKind::kLumped);
  return BuildSceneModel(scene);
}

struct Step {
  Eigen::VectorXd q, u, bound, guess, f, Ku;
  internal::StepScales scales;
  double force_scale = 0.0, m_max = 0.0;
};

// Step 0 from u^0 = 0, u^{-1} = -dt v: Q = K u^0 - f - M (u^0 - u^{-1}) / dt^2 (eq. 73),
// q = Q / force_scale; Tresca bounds g_c = 0.3 times the weight-and-impact force M v / dt
// of one node (system units), or none.
Step MakeStep(const SceneModel& built, bool friction) {
  const DynamicModel& model = built.model;
  const Eigen::Index n = model.M.rows();
  const double dt = built.options.dt;
  Step s;
  s.m_max = internal::MaxAbsEntry(model.M);
  s.force_scale = s.m_max / (dt * dt);
  s.u = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd velocity(n);
  for (Eigen::Index i = 0; i < n; ++i)
    velocity(i) = i % 2 == 0 ? 1.0 : -1.0;  // (1, -1) m/s
  s.f.resize(n);
  model.load(0.0, &s.f);
  s.Ku = model.K * s.u;
  const Eigen::VectorXd Q = s.Ku - s.f - model.M * velocity / dt;
  s.q = Q / s.force_scale;
  s.guess = dt * velocity;
  if (friction)
    s.bound =
        Eigen::VectorXd::Constant(static_cast<Eigen::Index>(model.contact_nodes.size()),
                                  0.3 * s.m_max * 1.0 / dt / s.force_scale);
  s.scales = internal::ComputeStepScales(s.f, s.Ku, 0.0, s.guess, model.contact_nodes,
                                         s.u, s.m_max, dt);
  return s;
}

// The step's equations, from the model: largest violation in system units (forces) and
// metres (gaps, slips).
struct Violation {
  double equilibrium = 0.0, signorini = 0.0, friction = 0.0;
};
Violation Check(const SceneModel& built, const Step& s, const ContactSystem::Result& r) {
  const DynamicModel& model = built.model;
  Violation v;
  Eigen::VectorXd residual =
      model.M * r.x / s.m_max + s.q;  // S du + q minus the contact forces
  for (size_t i = 0; i < model.contact_nodes.size(); ++i) {
    const ContactNode& node = model.contact_nodes[i];
    const auto c = static_cast<Eigen::Index>(i);
    const double lambda = r.normal_force(c), tau = r.tangent_force(0, c);
    double un = 0.0, slip = 0.0;
    for (int a = 0; a < model.dim; ++a) {
      if (node.dofs[a] < 0) continue;
      residual(node.dofs[a]) -= -lambda * node.normal(a) + tau * node.tangent1(a);
      un += node.normal(a) * (s.u(node.dofs[a]) + r.x(node.dofs[a]));
      slip += node.tangent1(a) * r.x(node.dofs[a]);
    }
    const double gap = node.gap - un;
    v.signorini =
        std::max({v.signorini, -gap, -lambda, std::min(std::abs(gap), std::abs(lambda))});
    const double g = s.bound.size() ? s.bound(c) : 0.0;
    v.friction = std::max(v.friction, std::abs(tau) - g);
    // Sliding (|tau| = g): tau opposes the slip; sticking (|tau| < g): no slip.
    if (std::abs(slip) > 1e-9 * s.scales.displacement)
      v.friction = std::max(v.friction, std::abs(tau + std::copysign(g, slip)));
  }
  v.equilibrium = residual.lpNorm<Eigen::Infinity>();
  return v;
}

ContactSystem::Result SolveWith(
    StepMethod method, ncp::NcpFunction function, const SceneModel& built, const Step& s,
    bool friction, FrictionFormulation formulation = FrictionFormulation::kLaggedBound) {
  DynamicOptions options = built.options;
  options.friction_formulation = formulation;
  options.step_method = method;
  options.ncp.ncp_function = function;
  options.friction_coefficient = friction ? 0.3 : 0.0;
  internal::MassInverse mass(built.model.M, "test: ");
  const auto algorithm =
      internal::MakeStepAlgorithm(built.model, options, &mass, s.m_max);
  ContactSystem::Result result;
  Eigen::VectorXd gaps(static_cast<Eigen::Index>(built.model.contact_nodes.size()));
  for (size_t c = 0; c < built.model.contact_nodes.size(); ++c)
    gaps(static_cast<Eigen::Index>(c)) = built.model.contact_nodes[c].gap;
  const internal::StepData data{s.q,      s.u,           s.bound, s.guess,
                                s.scales, s.force_scale, gaps};
  const internal::StepOutcome outcome = algorithm->Solve(data, &result);
  CAPTURE(outcome.status);
  REQUIRE(outcome.ok);
  CHECK(outcome.status == "converged");
  CHECK(outcome.implicit_friction_bound ==
        (friction && (method == StepMethod::kSparse ||
                      (method == StepMethod::kCondensed &&
                       formulation == FrictionFormulation::kCoulombFc))));
  return result;
}

}  // namespace

TEST_CASE(
    "Step methods through the interface: the step equations hold, the methods agree",
    "[contact][dynamics][step_method]") {
  const SceneModel built = PressedBlock();
  const bool friction = GENERATE(true, false);
  CAPTURE(friction);
  const Step s = MakeStep(built, friction);
  const ContactSystem::Result full = SolveWith(
      StepMethod::kFull, ncp::NcpFunction::kFischerBurmeister, built, s, friction);
  const double force = s.scales.force / s.force_scale;  // system units
  const double tol = 1e-8;
  // The step is a real contact step: every contact node pushes.
  CHECK((full.normal_force.array() > 0.0).all());
  auto [method, function] = GENERATE(table<StepMethod, ncp::NcpFunction>(
      {{StepMethod::kFull, ncp::NcpFunction::kFischerBurmeister},
       {StepMethod::kFull, ncp::NcpFunction::kMin},
       {StepMethod::kCondensed, ncp::NcpFunction::kFischerBurmeister},
       {StepMethod::kCondensed, ncp::NcpFunction::kPenalizedFischerBurmeister},
       {StepMethod::kExplicit, ncp::NcpFunction::kFischerBurmeister},
       {StepMethod::kSparse, ncp::NcpFunction::kFischerBurmeister},
       {StepMethod::kIpopt, ncp::NcpFunction::kFischerBurmeister}}));
  if (method == StepMethod::kIpopt && friction) return;  // Ipopt: frictionless only
  if (method == StepMethod::kSparse && friction)
    return;  // implicit Coulomb: next test case
  CAPTURE(ToString(method), ncp::ToString(function));
  const ContactSystem::Result r = SolveWith(method, function, built, s, friction);
  const Violation v = Check(built, s, r);
  CHECK(v.equilibrium <= tol * force);
  CHECK(v.signorini <= tol * std::max(force, s.scales.displacement));
  CHECK(v.friction <= tol * force);
  CHECK((r.x - full.x).lpNorm<Eigen::Infinity>() <=
        tol * full.x.lpNorm<Eigen::Infinity>());
  CHECK((r.normal_force - full.normal_force).lpNorm<Eigen::Infinity>() <=
        tol * full.normal_force.lpNorm<Eigen::Infinity>());
}

TEST_CASE("Step methods: a model a method cannot take is refused at set-up",
          "[contact][dynamics][step_method]") {
  SceneModel built = PressedBlock();
  built.model.M.coeffRef(0, 2) = built.model.M.coeffRef(2, 0) =
      1e-3 * built.model.M.coeff(0, 0);
  DynamicOptions options = built.options;
  options.step_method = StepMethod::kExplicit;
  internal::MassInverse mass(built.model.M, "test: ");
  CHECK_THROWS_WITH(internal::MakeStepAlgorithm(built.model, options, &mass, 1.0),
                    Catch::Contains("lumped (diagonal) mass"));
}

TEST_CASE(
    "Condensed step with implicit Coulomb (ncp::fc): the step equations hold with the "
    "bound f_c lambda^{k+1}; eq. 94 given that bound finds the same step",
    "[contact][dynamics][step_method]") {
  const SceneModel built = PressedBlock();
  Step s = MakeStep(built, true);
  const ContactSystem::Result r =
      SolveWith(StepMethod::kCondensed, ncp::NcpFunction::kFischerBurmeister, built, s,
                true, FrictionFormulation::kCoulombFc);
  CHECK((r.normal_force.array() > 0.0).all());
  // A Coulomb solution is the (unique) Tresca solution for its own bound f_c lambda.
  s.bound = 0.3 * r.normal_force;
  const double force = s.scales.force / s.force_scale, tol = 1e-8;
  const Violation v = Check(built, s, r);
  CHECK(v.equilibrium <= tol * force);
  CHECK(v.signorini <= tol * std::max(force, s.scales.displacement));
  CHECK(v.friction <= tol * force);
  const ContactSystem::Result full =
      SolveWith(StepMethod::kFull, ncp::NcpFunction::kFischerBurmeister, built, s, true);
  CHECK((r.x - full.x).lpNorm<Eigen::Infinity>() <=
        tol * full.x.lpNorm<Eigen::Infinity>());
  CHECK((r.normal_force - full.normal_force).lpNorm<Eigen::Infinity>() <=
        tol * full.normal_force.lpNorm<Eigen::Infinity>());
  // The block slides: every bottom node slips and its friction force is at the bound.
  for (Eigen::Index c = 0; c < r.normal_force.size(); ++c)
    CHECK_THAT(std::abs(r.tangent_force(0, c)),
               Catch::Matchers::WithinRel(0.3 * r.normal_force(c), 1e-8));
  // The sparse step (W applied, not formed) finds the same step.
  const ContactSystem::Result sparse =
      SolveWith(StepMethod::kSparse, ncp::NcpFunction::kFischerBurmeister, built, s, true,
                FrictionFormulation::kCoulombFc);
  CHECK((sparse.x - r.x).lpNorm<Eigen::Infinity>() <=
        tol * r.x.lpNorm<Eigen::Infinity>());
  CHECK((sparse.normal_force - r.normal_force).lpNorm<Eigen::Infinity>() <=
        tol * r.normal_force.lpNorm<Eigen::Infinity>());
}

TEST_CASE("The sparse step refuses the thesis friction formulation",
          "[contact][dynamics][step_method]") {
  const SceneModel built = PressedBlock();
  DynamicOptions options = built.options;
  options.step_method = StepMethod::kSparse;
  options.friction_coefficient = 0.3;
  options.friction_formulation = FrictionFormulation::kLaggedBound;
  internal::MassInverse mass(built.model.M, "test: ");
  CHECK_THROWS_WITH(internal::MakeStepAlgorithm(built.model, options, &mass, 1.0),
                    Catch::Contains("implicit Coulomb (coulomb-fc) only"));
}

TEST_CASE("auto: the method of least predicted cost per step",
          "[contact][dynamics][step_method]") {
  const MassKind kind = GENERATE(MassKind::kLumped, MassKind::kConsistent);
  CAPTURE(kind == MassKind::kLumped ? "lumped" : "consistent");
  const SceneModel built = BuildSceneModel(testing::SteelBlockOnFloor(kind));
  const DynamicModel& model = built.model;
  internal::MassInverse mass(model.M, "test: ");
  DynamicOptions options = built.options;  // step_method = kAuto by default
  REQUIRE(options.step_method == StepMethod::kAuto);
  for (const double friction : {0.0, 0.3})
    for (const FrictionFormulation formulation :
         {FrictionFormulation::kCoulombFc, FrictionFormulation::kLaggedBound}) {
      CAPTURE(friction, ToString(formulation));
      options.friction_coefficient = friction;
      options.friction_formulation = formulation;
      const StepCostPrediction p = internal::PredictStepCost(model, options, mass);
      const bool lagged =
          friction > 0.0 && formulation == FrictionFormulation::kLaggedBound;
      // Explicit only with a lumped M where it solves the same step; sparse not with the
      // lagged bound; condensed always.
      CHECK((p.explicit_seconds > 0.0) ==
            (kind == MassKind::kLumped && !(friction > 0.0 && !lagged)));
      CHECK((p.sparse_seconds > 0.0) == !lagged);
      CHECK(p.condensed_seconds > 0.0);
      // The choice is the cheapest that applies, and what ResolveStepMethod runs.
      double best = p.condensed_seconds;
      for (const double t : {p.explicit_seconds, p.sparse_seconds})
        if (t > 0.0) best = std::min(best, t);
      const double chosen = p.choice == StepMethod::kExplicit    ? p.explicit_seconds
                            : p.choice == StepMethod::kSparse    ? p.sparse_seconds
                            : p.choice == StepMethod::kCondensed ? p.condensed_seconds
                                                                 : -1.0;
      CHECK(chosen == best);
      CHECK(internal::ResolveStepMethod(model, options, mass) == p.choice);
      // With a lumped M the explicit step costs least whenever it applies.
      if (p.explicit_seconds > 0.0) CHECK(p.choice == StepMethod::kExplicit);
    }
  options.step_method = StepMethod::kFull;  // an explicit choice stays
  CHECK(internal::ResolveStepMethod(model, options, mass) == StepMethod::kFull);
}

TEST_CASE("The sparse step counts its GMRES iterations per step and per run",
          "[contact][dynamics][step_method]") {
  // The block pressed onto the floor by gravity, sliding sideways (a prescribed start
  // velocity) for 20 steps: the sparse step's Newton systems are solved by GMRES, whose
  // iterations the records and the summary count (the records' sum is the summary's);
  // the condensed step runs no GMRES.
  const StepMethod method = GENERATE(StepMethod::kSparse, StepMethod::kCondensed);
  CAPTURE(ToString(method));
  Scene scene = testing::SteelBlockOnFloor(MassKind::kConsistent);
  scene.dynamics.step_method = method;
  scene.dynamics.end_time = 20 * scene.dynamics.dt;
  scene.dynamics.initial_state = InitialState::kPrescribed;
  scene.initial_velocity = Eigen::Vector2d(1.0, 0.0);
  const SceneModel built = BuildSceneModel(scene);
  const DynamicSummary s = RunDynamics(built.model, built.options);
  INFO(s.message);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  REQUIRE(s.newton_iterations > 0);
  long krylov = 0;
  for (const StepRecord& r : s.records) {
    krylov += r.krylov_iterations;
    // A Newton step needs at least one GMRES iteration (its direction is not zero).
    if (method == StepMethod::kSparse) CHECK(r.krylov_iterations >= r.newton_iterations);
  }
  CHECK(krylov == s.krylov_iterations);
  if (method == StepMethod::kSparse)
    CHECK(s.krylov_iterations >= s.newton_iterations);
  else
    CHECK(s.krylov_iterations == 0);
}
