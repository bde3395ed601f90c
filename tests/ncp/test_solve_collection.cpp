// The solver on every problem of the collection, from every standard start point, with
// FB and min, over every linear-solver backend. Residuals are recomputed here from F, l,
// u.
#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/collection.hpp"
#include "solve_support.hpp"

using ncp::LinearSolverType;
using ncp::NcpFunction;
using ncp::TerminationType;
using ncp::Vector;
using namespace ncp::collection;
using namespace ncp::test;

namespace {

// A converged run (||Phi||_inf <= 1e-10) has natural residual below this: for FB,
// (2 - sqrt 2)|min(a, b)| <= |phi_FB(a, b)| (Tseng 1996, Lemma 3.1) gives 1.8e-10.
constexpr double kResidualTolerance = 1e-8;
constexpr int kDenseLimit = 50;

bool HonestFailure(TerminationType t) {
  return t == TerminationType::kStationaryPoint ||
         t == TerminationType::kLineSearchFailure || t == TerminationType::kMaxIterations;
}

// Failures of this solver observed on the standard collection that are NOT documented
// failures of the problems themselves (those are TestProblem::expected_failures). They
// are recorded here, with what was seen, and asserted to be honest (no false claim of
// convergence). If the solver improves, the assertion below fails: update this list.
struct KnownSolverFailure {
  const char* problem;
  const char* start;
  NcpFunction function;
  const char* observed;
  LinearSolverType backend = LinearSolverType::kAuto;  ///< kAuto: on every backend
};

const KnownSolverFailure kKnownSolverFailures[] = {
    // josephy from start 3 with FB reached a non-solution stationary point of psi_FB with
    // the monotone Armijo search (Algorithm 1, 235 iterations); the default nonmonotone
    // search (memory 3) converges in 28 (test_solver_globalization).
    {"mathiesen-mod", "hundred", NcpFunction::kMin,
     "min: max_iterations with ||Phi||_inf ~ 3.1 (psi_min is not differentiable; the "
     "Newton direction gives no Armijo decrease at the kinks)"},
    // The MCPLIB / GAMS problems added on 2026-11-24 (mcplib_nlp.hpp): min (not the
    // default)
    // fails on four of them, on every backend; FB converges on all (colvdual only through
    // Options::merit_restarts).
    {"colvdual", "hs117", NcpFunction::kMin, "min: max_iterations (500)"},
    {"colvdual", "zero", NcpFunction::kMin, "min: max_iterations (500)"},
    {"colvnlp", "hs117", NcpFunction::kMin,
     "min: stationary point of psi_min (324 iterations)"},
    {"colvnlp", "zero", NcpFunction::kMin,
     "min: stationary point of psi_min (79-121 iterations)"},
    {"transmcp", "gams", NcpFunction::kMin,
     "min: stationary point of psi_min (215 iterations)"},
    {"transmcp", "zero", NcpFunction::kMin,
     "min: stationary point of psi_min (214 iterations)"},
    {"hansmcp", "gams", NcpFunction::kMin, "min: max_iterations (500)"},
    // colvdual with FB converges only through the merit restarts, and only on some
    // backends:
    // the round-off of the factorization changes the path (dense LU: 298 and 162
    // iterations, SparseLU: 76 and 143; UMFPACK and KLU stall at ||Phi||_inf ~ 1.5e-2
    // after
    // 6 restarts, or reach max_iterations). kAuto picks dense LU for n = 20.
    {"colvdual", "hs117", NcpFunction::kFischerBurmeister,
     "FB: stationary point after 6 merit restarts (487 iterations)",
     LinearSolverType::kUmfpack},
    {"colvdual", "zero", NcpFunction::kFischerBurmeister,
     "FB: stationary point after 6 merit restarts (482 iterations)",
     LinearSolverType::kUmfpack},
    {"colvdual", "hs117", NcpFunction::kFischerBurmeister,
     "FB: stationary point after 6 merit restarts (499 iterations)",
     LinearSolverType::kKlu},
    {"colvdual", "zero", NcpFunction::kFischerBurmeister,
     "FB: max_iterations after 5 merit restarts", LinearSolverType::kKlu},
    // The GAMS model library problems of gams_equilibrium.hpp, observed on the three
    // sparse
    // backends (n > kDenseLimit) with the same outcome: vonthmcp (a known hard problem)
    // fails with min from the .gms start; FB stalls at a stationary point of psi_FB after
    // 77 iterations (||Phi||_inf ~ 9.8) and converges through the merit restarts (94
    // iterations in all). mr5mcp: FB converges (39).
    {"vonthmcp", "gams", NcpFunction::kMin,
     "min: max_iterations (500), ||Phi||_inf ~ 2.2e2"},
    {"mr5mcp", "gams", NcpFunction::kMin,
     "min: stationary point of psi_min after 21 iterations, ||Phi||_inf ~ 39"},
    // obstacle{1d,2d}-bump from "zero" with min ended in line-search failures while the
    // start (u0 = 0 < obstacle) was used as given; projected onto [l, u] it converges.
};

const KnownSolverFailure* FindKnownSolverFailure(const std::string& problem,
                                                 const std::string& start,
                                                 NcpFunction function,
                                                 LinearSolverType backend) {
  for (const KnownSolverFailure& f : kKnownSolverFailures) {
    if (problem == f.problem && start == f.start && function == f.function &&
        (f.backend == LinearSolverType::kAuto || f.backend == backend))
      return &f;
  }
  return nullptr;
}

}  // namespace

TEST_CASE("every collection problem from every start, FB and min, every backend",
          "[solver][collection]") {
  const LinearSolverType backend =
      GENERATE(LinearSolverType::kDenseLU, LinearSolverType::kSparseLU,
               LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  std::vector<TestProblem> problems = StandardCollection();
  for (TestProblem& p : problems) {
    // Dense LU only for small systems (the obstacle and random problems have 100 - 400
    // unknowns, and two-sided bounds add two slacks per unknown inside the solver).
    if (backend == LinearSolverType::kDenseLU && p.NumVariables() > kDenseLimit) continue;
    for (NcpFunction function : {NcpFunction::kFischerBurmeister, NcpFunction::kMin}) {
      for (const StartPoint& start : p.starts) {
        const Run run = SolveFrom(p, start.x, MakeOptions(function, backend));
        INFO(Describe(p, start.label, function, backend, run));
        CHECK(run.summary.linear_solver_used == backend);
        if (const ExpectedFailure* failure =
                p.FindExpectedFailure(start.label, function)) {
          INFO("documented failure: " << failure->reason);
          CHECK_FALSE(run.summary.IsSolutionUsable());
          CHECK(HonestFailure(run.summary.termination));
          CHECK(run.natural_residual > kResidualTolerance);
          continue;
        }
        if (const KnownSolverFailure* known =
                FindKnownSolverFailure(p.name, start.label, function, backend)) {
          INFO("known failure of this solver (not of the problem): " << known->observed);
          // Observed with a single strategy; the hybrid default (Options::hybrid) solves
          // many of them: then the claim is checked like any other.
          if (run.summary.IsSolutionUsable()) {
            CHECK(run.natural_residual <= kResidualTolerance);
            continue;
          }
          CHECK(HonestFailure(run.summary.termination));
          CHECK(run.natural_residual > kResidualTolerance);
          continue;
        }
        CHECK(run.summary.termination == TerminationType::kConverged);
        // Every problem here resolves the default 1e-10 in double precision, so the
        // round-off floor of the test (Options::roundoff_ulps) never decides.
        CHECK_FALSE(run.summary.roundoff_limited);
        CHECK(run.natural_residual <= kResidualTolerance);
        if (p.isolated_solutions && !p.solutions.empty() &&
            run.summary.IsSolutionUsable()) {
          // nash5's reference is quoted to 4 decimals; the rest are exact.
          const double distance_tolerance = p.name == "nash5" ? 1e-4 : 1e-6;
          CHECK(DistanceToNearest(run.x, p.solutions) <= distance_tolerance);
        }
      }
    }
  }
}

TEST_CASE("kojshin: all 8 MCPLIB starts reach one of the two known solutions",
          "[solver][collection]") {
  const LinearSolverType backend =
      GENERATE(LinearSolverType::kDenseLU, LinearSolverType::kSparseLU,
               LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  TestProblem p = KojimaShindo();
  const Vector degenerate = p.solutions[0];     // (sqrt(6)/2, 0, 0, 1/2)
  const Vector nondegenerate = p.solutions[1];  // (1, 0, 3, 0)
  for (const StartPoint& start : p.starts) {
    const Run run =
        SolveFrom(p, start.x, MakeOptions(NcpFunction::kFischerBurmeister, backend));
    INFO(Describe(p, start.label, NcpFunction::kFischerBurmeister, backend, run));
    REQUIRE(run.summary.termination == TerminationType::kConverged);
    CHECK(run.natural_residual <= kResidualTolerance);
    const double d0 = (run.x - degenerate).lpNorm<Eigen::Infinity>();
    const double d1 = (run.x - nondegenerate).lpNorm<Eigen::Infinity>();
    INFO("distance to (sqrt6/2,0,0,1/2): " << d0 << ", to (1,0,3,0): " << d1);
    CHECK(std::min(d0, d1) <= 1e-6);
  }
}

TEST_CASE("modified Mathiesen: any point of the solution set is accepted",
          "[solver][collection]") {
  TestProblem p = ModifiedMathiesen();
  for (NcpFunction function : {NcpFunction::kFischerBurmeister, NcpFunction::kMin}) {
    for (const StartPoint& start : p.starts) {
      const Run run =
          SolveFrom(p, start.x, MakeOptions(function, LinearSolverType::kDenseLU));
      INFO(Describe(p, start.label, function, LinearSolverType::kDenseLU, run));
      if (FindKnownSolverFailure(p.name, start.label, function,
                                 LinearSolverType::kDenseLU)) {
        CHECK_FALSE(run.summary.IsSolutionUsable());
        continue;
      }
      CHECK(run.summary.termination == TerminationType::kConverged);
      // Judged by the residual only: the solution set is not a single point.
      CHECK(run.natural_residual <= kResidualTolerance);
    }
  }
  // The start "zero" is itself a solution (lambda = 0): nothing to do.
  const Run at_solution =
      SolveFrom(p, Vector::Zero(4),
                MakeOptions(NcpFunction::kFischerBurmeister, LinearSolverType::kDenseLU));
  CHECK(at_solution.summary.termination == TerminationType::kConverged);
  CHECK(at_solution.summary.iterations == 0);
}

TEST_CASE("Billups: honest failure from 0, convergence from 3", "[solver][collection]") {
  const LinearSolverType backend =
      GENERATE(LinearSolverType::kDenseLU, LinearSolverType::kSparseLU,
               LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin);
  TestProblem p = Billups();
  {
    const Run run = SolveFrom(p, Vector::Zero(1), MakeOptions(function, backend));
    INFO(Describe(p, "0", function, backend, run));
    CHECK_FALSE(run.summary.IsSolutionUsable());
    CHECK(run.summary.termination != TerminationType::kConverged);
    CHECK(HonestFailure(run.summary.termination));
    // The returned point is not a solution and stayed near the local minimizer at 0,
    // far from x* = 2.005.
    CHECK(run.natural_residual > 1e-3);
    CHECK(std::abs(run.x(0)) < 0.1);
  }
  {
    const Run run =
        SolveFrom(p, Vector::Constant(1, 3.0), MakeOptions(function, backend));
    INFO(Describe(p, "3", function, backend, run));
    CHECK(run.summary.termination == TerminationType::kConverged);
    CHECK(run.natural_residual <= kResidualTolerance);
    CHECK(run.x(0) == Approx(1.0 + std::sqrt(1.01)).epsilon(1e-10));
  }
}

TEST_CASE("nash5 reproduces the published equilibrium", "[solver][collection]") {
  TestProblem p = NashCournot5();
  const Run run =
      SolveFrom(p, p.starts[0].x,
                MakeOptions(NcpFunction::kFischerBurmeister, LinearSolverType::kDenseLU));
  INFO(Describe(p, "tens", NcpFunction::kFischerBurmeister, LinearSolverType::kDenseLU,
                run));
  REQUIRE(run.summary.termination == TerminationType::kConverged);
  CHECK(run.natural_residual <= 1e-9);
  const Vector expected = p.solutions[0];
  for (int i = 0; i < 5; ++i) CHECK(run.x(i) == Approx(expected(i)).margin(5e-5));
}

TEST_CASE("1D bump obstacle converges to the continuous solution",
          "[solver][collection]") {
  // Error of the discrete solution against the exact one, on two grids.
  double previous_error = 0.0;
  for (int n : {99, 999}) {
    TestProblem p = Obstacle1D(n, ObstacleKind::kLowerBump);
    ncp::Options options =
        MakeOptions(NcpFunction::kFischerBurmeister, LinearSolverType::kKlu);
    options.tolerance = AttainableObstacleTolerance(1.0 / (n + 1));
    const Run run = SolveFrom(p, p.starts[0].x, options);
    INFO(Describe(p, "zero", NcpFunction::kFischerBurmeister, LinearSolverType::kKlu,
                  run));
    REQUIRE(run.summary.termination == TerminationType::kConverged);
    double error = 0.0;
    for (int i = 0; i < n; ++i)
      error = std::max(error, std::abs(run.x(i) - ExactLowerBump1D((i + 1.0) / (n + 1))));
    INFO("n = " << n << ": max error " << error);
    CHECK(error < 1e-2);
    if (previous_error > 0.0) CHECK(error < previous_error / 4);
    previous_error = error;
  }
}

TEST_CASE("oligomcp with nash5's cost data reproduces nash5's equilibrium",
          "[solver][collection]") {
  // oligomcp keeps the price p as a variable with the demand equation sum q = 5000
  // p^-1.1; nash5 eliminates it. With l = 1/5 the marginal costs coincide (c + (5 q)^
  // (1/beta)), so the q part of the solution must be nash5's, and p the inverse demand
  // (5000/Q)^(1/1.1). With the .gms data (l = 5) the economy differs.
  const NcpFunction fb = NcpFunction::kFischerBurmeister;
  const LinearSolverType dense = LinearSolverType::kDenseLU;
  TestProblem nash5 = NashCournot5();
  TestProblem oligo = OligoMcp(0.2);
  const Run run_nash = SolveFrom(nash5, nash5.starts[0].x, MakeOptions(fb, dense));
  const Run run_oligo = SolveFrom(oligo, oligo.starts[0].x, MakeOptions(fb, dense));
  INFO(Describe(nash5, "tens", fb, dense, run_nash));
  INFO(Describe(oligo, "gams", fb, dense, run_oligo));
  REQUIRE(run_nash.summary.termination == TerminationType::kConverged);
  REQUIRE(run_oligo.summary.termination == TerminationType::kConverged);
  CHECK(run_oligo.natural_residual <= kResidualTolerance);
  const Vector q = run_oligo.x.tail(5);
  CHECK((q - run_nash.x).lpNorm<Eigen::Infinity>() <= 1e-9);
  CHECK((q - nash5.solutions[0]).lpNorm<Eigen::Infinity>() <= 5e-5);  // 4 quoted decimals
  CHECK(run_oligo.x(0) == Approx(std::pow(5000.0 / q.sum(), 1 / 1.1)).epsilon(1e-12));
  // The .gms data give another equilibrium (its stored solution, checked above).
  TestProblem gams = OligoMcp();
  CHECK((gams.solutions[0].tail(5) - run_nash.x).lpNorm<Eigen::Infinity>() > 1.0);
}

TEST_CASE("COPS grid problems reach the optimal values published by COPS",
          "[solver][collection]") {
  // Optimal values of the COPS 3.0 report (Dolan, More and Munson 2004, cops3.pdf) for
  // 50 x 50 interior nodes (minsurf also 50 x 75 and 50 x 100), as quoted to 5-6 digits
  // in MadNLP/COPSBenchmark.jl (test/runtests.jl, benchmark tables); the COPS models
  // there (bearing.mod, torsion, minsurf) are those of the .gms files. Compared to the
  // quoted digits: within one unit of the last one (the minsurf values appear
  // truncated, not rounded: 2.514889 is quoted as 2.51488).
  struct Case {
    TestProblem problem;
    double (*objective)(int, int, const Vector&);
    int my;
    double published, last_digit;
  };
  Case cases[] = {
      {JournalBearing(50, 50), &JournalBearingObjective, 50, -1.5482e-1, 1e-5},
      {Torsion(50, 50), &TorsionObjective, 50, -4.18087e-1, 1e-6},
      {MinimalSurface(50, 50), &MinimalSurfaceObjective, 50, 2.51488, 1e-5},
      {MinimalSurface(50, 75), &MinimalSurfaceObjective, 75, 2.50568, 1e-5},
      {MinimalSurface(50, 100), &MinimalSurfaceObjective, 100, 2.50694, 1e-5}};
  for (Case& c : cases) {
    TestProblem& p = c.problem;
    const NcpFunction fb = NcpFunction::kFischerBurmeister;
    const Run run = SolveFrom(p, p.starts[0].x, MakeOptions(fb, LinearSolverType::kKlu));
    INFO(Describe(p, "gams", fb, LinearSolverType::kKlu, run));
    REQUIRE(run.summary.termination == TerminationType::kConverged);
    CHECK(run.natural_residual <= kResidualTolerance);
    const double f = c.objective(50, c.my, run.x);
    INFO("objective " << f << ", published " << c.published);
    CHECK(std::abs(f - c.published) <= c.last_digit);
  }
}
