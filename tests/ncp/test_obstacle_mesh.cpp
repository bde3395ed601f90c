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
#include <cstdio>
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
