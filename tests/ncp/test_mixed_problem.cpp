// The solver on a problem in mixed form (one equation + pairs): projection onto the
// simplex, whose solution is known in closed form. The residual
// max(|E|, max_j |min(A_j, B_j)|) is recomputed here from Evaluate().
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "ncp/solver.hpp"
#include "ncp_collection/mixed_examples.hpp"
#include "solve_support.hpp"

using ncp::LinearSolverType;
using ncp::NcpFunction;
using ncp::Vector;

namespace {

double MixedResidualHere(ncp::MixedProblem& problem, const Vector& z) {
  const int n = problem.NumVariables(), m = problem.NumEquations();
  Vector E(m), A(n - m), B(n - m);
  if (!problem.Evaluate(z, &E, &A, &B)) return std::numeric_limits<double>::infinity();
  double r = m > 0 ? E.lpNorm<Eigen::Infinity>() : 0.0;
  for (int j = 0; j < n - m; ++j) r = std::max(r, std::abs(std::min(A(j), B(j))));
  return r;
}

}  // namespace

TEST_CASE("simplex projection as a mixed problem", "[solver][mixed]") {
  const LinearSolverType backend =
      GENERATE(LinearSolverType::kDenseLU, LinearSolverType::kSparseLU,
               LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  Vector a(6);
  a << 0.8, 0.6, -0.2, 0.1, 0.35, -1.0;  // tau = 0.25: x = (0.55, 0.35, 0, 0, 0.1, 0)
  ncp::collection::MixedTestProblem p = ncp::collection::SimplexProjection(a);
  for (const ncp::collection::StartPoint& start : p.starts) {
    Vector z = start.x;
    ncp::Summary summary;
    ncp::Solve(ncp::test::MakeOptions(function, backend), *p.problem, &z, &summary);
    INFO(ncp::ToString(function) << " / " << ncp::ToString(backend) << " from "
                                 << start.label << ": " << summary.BriefReport());
    CHECK(summary.num_equations == 1);
    CHECK(summary.num_pairs == 6);
    CHECK(summary.termination == ncp::TerminationType::kConverged);
    CHECK(MixedResidualHere(*p.problem, z) <= 1e-9);
    CHECK((z - p.solutions[0]).lpNorm<Eigen::Infinity>() <= 1e-8);
    CHECK(z(0) == Approx(-0.25));
    CHECK(z.tail(6).sum() == Approx(1.0));
  }
}
