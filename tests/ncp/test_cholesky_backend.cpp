// LinearSolverType::kCholmod: the Newton matrix symmetrized by a row scaling and factored
// by CHOLMOD, UMFPACK's LU where that is impossible. Every result is checked against an
// independent UMFPACK solve of the same problem and by its natural residual recomputed
// from the problem data.
#include <catch2/catch.hpp>

#include "ncp_collection/affine_function.hpp"
#include "ncp_collection/cops_bound_constrained.hpp"
#include "ncp_collection/obstacle.hpp"
#include "ncp_collection/random_lcp.hpp"
#include "solve_support.hpp"

using ncp::LinearSolverType;
using ncp::NcpFunction;
using ncp::TerminationType;
using namespace ncp::collection;
using namespace ncp::test;

namespace {

// Solves p from start with kCholmod and with kUmfpack; both must converge to the same x.
void CompareWithUmfpack(TestProblem& p, const ncp::Vector& start, ncp::Options options,
                        Run* cholesky) {
  options.linear_solver = LinearSolverType::kCholmod;
  *cholesky = SolveFrom(p, start, options);
  options.linear_solver = LinearSolverType::kUmfpack;
  const Run lu = SolveFrom(p, start, options);
  INFO(p.name << "\ncholmod: " << cholesky->summary.FullReport()
              << "\numfpack: " << lu.summary.FullReport());
  REQUIRE(cholesky->summary.termination == TerminationType::kConverged);
  REQUIRE(lu.summary.termination == TerminationType::kConverged);
  CHECK(cholesky->summary.linear_solver_used == LinearSolverType::kCholmod);
  CHECK(cholesky->natural_residual <= 1e-8);
  CHECK((cholesky->x - lu.x).lpNorm<Eigen::Infinity>() <= 1e-8);
}

}  // namespace

TEST_CASE(
    "obstacle: S J = diag(da/db) + A is factored by Cholesky, no fallback, "
    "the iterates of the LU",
    "[solver][cholmod]") {
  // (The min function from this start fails on the 1D grid with either backend: 500
  // iterations, ||Phi|| ~ 0.49.)
  const auto [function, dimension] =
      GENERATE(table<NcpFunction, int>({{NcpFunction::kFischerBurmeister, 1},
                                        {NcpFunction::kPenalizedFischerBurmeister, 1},
                                        {NcpFunction::kFischerBurmeister, 2},
                                        {NcpFunction::kMin, 2},
                                        {NcpFunction::kPenalizedFischerBurmeister, 2}}));
  TestProblem p = dimension == 1
                      ? Obstacle1D(2000, ObstacleKind::kLowerBump, ObstacleVariable::kGap)
                      : Obstacle2D(40, ObstacleKind::kLowerBump, ObstacleVariable::kGap);
  ncp::Options options = MakeOptions(function, LinearSolverType::kCholmod);
  options.project_start_point = false;
  options.tolerance = 1e-9;
  Run run;
  CompareWithUmfpack(p, p.starts[0].x, options, &run);
  INFO(p.name << " " << ncp::ToString(function) << ": " << run.summary.FullReport());
  CHECK(run.summary.cholesky_fallbacks == 0);
  CHECK(run.summary.symbolic_factorizations == 1);
}

TEST_CASE("COPS journal bearing (lower bounds, SPD Hessian): Cholesky throughout",
          "[solver][cholmod]") {
  TestProblem p = JournalBearing(20, 20);
  Run run;
  CompareWithUmfpack(p, p.starts[0].x, ncp::Options(), &run);
  CHECK(run.summary.cholesky_fallbacks == 0);
}

TEST_CASE(
    "not symmetrizable: two-sided bounds (slack rows) and an unsymmetric M fall "
    "back to the LU and still converge",
    "[solver][cholmod]") {
  SECTION("two-sided obstacle") {
    TestProblem p = Obstacle2D(30, ObstacleKind::kTwoSidedBand);
    Run run;
    CompareWithUmfpack(p, p.starts[0].x, ncp::Options(), &run);
    // Every factorization went to UMFPACK (the mixed form's slack rows are not
    // symmetric).
    CHECK(run.summary.cholesky_fallbacks >= run.summary.iterations);
  }
  SECTION("random sparse P-LCP (M unsymmetric)") {
    TestProblem p = RandomPLcp(300);
    Run run;
    CompareWithUmfpack(p, p.starts[0].x, ncp::Options(), &run);
    CHECK(run.summary.cholesky_fallbacks >= run.summary.iterations);
  }
}

TEST_CASE("symmetric but indefinite: Cholesky fails once, LU afterwards",
          "[solver][cholmod]") {
  // LCP with M = [[0, 10], [10, 0]] (indefinite), q = (-95, -95): solution x =
  // (9.5, 9.5), F = 0. At x0 = (10, 10): a = 10, b = F = 5, FB partials da = a/r - 1 =
  // -0.106, db = b/r - 1 = -0.553, so S J = diag(da/db) + M = [[0.19, 10], [10, 0.19]]:
  // indefinite.
  ncp::SparseMatrix M(2, 2);
  M.insert(0, 1) = 10.0;
  M.insert(1, 0) = 10.0;
  M.insert(0, 0) = 0.0;  // stored diagonal: the pattern is symmetric with a diagonal
  M.insert(1, 1) = 0.0;
  M.makeCompressed();
  TestProblem p;
  p.name = "indefinite-2";
  p.F = std::make_unique<AffineFunction>(M, ncp::Vector::Constant(2, -95.0));
  p.lower = ncp::Vector::Zero(2);
  p.upper = ncp::Vector::Constant(2, std::numeric_limits<double>::infinity());
  Run run;
  CompareWithUmfpack(p, ncp::Vector::Constant(2, 10.0), ncp::Options(), &run);
  CHECK((run.x - ncp::Vector::Constant(2, 9.5)).lpNorm<Eigen::Infinity>() <= 1e-12);
  CHECK(run.summary.cholesky_fallbacks >= 1);
  CHECK(run.summary.cholesky_fallbacks >= run.summary.iterations);  // LU after the first
}
