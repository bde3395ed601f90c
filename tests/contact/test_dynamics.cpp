// RunDynamics on small spring-mass models whose exact answers are known: a bar hitting a
// rigid wall (1D wave: contact lasts 2L/c with stress rho c v0, rebound at -v0), a mass
// sliding to rest under Coulomb friction, the critical time step, and the stability
// guard.
#include <catch2/catch.hpp>
#include <limits>

#include "contact/dynamics.hpp"

using namespace contact;

namespace {

// Bar of length L = 1 m, E = rho = 1, cross-section 1 (wave speed c = 1 m/s), N linear
// elements along x, lumped or consistent mass. The model is 2D with decoupled unit
// springs/masses in y. The right end (node N) is the contact node; the wall is at gap 0.
DynamicModel Bar(int N, bool lumped) {
  const double h = 1.0 / N;
  const int n = 2 * (N + 1);
  std::vector<Eigen::Triplet<double>> tk, tm;
  for (int e = 0; e < N; ++e) {
    const int a = 2 * e, b = 2 * (e + 1);
    tk.insert(tk.end(), {{a, a, 1 / h}, {b, b, 1 / h}, {a, b, -1 / h}, {b, a, -1 / h}});
    if (lumped)
      tm.insert(tm.end(), {{a, a, h / 2}, {b, b, h / 2}});
    else
      tm.insert(tm.end(), {{a, a, h / 3}, {b, b, h / 3}, {a, b, h / 6}, {b, a, h / 6}});
  }
  for (int i = 0; i <= N; ++i) {
    tk.emplace_back(2 * i + 1, 2 * i + 1, 1.0);
    tm.emplace_back(2 * i + 1, 2 * i + 1, h);
  }
  DynamicModel model;
  model.dim = 2;
  model.K.resize(n, n);
  model.M.resize(n, n);
  model.K.setFromTriplets(tk.begin(), tk.end());
  model.M.setFromTriplets(tm.begin(), tm.end());
  model.load = [n](double, Eigen::VectorXd* f) { f->setZero(n); };
  ContactNode node;
  node.node = N;
  node.dofs[0] = 2 * N;
  node.dofs[1] = 2 * N + 1;
  node.normal = Eigen::Vector3d::UnitX();
  CompleteContactFrame(2, &node);
  node.area = 1.0;
  model.contact_nodes = {node};
  return model;
}

DynamicOptions BarImpact(const DynamicModel& model, double v0) {
  DynamicOptions o;
  o.end_time = 3.0;
  o.initial_state = InitialState::kPrescribed;
  o.u0 = Eigen::VectorXd::Zero(model.K.rows());
  o.v0 = Eigen::VectorXd::Zero(model.K.rows());
  for (Eigen::Index i = 0; i < o.v0.size(); i += 2) o.v0(i) = v0;
  return o;
}

}  // namespace

TEST_CASE("Critical time step of a bar: h/c lumped, h/(c sqrt 3) consistent",
          "[dynamics]") {
  const double h = 0.01;
  const CriticalTimeStep lumped =
      EstimateCriticalTimeStep(Bar(100, true).K, Bar(100, true).M);
  const CriticalTimeStep consistent =
      EstimateCriticalTimeStep(Bar(100, false).K, Bar(100, false).M);
  CHECK(lumped.converged);
  // Free-free bar: omega_max -> 2c/h from below as N grows; 100 elements: within 1e-3.
  CHECK_THAT(lumped.dt_crit, Catch::Matchers::WithinRel(h, 1e-3));
  CHECK_THAT(consistent.dt_crit, Catch::Matchers::WithinRel(h / std::sqrt(3.0), 1e-3));
}

TEST_CASE("Elastic bar hits a rigid wall: duration 2L/c, stress rho c v0, rebound -v0",
          "[dynamics][impact]") {
  const double v0 = 0.1;
  DynamicModel model = Bar(100, true);
  DynamicOptions o = BarImpact(model, v0);
  o.dt = 0.5 * EstimateCriticalTimeStep(model.K, model.M).dt_crit;
  double first = -1, last = -1, force_sum = 0;
  int force_count = 0;
  o.on_step = [&](const StepRecord& r, const Eigen::VectorXd&,
                  const ContactSystem::Result&, double) {
    if (r.normal_force_sum > 0.01 * v0) {  // 1% of rho c v0 A: above solver noise
      if (first < 0) first = r.time;
      last = r.time;
      if (r.time > 0.2 && r.time < 1.8) {
        force_sum += r.normal_force_sum;
        ++force_count;
      }
    }
  };
  const DynamicSummary s = RunDynamics(model, o);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  // Contact duration 2L/c = 2 s, within 3 time steps.
  CHECK(std::abs((last - first) - 2.0) <= 3 * o.dt);
  // Mean contact force over the plateau = rho c v0 A = 0.1 N within 1%.
  CHECK_THAT(force_sum / force_count, Catch::Matchers::WithinRel(0.1, 0.01));
  // Rebound: mean velocity after separation is -v0 within 1% (momentum / mass).
  const StepRecord& end = s.records.back();
  CHECK_THAT(end.kinetic, Catch::Matchers::WithinRel(0.5 * v0 * v0, 0.02));
  // The discrete energy balance closes to round-off; no penetration beyond tolerance.
  CHECK(s.energy_balance_error < 1e-12 * 0.5 * v0 * v0 * 1e3);
  CHECK(s.max_penetration < 1e-12);
}

TEST_CASE("Ipopt and Fischer-Burmeister agree on every step of a frictionless run",
          "[dynamics][ipopt]") {
  DynamicModel model = Bar(20, true);
  DynamicOptions o = BarImpact(model, 0.1);
  o.end_time = 2.5;
  o.dt = 0.5 * EstimateCriticalTimeStep(model.K, model.M).dt_crit;
  o.compare_with_ipopt = true;
  // Relative to the increment du (~2.5e-3 m), 1e-8 needs the gap of the active node to
  // 1e-11 m: FB at ||Phi||_inf <= 1e-12 and Ipopt at tol = 1e-14 (its default here).
  o.ncp.tolerance = 1e-12;
  const DynamicSummary s = RunDynamics(model, o);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  for (const StepRecord& r : s.records) REQUIRE(r.ipopt_relative_difference >= 0.0);
  CHECK(s.max_ipopt_relative_difference < 1e-8);
}

TEST_CASE("A mass sliding on a floor with Coulomb friction stops at v0 / (mu g)",
          "[dynamics][friction]") {
  // One node of mass m = 2 kg on the floor y >= 0 (outward normal -e_y), gravity g = 10
  // m/s^2, initial velocity v0 = 3 m/s along x, mu = 0.5: deceleration mu g = 5 m/s^2,
  // stop at t = 0.6 s after sliding v0^2 / (2 mu g) = 0.9 m. No stiffness: K = 0.
  const double m = 2.0, g = 10.0, v0 = 3.0, mu = 0.5;
  DynamicModel model;
  model.dim = 2;
  model.K.resize(2, 2);
  model.M.resize(2, 2);
  model.M.insert(0, 0) = m;
  model.M.insert(1, 1) = m;
  model.load = [&](double, Eigen::VectorXd* f) { *f = Eigen::Vector2d(0.0, -m * g); };
  ContactNode node;
  node.dofs[0] = 0;  // dofs of the global components x, y
  node.dofs[1] = 1;
  node.normal = -Eigen::Vector3d::UnitY();
  CompleteContactFrame(2, &node);
  model.contact_nodes = {node};
  DynamicOptions o;
  o.dt = 1e-3;
  o.end_time = 1.0;
  o.friction_coefficient = mu;
  o.initial_state = InitialState::kPrescribed;
  o.u0 = Eigen::Vector2d::Zero();
  o.v0 = Eigen::Vector2d(v0, 0.0);
  double stop_time = -1.0;
  Eigen::VectorXd previous = Eigen::Vector2d::Zero();
  o.on_step = [&](const StepRecord& r, const Eigen::VectorXd& u,
                  const ContactSystem::Result&, double) {
    // Stopped: velocity below 1e-6 m/s (the solver leaves ~1e-8 m/s of round-off).
    if (stop_time < 0 && r.step > 1 && std::abs(u(0) - previous(0)) < 1e-6 * o.dt)
      stop_time = r.time;
    previous = u;
  };
  const DynamicSummary s = RunDynamics(model, o);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  // The friction bound lags one step (thesis eq. 70) and the prescribed start has no
  // normal force yet, so allow a few steps of error.
  CHECK(std::abs(stop_time - v0 / (mu * g)) <= 3 * o.dt);
  CHECK_THAT(s.u(0), Catch::Matchers::WithinAbs(v0 * v0 / (2 * mu * g), 3 * v0 * o.dt));
  CHECK(std::abs(s.u(1)) < 1e-12);  // stays on the floor
  // All kinetic energy went into friction.
  CHECK_THAT(s.records.back().friction_dissipation,
             Catch::Matchers::WithinRel(0.5 * m * v0 * v0, 0.01));
}

TEST_CASE(
    "A time step above dt_crit is refused with both values, or blows up when forced",
    "[dynamics][stability]") {
  DynamicModel model = Bar(50, true);
  DynamicOptions o = BarImpact(model, 0.1);
  const double dt_crit = EstimateCriticalTimeStep(model.K, model.M).dt_crit;
  o.dt = 1.5 * dt_crit;
  DynamicSummary s = RunDynamics(model, o);
  CHECK(s.status == DynamicStatus::kRefusedUnstable);
  CHECK_THAT(s.message, Catch::Contains("exceeds the critical step dt_crit"));
  CHECK(s.steps == 0);
  o.allow_unstable_time_step = true;
  s = RunDynamics(model, o);
  CHECK(s.status == DynamicStatus::kEnergyBlowUp);
  CHECK_THAT(s.message, Catch::Contains("energy blow-up"));
}

TEST_CASE("RunDynamics rejects inconsistent input", "[dynamics][errors]") {
  DynamicModel model = Bar(4, true);
  DynamicOptions o = BarImpact(model, 0.1);
  o.dt = -1.0;
  CHECK_THROWS_WITH(RunDynamics(model, o), Catch::Contains("dt must be > 0"));
  o.dt = 1e-3;
  o.friction_coefficient = 0.3;
  const StepMethod method = o.step_method;
  o.step_method = StepMethod::kIpopt;
  CHECK_THROWS_WITH(RunDynamics(model, o), Catch::Contains("frictionless contact only"));
  o.step_method = method;
  o.v0 = Eigen::VectorXd::Zero(3);
  CHECK_THROWS_WITH(RunDynamics(model, o), Catch::Contains("must have size"));
  o.v0 = Eigen::VectorXd::Zero(model.K.rows());
  DynamicModel skewed = model;
  skewed.K.coeffRef(0, 2) += 0.5;  // K_02 != K_20
  CHECK_THROWS_WITH(RunDynamics(skewed, o), Catch::Contains("K and M must be symmetric"));
  DynamicModel massless = model;
  massless.M.coeffRef(2, 2) = 0.0;  // a zero lumped mass
  CHECK_THROWS_WITH(RunDynamics(massless, o),
                    Catch::Contains("mass matrix is not positive definite"));
  DynamicModel indefinite = Bar(4, false);
  indefinite.M.coeffRef(0, 2) = indefinite.M.coeffRef(2, 0) =
      1.0;  // off-diagonal > diagonal
  CHECK_THROWS_WITH(RunDynamics(indefinite, o),
                    Catch::Contains("not positive definite (Cholesky failed)"));
  CHECK_THROWS_WITH(
      EstimateCriticalTimeStep(indefinite.K, indefinite.M),
      Catch::Contains(
          "EstimateCriticalTimeStep: the mass matrix is not positive definite"));
  // Before: the step count overflowed (0 steps "completed") or reserved 1e10 records.
  DynamicOptions long_run = BarImpact(model, 0.1);
  long_run.dt = 1e-300;
  CHECK_THROWS_WITH(RunDynamics(model, long_run),
                    Catch::Contains("time steps; at most 1e+06 are accepted"));
  long_run.dt = 1e-3;
  long_run.end_time = 1e7;  // 1e10 steps
  CHECK_THROWS_WITH(RunDynamics(model, long_run),
                    Catch::Contains("1e+10 time steps; at most 1e+06"));
  long_run.end_time = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(RunDynamics(model, long_run),
                    Catch::Contains("end_time must be finite"));
  // K scaled to overflow: omega_max = inf, dt_crit = 0 is an error naming E and rho, not
  // a run.
  DynamicModel overflowing = model;
  overflowing.K *= 1e306;
  CHECK_THROWS_WITH(RunDynamics(overflowing, o),
                    Catch::Contains("is not a positive finite number"));
}
