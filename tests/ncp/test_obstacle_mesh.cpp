// Newton iteration counts of the obstacle problems as the grid is refined, with a table.
// Each solve's natural residual is recomputed here.
//
// Theory (read before changing the bounds): mesh independence of semismooth Newton is
// proved when the complementarity map has a smoothing property ("norm gap"),
// Hintermueller and Ulbrich, Math. Programming 101 (2004) 151-184. The plain obstacle
// problem has none; starting from an active set that is too large, the primal-dual active
// set method (semismooth Newton with min) removes only the boundary nodes of the active
// set per iteration, because the multiplier of a too large active set is concentrated on
// its boundary. Iteration counts then grow like the number of grid points to the true
// free boundary. The tests therefore assert what holds and record what does not.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/obstacle.hpp"
#include "solve_support.hpp"

using ncp::LinearSolverType;
using ncp::NcpFunction;
using ncp::TerminationType;
using namespace ncp::collection;
using namespace ncp::test;

namespace {

struct Row {
  std::string problem;
  int n = 0;
  double tolerance = 0.0;
  Run run;
};

// Solves the given grids (1D sizes n or 2D sizes m) from start 0 ("zero") and prints
// one table row per grid. For the bump, u0 = 0 lies below the obstacle; it is used as
// given (all nodes inactive) unless project_start, which moves it onto the obstacle
// (u0 = max(psi, 0), every node of the bump active: the too large active set above).
std::vector<Row> SolveOnGrids(int dimension, const std::vector<int>& sizes,
                              ObstacleKind kind, NcpFunction function,
                              bool project_start = false) {
  std::vector<Row> rows;
  std::printf("\n%-26s %8s %-19s %9s %-20s %5s %6s %5s %10s\n", "problem", "n",
              "function", "tolerance", "status", "iter", "resid", "bt", "nat.res");
  for (int size : sizes) {
    TestProblem p = dimension == 1 ? Obstacle1D(size, kind) : Obstacle2D(size, kind);
    ncp::Options options = MakeOptions(
        function, dimension == 1 ? LinearSolverType::kKlu : LinearSolverType::kUmfpack);
    options.tolerance = AttainableObstacleTolerance(1.0 / (size + 1));
    options.project_start_point = project_start;
    Row row;
    row.problem = p.name;
    row.n = p.NumVariables();
    row.tolerance = options.tolerance;
    row.run = SolveFrom(p, p.starts[0].x, options);
    const ncp::Summary& s = row.run.summary;
    std::printf("%-26s %8d %-19s %9.1e %-20s %5d %6d %5d %10.3e\n", p.name.c_str(), row.n,
                ncp::ToString(function), options.tolerance, ncp::ToString(s.termination),
                s.iterations, s.residual_evaluations, s.backtracks,
                row.run.natural_residual);
    std::fflush(stdout);
    rows.push_back(row);
  }
  return rows;
}

void CheckAllConvergedWithinFactor(const std::vector<Row>& rows, double factor) {
  int fewest = 1 << 30, most = 0;
  for (const Row& row : rows) {
    INFO(row.problem << ": " << row.run.summary.BriefReport() << ", natural residual "
                     << row.run.natural_residual);
    CHECK(row.run.summary.termination == TerminationType::kConverged);
    // ||Phi_FB|| <= tol implies a natural residual below tol / (2 - sqrt 2) (Tseng 1996).
    CHECK(row.run.natural_residual <= 2 * row.tolerance);
    fewest = std::min(fewest, row.run.summary.iterations);
    most = std::max(most, row.run.summary.iterations);
  }
  INFO("iterations range from " << fewest << " to " << most);
  CHECK(most <= factor * fewest);
}

}  // namespace

TEST_CASE("1D bump obstacle, FB from zero: iterations nearly constant, n = 1e2 .. 1e4",
          "[solver][obstacle][mesh]") {
  CheckAllConvergedWithinFactor(
      SolveOnGrids(1, {100, 1000, 10000}, ObstacleKind::kLowerBump,
                   NcpFunction::kFischerBurmeister),
      2.0);
}

TEST_CASE("2D bump obstacle, FB from zero: iterations nearly constant, 10x10 .. 100x100",
          "[solver][obstacle][mesh]") {
  CheckAllConvergedWithinFactor(SolveOnGrids(2, {10, 30, 100}, ObstacleKind::kLowerBump,
                                             NcpFunction::kFischerBurmeister),
                                2.0);
}

// The following record behaviour that does not meet "max iterations <= 2 min iterations
// and converged" with the current solver; [!mayfail] reports the failed checks without
// failing the suite. See the report of the collection for the numbers.
TEST_CASE("1D bump obstacle, FB from zero, up to n = 1e5 (recorded)",
          "[solver][obstacle][mesh][!mayfail]") {
  CheckAllConvergedWithinFactor(
      SolveOnGrids(1, {100, 1000, 10000, 100000}, ObstacleKind::kLowerBump,
                   NcpFunction::kFischerBurmeister),
      2.0);
}

TEST_CASE("2D bump obstacle, FB from zero, up to 300x300 (recorded)",
          "[solver][obstacle][mesh][!mayfail]") {
  CheckAllConvergedWithinFactor(
      SolveOnGrids(2, {10, 30, 100, 300}, ObstacleKind::kLowerBump,
                   NcpFunction::kFischerBurmeister),
      2.0);
}

TEST_CASE("two-sided band obstacle, FB from zero (recorded)",
          "[solver][obstacle][mesh][!mayfail]") {
  CheckAllConvergedWithinFactor(
      SolveOnGrids(1, {100, 1000, 10000}, ObstacleKind::kTwoSidedBand,
                   NcpFunction::kFischerBurmeister),
      2.0);
  CheckAllConvergedWithinFactor(SolveOnGrids(2, {10, 30, 60}, ObstacleKind::kTwoSidedBand,
                                             NcpFunction::kFischerBurmeister),
                                2.0);
}

// The zero start projected onto [l, u] is the "obstacle" start: measured 22 iterations at
// n = 100 and 186 at n = 1000 (the active set shrinks by boundary nodes per iteration).
TEST_CASE("1D bump obstacle, FB from zero projected onto the obstacle (recorded)",
          "[solver][obstacle][mesh][!mayfail]") {
  CheckAllConvergedWithinFactor(SolveOnGrids(1, {100, 1000}, ObstacleKind::kLowerBump,
                                             NcpFunction::kFischerBurmeister, true),
                                2.0);
}

// Fine grids put the rows' round-off (eps h^-2 |u|) above the default tolerance 1e-10.
// The solver then stops at the round-off floor (Options::roundoff_ulps) and says so; the
// floor is recomputed here from the FB function's partials and |A||u|, independently of
// the solver's bookkeeping.
TEST_CASE("1D bump obstacle, n = 1e4, default tolerance: ends at the round-off floor",
          "[solver][obstacle][roundoff]") {
  const int n = 10000;
  TestProblem p = Obstacle1D(n, ObstacleKind::kLowerBump);
  ncp::Options options =
      MakeOptions(NcpFunction::kFischerBurmeister, LinearSolverType::kKlu);
  options.project_start_point = false;  // u = 0 below the obstacle (see SolveOnGrids)
  REQUIRE(options.tolerance == 1e-10);
  const Run run = SolveFrom(p, p.starts[0].x, options);
  const ncp::Summary& s = run.summary;
  INFO(s.FullReport());
  // Above the tolerance: its own status, not kConverged, and usable.
  REQUIRE(s.termination == TerminationType::kAtRoundoffFloor);
  CHECK(std::string(ncp::ToString(s.termination)) == "at-roundoff-floor");
  CHECK(s.IsSolutionUsable());
  CHECK(s.roundoff_limited);
  CHECK(s.final_phi_inf > options.tolerance);  // the tolerance itself was not reachable
  CHECK(s.message.find("round-off floor") != std::string::npos);

  // Row by row: |phi_FB(a, b)| <= tol + 10 eps (|phi_a| |u_i| + |phi_b| (|A||u|)_i),
  // a = u - psi, b = F(u), phi_a = 1 - a / r, phi_b = 1 - b / r, r = |(a, b)|.
  ncp::Vector F(n);
  ncp::SparseMatrix A;
  REQUIRE(p.F->Evaluate(run.x, &F));
  REQUIRE(p.F->Jacobian(run.x, &A));
  const ncp::Vector terms = A.cwiseAbs() * run.x.cwiseAbs();
  const double eps = std::numeric_limits<double>::epsilon();
  double largest_floor = 0.0;
  for (int i = 0; i < n; ++i) {
    const double a = run.x(i) - p.lower(i), b = F(i), r = std::hypot(a, b);
    const double phi = a + b - r;
    const double da = r > 0 ? std::abs(1 - a / r) : 1.0,
                 db = r > 0 ? std::abs(1 - b / r) : 1.0;
    const double floor = 10 * eps * (da * std::abs(run.x(i)) + db * terms(i));
    largest_floor = std::max(largest_floor, floor);
    INFO("row " << i << ": a = " << a << ", b = " << b << ", floor " << floor);
    REQUIRE(std::abs(phi) <= options.tolerance + floor);
  }
  // The floor is that of the grid, 10 eps h^-2 |u| (2 |u| <= 1 times the diagonal 2
  // h^-2), no looser: at h = 1e-4 about 2e-6.
  CHECK(largest_floor <= 10 * eps * 2.0 * (n + 1.0) * (n + 1.0) * 1.0);
  // And the membrane is the continuous one to the discretization error O(h^2).
  double error = 0.0;
  for (int i = 0; i < n; ++i)
    error = std::max(error, std::abs(run.x(i) - ExactLowerBump1D((i + 1.0) / (n + 1))));
  CHECK(error <= 1e-6);

  // Without the floor the same tolerance is not claimed unless it was really reached.
  options.roundoff_ulps = 0.0;
  options.max_iterations = 60;
  const Run strict = SolveFrom(p, p.starts[0].x, options);
  INFO(strict.summary.BriefReport());
  CHECK_FALSE(strict.summary.roundoff_limited);
  if (strict.summary.termination == TerminationType::kConverged)
    CHECK(strict.summary.final_phi_inf <= options.tolerance);
}

// The guard on the Newton solve compares ||J d + Phi|| with the terms |J||d| (normwise
// backward error), not with ||Phi||: on this grid the rows are h^-2 ~ 9e10 and any solve
// leaves a residual ~ eps |J||d| ~ 1e-6 > 1e-6 ||Phi||. Measured before the change: the
// first direction rejected as a linear-solver failure, the gradient step then failed the
// line search (line-search-failure at iteration 0, after 6 restarts).
TEST_CASE("1D bump obstacle, n = 3e5: the first Newton step is accepted",
          "[solver][obstacle][roundoff]") {
  const int n = 300000;
  TestProblem p = Obstacle1D(n, ObstacleKind::kLowerBump);
  ncp::Options options =
      MakeOptions(NcpFunction::kFischerBurmeister, LinearSolverType::kKlu);
  options.project_start_point = false;
  options.max_iterations = 1;
  options.keep_trace = true;
  const Run run = SolveFrom(p, p.starts[0].x, options);
  const ncp::Summary& s = run.summary;
  INFO(s.FullReport());
  CHECK(s.iterations == 1);
  CHECK(s.linear_solver_failures == 0);
  CHECK(s.gradient_steps == 0);
  REQUIRE(!s.trace.empty());
  CHECK(s.final_psi < s.trace.front().psi);  // the Newton step decreased psi
}

// The same membrane written in the gap w = u - psi (ObstacleVariable::kGap): the
// iterates' round-off no longer grows with h^-2 on the contact set. Checked against the
// height formulation's solution (independent solve) and the continuous solution.
TEST_CASE("1D bump obstacle in the gap variable, n = 1e2 .. 1e5, default tolerance",
          "[solver][obstacle][mesh]") {
  std::printf("\n%-30s %8s %-20s %5s %10s %10s\n", "problem", "n", "status", "iter",
              "|Phi|inf", "err vs exact");
  for (int n : {100, 1000, 10000, 100000}) {
    TestProblem p = Obstacle1D(n, ObstacleKind::kLowerBump, ObstacleVariable::kGap);
    ncp::Options options =
        MakeOptions(NcpFunction::kFischerBurmeister, LinearSolverType::kKlu);
    options.project_start_point = false;  // w0 = -psi: u = 0, below the obstacle
    const Run run = SolveFrom(p, p.starts[0].x, options);
    TestProblem height = Obstacle1D(n, ObstacleKind::kLowerBump);
    double error = 0.0;
    for (int i = 0; i < n; ++i)
      error = std::max(error, std::abs(run.x(i) + height.lower(i) -
                                       ExactLowerBump1D((i + 1.0) / (n + 1))));
    const ncp::Summary& s = run.summary;
    std::printf("%-30s %8d %-20s %5d %10.3e %10.3e\n", p.name.c_str(), n,
                ncp::ToString(s.termination), s.iterations, s.final_phi_inf, error);
    std::fflush(stdout);
    INFO(p.name << ": " << s.FullReport());
    REQUIRE(s.IsSolutionUsable());  // (from n = 1e5 on at the round-off floor)
    // Discretization error: the bound allows O(h) (u is only C^1 at the free boundary);
    // measured 5.4e-5, 1.6e-6, 1.5e-8, 7.0e-11 for n = 1e2 .. 1e5.
    CHECK(error <= 0.1 / (n + 1.0));
    CHECK(s.iterations <= 40);  // measured 18, 18, 22, 31
  }
}

// Not run by default (Catch2 hidden tag; several minutes): the sizes of the
// 10^6-unknown target. build/bin/test_obstacle_mesh "[.obstacle-large]"
TEST_CASE("bump obstacle at 10^6 unknowns, 1D and 2D, gap variable (table)",
          "[.obstacle-large]") {
  // "ratio" = total time / (linear-solver time per Jacobian): the solve's cost in
  // factorizations (+ solves) of the same matrix.
  std::printf("\n%-30s %-8s %8s %-20s %5s %6s %10s %8s %6s\n", "problem", "backend", "n",
              "status", "iter", "resid", "|Phi|inf", "seconds", "ratio");
  auto run = [](TestProblem p, LinearSolverType backend) {
    ncp::Options options = MakeOptions(NcpFunction::kFischerBurmeister, backend);
    options.project_start_point = false;
    const Run r = SolveFrom(p, p.starts[0].x, options);
    const ncp::Summary& s = r.summary;
    const double per_factorization = s.linear_solver_time_s / s.jacobian_evaluations;
    std::printf("%-30s %-8s %8d %-20s %5d %6d %10.3e %8.2f %6.1f%s\n", p.name.c_str(),
                ncp::ToString(backend), p.NumVariables(), ncp::ToString(s.termination),
                s.iterations, s.residual_evaluations, s.final_phi_inf, s.total_time_s,
                s.total_time_s / per_factorization,
                s.roundoff_limited ? " (round-off floor)" : "");
    std::fflush(stdout);
    CHECK(s.IsSolutionUsable());
  };
  for (int n : {100000, 1000000})
    run(Obstacle1D(n, ObstacleKind::kLowerBump, ObstacleVariable::kGap),
        LinearSolverType::kKlu);
  for (int m : {300, 1000})
    for (LinearSolverType backend :
         {LinearSolverType::kCholmod, LinearSolverType::kUmfpack})
      run(Obstacle2D(m, ObstacleKind::kLowerBump, ObstacleVariable::kGap), backend);
}
