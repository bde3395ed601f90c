// ncp::petsc::Solver against the serial ncp::Solver on the same problems: the same
// iteration count and the same solution to 1e-10 relative on 1, 2 and 4 ranks (ctest runs
// this executable under mpiexec -n 1, 2, 4; CMakeLists.txt), and bad input rejected with
// the same message on every rank. The natural residual ||mid(l, u, x - F(x)) - x||_inf...
// of every solution is recomputed here from F, l, u (collection::NaturalResidual).
#define CATCH_CONFIG_RUNNER
#include <petscdmda.h>
#include <petscsys.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "catch_on_ranks.hpp"
#include "distributed_function.hpp"
#include "ncp/petsc/solver.hpp"
#include "ncp/solver.hpp"
#include "ncp_collection/affine_function.hpp"
#include "ncp_collection/checks.hpp"
#include "ncp_collection/mcplib_nlp.hpp"
#include "ncp_collection/obstacle.hpp"
#include "ncp_collection/random_lcp.hpp"
#include "ncp_collection/small_problems.hpp"

using ncp::NcpFunction;
using ncp::Options;
using ncp::Summary;
using ncp::TerminationType;
using ncp::Vector;
using namespace ncp::collection;
using ncp::test::DistributedFunction;
using ncp::test::MakeVec;
using ncp::test::SetOwnedEntries;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSameSolution =
    1e-10;  // relative, ||x_petsc - x_serial||_inf / ||x_serial||_inf
constexpr double kNaturalResidual = 1e-8;

struct Both {
  Summary serial, parallel;
  Vector x_serial, x_parallel;
  bool symmetric_newton = false;  // the PETSc solve's KspReport::symmetric_newton
  int linear_iterations = -1, residual_test_iterations = -1;  // its KspReport's
};

// The box MCP solved by ncp::Solver and by ncp::petsc::Solver on PETSC_COMM_WORLD.
Both SolveBoth(TestProblem& problem, const Vector& x0, const Options& options,
               const std::string& prefix = "ncp_") {
  Both out;
  out.x_serial = x0;
  ncp::Solver(options).Solve(*problem.F, problem.lower, problem.upper, &out.x_serial,
                             &out.serial);

  Vec x = MakeVec(PETSC_COMM_WORLD, x0);
  Vec lower = MakeVec(PETSC_COMM_WORLD, problem.lower);
  Vec upper = MakeVec(PETSC_COMM_WORLD, problem.upper);
  {
    DistributedFunction F(*problem.F, x, x0);
    ncp::petsc::Solver solver(PETSC_COMM_WORLD, options, prefix);
    solver.Solve(F.Problem(lower, upper), x, &out.parallel);
    out.symmetric_newton = solver.ksp_report().symmetric_newton;
    out.linear_iterations = solver.ksp_report().linear_iterations;
    out.residual_test_iterations = solver.ksp_report().residual_test_iterations;
    out.x_parallel = F.Gather(x);
  }
  VecDestroy(&x);
  VecDestroy(&lower);
  VecDestroy(&upper);
  return out;
}

void CheckSameAnswer(TestProblem& problem, const Both& r) {
  INFO("serial:   " << r.serial.BriefReport() << " - " << r.serial.message);
  INFO("parallel: " << r.parallel.BriefReport() << " - " << r.parallel.message);
  REQUIRE(r.serial.termination == TerminationType::kConverged);
  CHECK(r.parallel.termination == TerminationType::kConverged);
  CHECK(r.parallel.iterations == r.serial.iterations);
  CHECK(r.parallel.gradient_steps == r.serial.gradient_steps);
  CHECK(r.parallel.merit_restarts == r.serial.merit_restarts);
  const double scale = std::max(1.0, r.x_serial.lpNorm<Eigen::Infinity>());
  CHECK((r.x_parallel - r.x_serial).lpNorm<Eigen::Infinity>() <= kSameSolution * scale);
  CHECK(NaturalResidual(*problem.F, problem.lower, problem.upper, r.x_parallel) <=
        kNaturalResidual);
}

// A solve that fails the same way: same status, iteration and gradient-step counts, and
// the same ||Phi||_inf at the end to 1e-6 relative.
void CheckSameFailure(const Both& r) {
  INFO("serial:   " << r.serial.BriefReport() << " - " << r.serial.message);
  INFO("parallel: " << r.parallel.BriefReport() << " - " << r.parallel.message);
  CHECK(r.parallel.termination == r.serial.termination);
  CHECK(r.parallel.iterations == r.serial.iterations);
  CHECK(r.parallel.gradient_steps == r.serial.gradient_steps);
  CHECK(std::abs(r.parallel.final_phi_inf - r.serial.final_phi_inf) <=
        1e-6 * r.serial.final_phi_inf);
}

// The random P-LCP of the collection with bounds of every kind: component i is
// lower-bounded (i mod 5 = 0, 4; at 0 and -0.3), upper-bounded (1: u = 0.5), free (2,
// with +-1e20) or fixed (3: l = u = 0.25); with two_sided, the components i mod 5 = 4
// have [-0.3, 0.1] instead (and n = 300 then has solutions at both bounds and between).
// F is a P-function, so the box MCP has one solution.
TestProblem RandomBoxMcp(int n, bool two_sided = false) {
  RandomLcpOptions options;
  options.seed = 26;
  TestProblem p = RandomPLcp(n, options);
  for (int i = 0; i < n; ++i) {
    switch (i % 5) {
      case 0:
        p.lower(i) = 0.0;
        p.upper(i) = kInf;
        break;
      case 1:
        p.lower(i) = -kInf;
        p.upper(i) = 0.5;
        break;
      case 2:
        p.lower(i) = -1e20;
        p.upper(i) = 1e20;
        break;
      case 3:
        p.lower(i) = p.upper(i) = 0.25;
        break;
      default:
        p.lower(i) = -0.3;
        p.upper(i) = two_sided ? 0.1 : kInf;
        break;
    }
  }
  return p;
}

// The box MCP's conditions recomputed from F at x, independently of both solvers and of
// the natural residual: l <= x <= u, F_i > 0 only where x_i = l_i and F_i < 0 only where
// x_i = u_i. Returns the largest violation
//   max_i max(l_i - x_i, x_i - u_i, min(x_i - l_i, F_i^+), min(u_i - x_i, F_i^-)).
double BoxConditionsViolation(ncp::SquareFunction& F, const Vector& lower,
                              const Vector& upper, const Vector& x) {
  Vector Fx(x.size());
  REQUIRE(F.Evaluate(x, &Fx));
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double l = lower(i) <= -1e20 ? -kInf : lower(i);
    const double u = upper(i) >= 1e20 ? kInf : upper(i);
    worst = std::max({worst, l - x(i), x(i) - u, std::min(x(i) - l, std::max(Fx(i), 0.0)),
                      std::min(u - x(i), std::max(-Fx(i), 0.0))});
  }
  return worst;
}

// How many two-sided components of a solution x sit at l, at u and strictly between.
struct TwoSidedCounts {
  int at_lower = 0, at_upper = 0, between = 0;
};
TwoSidedCounts CountTwoSided(const TestProblem& p, const Vector& x) {
  TwoSidedCounts c;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double l = p.lower(i), u = p.upper(i);
    if (!(std::isfinite(l) && std::isfinite(u) && l < u)) continue;
    if (x(i) <= l + 1e-9)
      ++c.at_lower;
    else if (x(i) >= u - 1e-9)
      ++c.at_upper;
    else
      ++c.between;
  }
  return c;
}

int Rank() {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

}  // namespace

TEST_CASE("2D obstacle of the collection: the serial iterates on any rank count",
          "[petsc][mpi]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  const ObstacleVariable variable =
      GENERATE(ObstacleVariable::kHeight, ObstacleVariable::kGap);
  TestProblem problem = Obstacle2D(16, ObstacleKind::kLowerBump, variable);
  Options options;
  options.ncp_function = function;
  for (const StartPoint& start : problem.starts) {
    INFO(problem.name << " from " << start.label << " with " << ncp::ToString(function));
    CheckSameAnswer(problem, SolveBoth(problem, start.x, options));
  }
}

TEST_CASE("random sparse box MCP: the serial iterates on any rank count",
          "[petsc][mpi]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  TestProblem problem = RandomBoxMcp(300);
  Options options;
  options.ncp_function = function;
  for (const StartPoint& start : problem.starts) {
    INFO(problem.name << " (box) from " << start.label << " with "
                      << ncp::ToString(function));
    const Both r = SolveBoth(problem, start.x, options);
    CheckSameAnswer(problem, r);
    CHECK(r.parallel.projected_start_components == r.serial.projected_start_components);
  }
}

TEST_CASE("random sparse box MCP with two-sided bounds: the serial iterates",
          "[petsc][mpi]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  TestProblem problem = RandomBoxMcp(300, true);
  Options options;
  options.ncp_function = function;
  for (const StartPoint& start : problem.starts) {
    INFO(problem.name << " (two-sided box) from " << start.label << " with "
                      << ncp::ToString(function));
    const Both r = SolveBoth(problem, start.x, options);
    if (r.serial.termination != TerminationType::kConverged) {
      // (min from "ones": both stop at max_iterations on the same path.)
      CheckSameFailure(r);
      continue;
    }
    CheckSameAnswer(problem, r);
    // The slack form of both: 60 two-sided components, 2 slacks each.
    CHECK(r.parallel.num_variables == 300 + 2 * 60);
    CHECK(r.parallel.num_variables == r.serial.num_variables);
    CHECK(r.parallel.num_equations == r.serial.num_equations);
    CHECK(BoxConditionsViolation(*problem.F, problem.lower, problem.upper,
                                 r.x_parallel) <= kNaturalResidual);
    const TwoSidedCounts c = CountTwoSided(problem, r.x_parallel);
    INFO("two-sided at l: " << c.at_lower << ", at u: " << c.at_upper
                            << ", between: " << c.between);
    CHECK(c.at_lower > 0);
    CHECK(c.at_upper > 0);
    CHECK(c.between > 0);
  }
}

TEST_CASE("Levenberg-Marquardt directions (regularized_direction): the serial iterates",
          "[petsc][mpi]") {
  // Problems and starts where the Newton direction fails the descent test and
  // (J'J + mu I) d = -J' Phi is taken instead; obstacle-band has two-sided bounds.
  // Under the prefix symlm_ the Newton systems are symmetrized (solved exactly by the
  // default LU), so the KSP's matrix is not J and the LM step needs J built apart;
  // two-sided bounds are refused there and skipped.
  PetscOptionsSetValue(nullptr, "-symlm_symmetric_newton", "true");
  const std::string prefix = GENERATE(std::string("ncp_"), std::string("symlm_"));
  const bool symmetric = prefix == "symlm_";
  struct Case {
    TestProblem problem;
    std::string start;
    NcpFunction function;
  };
  std::vector<Case> cases;
  cases.push_back({HarkMcp(), "zero", NcpFunction::kFischerBurmeister});
  cases.push_back({HarkMcp(), "gams", NcpFunction::kPenalizedFischerBurmeister});
  cases.push_back({Obstacle1D(100, ObstacleKind::kTwoSidedBand), "ceiling",
                   NcpFunction::kFischerBurmeister});
  for (Case& c : cases) {
    const Eigen::Index two_sided =
        (c.problem.lower.array().isFinite() && c.problem.upper.array().isFinite() &&
         c.problem.lower.array() < c.problem.upper.array())
            .count();
    if (symmetric && two_sided > 0) continue;
    Options options;
    options.hybrid = false;
    options.regularized_direction = true;
    options.minimum_norm_step = false;  // else these singular systems take that step
    options.scale_newton_system = false;
    options.ncp_function = c.function;
    for (const StartPoint& start : c.problem.starts) {
      if (start.label != c.start) continue;
      INFO(c.problem.name << " from " << start.label << " with "
                          << ncp::ToString(c.function) << " under " << prefix);
      const Both r = SolveBoth(c.problem, start.x, options, prefix);
      CHECK(r.symmetric_newton == symmetric);
      CheckSameAnswer(c.problem, r);
      CHECK(r.serial.regularized_steps > 0);
      CHECK(r.parallel.regularized_steps == r.serial.regularized_steps);
    }
  }
}

TEST_CASE("2D two-sided obstacle band: every component split, MUMPS given workspace",
          "[petsc][mpi]") {
  // 900 two-sided components, 1800 slacks. The zero entries of the slack rows delay
  // MUMPS' pivots beyond its workspace estimate (INFOG(1) = -9 at the first Newton
  // system); the solver factorizes again with a larger ICNTL(14), so no Newton system
  // fails and the iterates stay the serial ones.
  TestProblem problem =
      Obstacle2D(30, ObstacleKind::kTwoSidedBand, ObstacleVariable::kGap);
  const StartPoint& start = problem.starts.front();
  REQUIRE(start.label == "zero");
  const Both r = SolveBoth(problem, start.x, Options());
  CheckSameAnswer(problem, r);
  CHECK(r.parallel.num_variables == 3 * 900);
  CHECK(r.parallel.linear_solver_failures == 0);
  CHECK(r.serial.linear_solver_failures == 0);
  CHECK(BoxConditionsViolation(*problem.F, problem.lower, problem.upper, r.x_parallel) <=
        kNaturalResidual);
}

TEST_CASE("the hybrid default switches strategy as the serial solver does",
          "[petsc][mpi]") {
  // min from "ones" on the two-sided box MCP makes slow progress (gradient steps only)
  // and is left for penalized FB; the default options (hybrid on) throughout.
  TestProblem problem = RandomBoxMcp(300, true);
  Options options;
  options.ncp_function = NcpFunction::kMin;
  const Both r = SolveBoth(problem, problem.starts.back().x, options);
  REQUIRE(problem.starts.back().label == "ones");
  CheckSameAnswer(problem, r);
  REQUIRE(r.serial.strategy_switches.size() == 1);
  REQUIRE(r.parallel.strategy_switches.size() == 1);
  const ncp::StrategySwitch &a = r.serial.strategy_switches[0],
                            &b = r.parallel.strategy_switches[0];
  CHECK(b.iteration == a.iteration);
  CHECK(b.best_iteration == a.best_iteration);
  CHECK(b.reason == a.reason);
  CHECK(b.to_strategy.ncp_function == a.to_strategy.ncp_function);
  CHECK(std::abs(b.best_psi - a.best_psi) <= 1e-10 * a.best_psi);
}

TEST_CASE("any KSP from the options database under the solver's prefix", "[petsc][mpi]") {
  // GMRES + block Jacobi solved tightly: the Newton directions agree with the direct
  // solver's to about the KSP tolerance, so the iterates do too.
  PetscOptionsSetValue(nullptr, "-iter_ksp_type", "gmres");
  PetscOptionsSetValue(nullptr, "-iter_pc_type", "bjacobi");
  PetscOptionsSetValue(nullptr, "-iter_ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-iter_ksp_max_it", "2000");
  TestProblem problem = RandomBoxMcp(200);
  Options options;
  const Both r = SolveBoth(problem, problem.starts.front().x, options, "iter_");
  CheckSameAnswer(problem, r);
}

TEST_CASE("CG + BoomerAMG on the symmetrized Newton system: the serial iterates",
          "[petsc][mpi]") {
  // -cg_ksp_type cg switches the symmetrized system on (KspReport::symmetric_newton).
  // With the min function it is the reduced-space system F'_II d_I = -Phi_I - F'_IA d_A
  // (active rows eliminated exactly); the Newton matrix J itself is then never formed,
  // so the gradient and the backward-error guard come from F' (solver.cpp).
  PetscOptionsSetValue(nullptr, "-cg_ksp_type", "cg");
  PetscOptionsSetValue(nullptr, "-cg_pc_type", "hypre");
  PetscOptionsSetValue(nullptr, "-cg_ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-cg_ksp_norm_type", "unpreconditioned");
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin);
  const ObstacleVariable variable =
      GENERATE(ObstacleVariable::kGap, ObstacleVariable::kHeight);
  TestProblem problem = Obstacle2D(16, ObstacleKind::kLowerBump, variable);
  Options options;
  options.ncp_function = function;
  for (const StartPoint& start : problem.starts) {
    INFO(problem.name << " from " << start.label << " with " << ncp::ToString(function));
    CheckSameAnswer(problem, SolveBoth(problem, start.x, options, "cg_"));
  }
}

TEST_CASE("a loose KSP runs on until its residual passes the outer stopping test",
          "[petsc][mpi]") {
  // CG + Jacobi stopped by its own test at rtol 0.1 alone gives inexact Newton steps and
  // more of them; -<prefix>newton_residual_fraction (default 0.5) continues each solve
  // until every row of J d + Phi is within half the stopping test's bound, so each
  // min-Newton step with an unchanged active set ends the solve, as the direct solve's.
  TestProblem problem = Obstacle2D(16, ObstacleKind::kLowerBump, ObstacleVariable::kGap);
  Options options;
  options.ncp_function = NcpFunction::kMin;
  const Vector& x0 = problem.starts.front().x;
  for (const char* prefix : {"loose_", "looseoff_"}) {
    const std::string p = std::string("-") + prefix;
    PetscOptionsSetValue(nullptr, (p + "ksp_type").c_str(), "cg");
    PetscOptionsSetValue(nullptr, (p + "pc_type").c_str(), "jacobi");
    PetscOptionsSetValue(nullptr, (p + "ksp_rtol").c_str(), "0.1");
    PetscOptionsSetValue(nullptr, (p + "ksp_norm_type").c_str(), "unpreconditioned");
  }
  PetscOptionsSetValue(nullptr, "-looseoff_newton_residual_fraction", "0");
  const Both on = SolveBoth(problem, x0, options, "loose_");
  INFO("with the test: " << on.parallel.BriefReport());
  CHECK(on.residual_test_iterations > 0);
  CHECK(on.residual_test_iterations < on.linear_iterations);
  CheckSameAnswer(problem, on);
  // The control: the same KSP on its own test takes other (more) Newton steps.
  const Both off = SolveBoth(problem, x0, options, "looseoff_");
  INFO("without: " << off.parallel.BriefReport());
  CHECK(off.residual_test_iterations == 0);
  CHECK(off.parallel.iterations > on.parallel.iterations);
}

TEST_CASE("-<prefix>newton_residual_fraction outside [0, 1] is rejected",
          "[petsc][mpi]") {
  TestProblem problem = RandomBoxMcp(20);
  PetscOptionsSetValue(nullptr, "-badfraction_ksp_type", "gmres");
  PetscOptionsSetValue(nullptr, "-badfraction_newton_residual_fraction", "1.5");
  Vec x = MakeVec(PETSC_COMM_WORLD, problem.starts.front().x);
  {
    DistributedFunction F(*problem.F, x, problem.starts.front().x);
    ncp::petsc::Solver solver(PETSC_COMM_WORLD, Options(), "badfraction_");
    Summary summary;
    CHECK_THROWS_WITH(solver.Solve(F.Problem(nullptr, nullptr), x, &summary),
                      Catch::Contains("-badfraction_newton_residual_fraction = 1.5: "
                                      "accepted a number in [0, 1]"));
  }
  VecDestroy(&x);
}

TEST_CASE(
    "CG + PCMG restricted to the inactive set (SetMultigridGrid): the serial iterates",
    "[petsc][mpi]") {
  // The 17 x 17 obstacle on a DMDA split into row bands (1 x ranks processes), so that
  // PETSc's ordering of the grid is the collection's lexicographic one; PCMG with 3
  // levels (17, 9, 5 nodes per side) on the min function's reduced Newton system, solved
  // tightly: the directions are the direct solver's to about the KSP tolerance.
  PetscOptionsSetValue(nullptr, "-rmg_ksp_type", "cg");
  PetscOptionsSetValue(nullptr, "-rmg_pc_type", "mg");
  PetscOptionsSetValue(nullptr, "-rmg_pc_mg_levels", "3");
  PetscOptionsSetValue(nullptr, "-rmg_mg_levels_ksp_type", "richardson");
  PetscOptionsSetValue(nullptr, "-rmg_mg_levels_pc_type", "sor");
  PetscOptionsSetValue(nullptr, "-rmg_ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-rmg_ksp_norm_type", "unpreconditioned");
  // Either the grid is made at its size (the levels by DMCoarsen) or it is refined
  // from a 9 x 9 grid recorded as its coarse DM (a nested iteration's grid): then level 1
  // is that grid with its interpolation kept by GridInterpolation, level 0 a coarsening.
  constexpr int kM = 17;
  const ObstacleVariable variable =
      GENERATE(ObstacleVariable::kGap, ObstacleVariable::kHeight);
  const bool refined = GENERATE(false, true);
  TestProblem problem = Obstacle2D(kM, ObstacleKind::kLowerBump, variable);
  REQUIRE(problem.F->NumVariables() == kM * kM);
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  DM da = nullptr;
  const int made = refined ? (kM + 1) / 2 : kM;
  REQUIRE(DMDACreate2d(PETSC_COMM_WORLD, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                       DMDA_STENCIL_STAR, made, made, 1, size, 1, 1, nullptr, nullptr,
                       &da) == 0);
  REQUIRE(DMSetUp(da) == 0);
  if (refined) {
    DM coarse = da;
    REQUIRE(DMRefine(coarse, PETSC_COMM_WORLD, &da) == 0);
    REQUIRE(DMSetCoarseDM(da, coarse) == 0);
    Mat P = ncp::petsc::GridInterpolation(coarse, da);
    PetscInt rows = 0, cols = 0;
    MatGetSize(P, &rows, &cols);
    CHECK(rows == kM * kM);
    CHECK(cols == made * made);
    CHECK(ncp::petsc::GridInterpolation(coarse, da) == P);  // made once, kept on da
    DMDestroy(&coarse);                                     // da keeps it
  }
  PetscInt grid_size = 0;
  DMDAGetInfo(da, nullptr, &grid_size, nullptr, nullptr, nullptr, nullptr, nullptr,
              nullptr, nullptr, nullptr, nullptr, nullptr, nullptr);
  REQUIRE(grid_size == kM);
  // A Vec of the grid's layout holding v (natural = PETSc ordering for row bands).
  auto grid_vec = [&](const Vector& v) {
    Vec out = nullptr;
    DMCreateGlobalVector(da, &out);
    SetOwnedEntries(v, out);
    return out;
  };
  Options options;
  options.ncp_function = NcpFunction::kMin;
  for (const StartPoint& start : problem.starts) {
    INFO(problem.name << " from " << start.label
                      << (refined ? " on a refined grid" : ""));
    Both r;
    r.x_serial = start.x;
    ncp::Solver(options).Solve(*problem.F, problem.lower, problem.upper, &r.x_serial,
                               &r.serial);
    Vec x = grid_vec(start.x), lower = grid_vec(problem.lower),
        upper = grid_vec(problem.upper);
    {
      DistributedFunction F(*problem.F, x, start.x);
      ncp::petsc::Solver solver(PETSC_COMM_WORLD, options, "rmg_");
      solver.SetMultigridGrid(da);
      solver.Solve(F.Problem(lower, upper), x, &r.parallel);
      CHECK(solver.ksp_report().symmetric_newton);
      CHECK(solver.ksp_report().pc_type == "mg");
      // Multigrid's grid-independent convergence: 6-7 CG iterations per Newton system
      // to 1e-13 on 1-4 ranks (SOR alone, or a coarse correction polluted by the
      // eliminated rows, needs more).
      CHECK(solver.ksp_report().linear_iterations <= 8 * r.parallel.iterations);
      r.x_parallel = F.Gather(x);
    }
    CheckSameAnswer(problem, r);
    VecDestroy(&x);
    VecDestroy(&lower);
    VecDestroy(&upper);
  }
  DMDestroy(&da);
}

TEST_CASE("SetMultigridGrid needs PCMG, the symmetric mode and the grid of x",
          "[petsc][mpi]") {
  constexpr int kM = 9;
  TestProblem problem = Obstacle2D(kM);
  DM da = nullptr;
  REQUIRE(DMDACreate2d(PETSC_COMM_WORLD, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                       DMDA_STENCIL_STAR, kM + 2, kM + 2, 1, PETSC_DECIDE, 1, 1, nullptr,
                       nullptr, &da) == 0);
  REQUIRE(DMSetUp(da) == 0);
  Vec x = MakeVec(PETSC_COMM_WORLD, problem.starts.front().x);
  Vec lower = MakeVec(PETSC_COMM_WORLD, problem.lower);
  {
    DistributedFunction F(*problem.F, x, problem.starts.front().x);
    Summary summary;
    Options options;
    options.ncp_function = NcpFunction::kMin;
    ncp::petsc::Solver lu(PETSC_COMM_WORLD, options, "mglu_");  // default: LU
    lu.SetMultigridGrid(da);
    CHECK_THROWS_WITH(lu.Solve(F.Problem(lower, nullptr), x, &summary),
                      Catch::Contains("needs -mglu_pc_type mg"));
    PetscOptionsSetValue(nullptr, "-mgsize_ksp_type", "cg");
    PetscOptionsSetValue(nullptr, "-mgsize_pc_type", "mg");
    ncp::petsc::Solver wrong_grid(PETSC_COMM_WORLD, options, "mgsize_");
    wrong_grid.SetMultigridGrid(da);  // 11 x 11 nodes, x has 9 x 9
    CHECK_THROWS_WITH(wrong_grid.Solve(F.Problem(lower, nullptr), x, &summary),
                      Catch::Contains("the grid must be the one x lives on"));
  }
  VecDestroy(&x);
  VecDestroy(&lower);
  DMDestroy(&da);
}

TEST_CASE("the KSP report names the default direct solver", "[petsc][mpi]") {
  TestProblem problem = RandomBoxMcp(50);
  Vec x = MakeVec(PETSC_COMM_WORLD, problem.starts.front().x);
  {
    DistributedFunction F(*problem.F, x, problem.starts.front().x);
    ncp::petsc::Solver solver(PETSC_COMM_WORLD, Options(), "report_");
    Summary summary;
    Vec lower = MakeVec(PETSC_COMM_WORLD, problem.lower),
        upper = MakeVec(PETSC_COMM_WORLD, problem.upper);
    solver.Solve(F.Problem(lower, upper), x, &summary);
    CHECK(summary.IsSolutionUsable());
    CHECK(solver.ksp_report().ksp_type == "preonly");
    CHECK(solver.ksp_report().pc_type == "lu");
    CHECK(solver.ksp_report().factor_solver_type == "mumps");
    CHECK_FALSE(solver.ksp_report().symmetric_newton);
    int size = 0;
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    CHECK(solver.ksp_report().ranks == size);
    VecDestroy(&lower);
    VecDestroy(&upper);
  }
  VecDestroy(&x);
}

// ---- bad input: the same exception (or status) on every rank, never a hang
// -------------

namespace {

// F(x) = M x + q of a small random P-LCP, n = 23 (not a multiple of the rank count:
// uneven layouts). The test of each case is that every rank returns from Solve.
struct SmallProblem {
  TestProblem problem = RandomBoxMcp(23);
  Vec x = MakeVec(PETSC_COMM_WORLD, problem.starts.front().x);
  Vec lower = MakeVec(PETSC_COMM_WORLD, problem.lower);
  Vec upper = MakeVec(PETSC_COMM_WORLD, problem.upper);
  DistributedFunction F{*problem.F, x, problem.starts.front().x};
  ~SmallProblem() {
    VecDestroy(&x);
    VecDestroy(&lower);
    VecDestroy(&upper);
  }
  // v[i] = value (collective; the owner sets it).
  static void Set(Vec v, PetscInt i, double value) {
    VecSetValue(v, i, value, INSERT_VALUES);
    VecAssemblyBegin(v);
    VecAssemblyEnd(v);
  }
};

std::string SolveMessage(SmallProblem& s, const ncp::petsc::BoxMcp& problem) {
  ncp::petsc::Solver solver(PETSC_COMM_WORLD);
  Summary summary;
  try {
    solver.Solve(problem, s.x, &summary);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception: " + summary.message;
}

}  // namespace

TEST_CASE("bad input is rejected on every rank with the same message", "[petsc][mpi]") {
  SmallProblem s;
  INFO("rank " << Rank());
  SECTION("a bound Vec of another size") {
    Vec small = nullptr;
    VecCreateMPI(PETSC_COMM_WORLD, PETSC_DECIDE, 22, &small);
    VecSet(small, 0.0);
    const std::string message = SolveMessage(s, s.F.Problem(small, s.upper));
    CHECK_THAT(message, Catch::Contains("lower has global size 22, the start point 23"));
    VecDestroy(&small);
  }
  SECTION("lower > upper at the last index") {
    SmallProblem::Set(s.lower, 22, 1.0);
    SmallProblem::Set(s.upper, 22, 0.5);
    CHECK_THAT(SolveMessage(s, s.F.Problem(s.lower, s.upper)),
               Catch::Contains("lower[22] = 1 > upper[22] = 0.5"));
  }
  SECTION("NaN in a bound") {
    SmallProblem::Set(s.upper, 17, std::nan(""));
    CHECK_THAT(SolveMessage(s, s.F.Problem(s.lower, s.upper)),
               Catch::Contains("bound[17] is NaN"));
  }
  SECTION("NaN in the start point") {
    SmallProblem::Set(s.x, 9, std::nan(""));
    CHECK_THAT(SolveMessage(s, s.F.Problem(s.lower, s.upper)),
               Catch::Contains("start point x[9] = nan is not finite"));
  }
  SECTION("lower > upper on a two-sided component") {
    SmallProblem::Set(s.lower, 1, 0.75);  // component 1 has u = 0.5
    CHECK_THAT(SolveMessage(s, s.F.Problem(s.lower, s.upper)),
               Catch::Contains("lower[1] = 0.75 > upper[1] = 0.5"));
  }
  SECTION("NaN in a bound of a two-sided component") {
    SmallProblem::Set(s.lower, 1, -1.0);  // component 1 has u = 0.5
    SmallProblem::Set(s.lower, 6, std::nan(""));
    CHECK_THAT(SolveMessage(s, s.F.Problem(s.lower, s.upper)),
               Catch::Contains("bound[6] is NaN"));
  }
  SECTION("two finite bounds with a CG KSP (symmetrized system): refused") {
    PetscOptionsSetValue(nullptr, "-sym_ksp_type", "cg");
    SmallProblem::Set(s.lower, 1, -1.0);  // component 1 has u = 0.5
    ncp::petsc::Solver solver(PETSC_COMM_WORLD, Options(), "sym_");
    Summary summary;
    CHECK_THROWS_WITH(
        solver.Solve(s.F.Problem(s.lower, s.upper), s.x, &summary),
        Catch::Contains("two-sided bounds (l < u, both finite) at 1 components") &&
            Catch::Contains("-sym_symmetric_newton false"));
    PetscOptionsClearValue(nullptr, "-sym_ksp_type");
  }
  SECTION("a Jacobian matrix of another size") {
    Mat wrong = nullptr;
    MatCreateAIJ(PETSC_COMM_WORLD, PETSC_DECIDE, PETSC_DECIDE, 22, 22, 1, nullptr, 1,
                 nullptr, &wrong);
    MatAssemblyBegin(wrong, MAT_FINAL_ASSEMBLY);
    MatAssemblyEnd(wrong, MAT_FINAL_ASSEMBLY);
    ncp::petsc::BoxMcp problem = s.F.Problem(s.lower, s.upper);
    problem.jacobian_matrix = wrong;
    CHECK_THAT(SolveMessage(s, problem),
               Catch::Contains("the Jacobian matrix is 22 x 22"));
    MatDestroy(&wrong);
  }
  SECTION("NaN in F: a status on every rank, no exception") {
    ncp::petsc::BoxMcp problem = s.F.Problem(s.lower, s.upper);
    problem.residual = [&](Vec x, Vec f) {
      const PetscErrorCode code = s.F.Residual(x, f);
      PetscInt first = 0, last = 0;
      VecGetOwnershipRange(f, &first, &last);
      if (first <= 11 && 11 < last) VecSetValue(f, 11, std::nan(""), INSERT_VALUES);
      VecAssemblyBegin(f);
      VecAssemblyEnd(f);
      return code;
    };
    ncp::petsc::Solver solver(PETSC_COMM_WORLD);
    Summary summary;
    solver.Solve(problem, s.x, &summary);
    CHECK(summary.termination == TerminationType::kNonFiniteValues);
    CHECK_THAT(summary.message, Catch::Contains("Phi(x0) has NaN or Inf entries"));
  }
  SECTION("F not evaluable on one rank only: a status on every rank") {
    ncp::petsc::BoxMcp problem = s.F.Problem(s.lower, s.upper);
    const int last_rank = [] {
      int size = 0;
      MPI_Comm_size(PETSC_COMM_WORLD, &size);
      return size - 1;
    }();
    problem.residual = [&](Vec x, Vec f) -> PetscErrorCode {
      const PetscErrorCode code = s.F.Residual(x, f);
      return Rank() == last_rank ? 1 : code;
    };
    ncp::petsc::Solver solver(PETSC_COMM_WORLD);
    Summary summary;
    solver.Solve(problem, s.x, &summary);
    CHECK(summary.termination == TerminationType::kEvaluationFailure);
  }
}

TEST_CASE("invalid options are rejected before any work", "[petsc][mpi]") {
  Options options;
  options.linear_solver = ncp::LinearSolverType::kUmfpack;
  CHECK_THROWS_WITH(ncp::petsc::Solver(PETSC_COMM_WORLD, options),
                    Catch::Contains("KSP"));
  options = Options();
  options.armijo_beta = 0.7;
  CHECK_THROWS_WITH(ncp::petsc::Solver(PETSC_COMM_WORLD, options),
                    Catch::Contains("armijo_beta"));
}

// PETSc is initialized here, not by the library; the exit code is the worst over the
// ranks.
TEST_CASE("singular Newton systems: the least-norm step of the serial solver",
          "[petsc][mpi]") {
  // Default options (minimum_norm_step and scale_newton_system on). At these starts the
  // serial dense LU calls J singular and takes the least-norm step; MUMPS' null-pivot
  // detection calls the same J singular and MinimumNormSolver gives the same step (to
  // round-off), on 1, 2 and 4 ranks. Switched off over PETSc, the least-norm steps are
  // gone and the iteration count differs: the test sees the feature.
  struct Case {
    TestProblem problem;
    std::string start;
    NcpFunction function;
  };
  std::vector<Case> cases;
  cases.push_back({HarkMcp(), "gams", NcpFunction::kFischerBurmeister});
  cases.push_back({ModifiedMathiesen(), "1100", NcpFunction::kMin});
  for (Case& c : cases) {
    Options options;
    options.ncp_function = c.function;
    options.keep_trace = true;
    for (const StartPoint& start : c.problem.starts) {
      if (start.label != c.start) continue;
      INFO(c.problem.name << " from " << start.label << " with "
                          << ncp::ToString(c.function));
      const Both r = SolveBoth(c.problem, start.x, options);
      CheckSameAnswer(c.problem, r);
      CHECK(r.serial.minimum_norm_steps > 0);
      CHECK(r.parallel.minimum_norm_steps == r.serial.minimum_norm_steps);
      CHECK(r.parallel.linear_solver_failures == r.serial.linear_solver_failures);
      CHECK(r.parallel.descent_test_failures == r.serial.descent_test_failures);
      CHECK(r.parallel.equilibrated_factorizations ==
            r.serial.equilibrated_factorizations);
      CHECK(r.parallel.backtracks == r.serial.backtracks);
      // The least-norm steps at the same iterations; up to the last of them the same
      // directions (||d||_2 to 1e-10 relative). (Later Newton systems of harkmcp are
      // ill-conditioned: the dense LU and MUMPS solve the one at x^3 differently,
      // docs/petsc-design.md.)
      REQUIRE(r.parallel.trace.size() == r.serial.trace.size());
      size_t last_least_norm = 0;
      for (size_t k = 0; k < r.serial.trace.size(); ++k) {
        INFO("iteration " << k);
        CHECK(r.parallel.trace[k].minimum_norm_step ==
              r.serial.trace[k].minimum_norm_step);
        if (r.serial.trace[k].minimum_norm_step) last_least_norm = k;
      }
      for (size_t k = 0; k <= last_least_norm; ++k) {
        const double a = r.serial.trace[k].direction_norm,
                     b = r.parallel.trace[k].direction_norm;
        INFO("iteration " << k << ": ||d|| serial " << a << ", PETSc " << b);
        CHECK(std::abs(b - a) <= 1e-10 * a);
      }

      Options off = options;
      off.minimum_norm_step = false;
      const Both without = SolveBoth(c.problem, start.x, off);
      INFO("without the least-norm step: " << without.parallel.BriefReport());
      CHECK(without.parallel.termination == TerminationType::kConverged);
      CHECK(without.parallel.minimum_norm_steps == 0);
      CHECK(without.parallel.iterations != r.serial.iterations);
    }
  }
}

int main(int argc, char** argv) { return RunTestsOnRanks(argc, argv); }
