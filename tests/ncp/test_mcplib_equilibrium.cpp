// The MCPLIB / GAMS equilibrium problems (mcplib_equilibrium.hpp): analytic Jacobians
// against central differences, the known solutions against a natural residual recomputed
// here from F, l, u alone, and the default solver from every standard start (reported;
// asserted where it converges, documented failures otherwise).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/checks.hpp"
#include "ncp_collection/mcplib_equilibrium.hpp"

using ncp::DenseMatrix;
using ncp::SparseMatrix;
using ncp::Vector;
using namespace ncp::collection;

namespace {

// ||mid(l, u, x - F(x)) - x||_inf / max(1, ||x||_inf), written out here (not the library's
// NaturalResidual) so the check does not depend on the code under test.
double RelativeNaturalResidual(TestProblem& p, const Vector& x) {
  Vector Fx(p.NumVariables());
  if (!p.F->Evaluate(x, &Fx)) return INFINITY;
  double worst = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double y = x(i) - Fx(i);
    const double mid = std::max(p.lower(i), std::min(p.upper(i), y));
    worst = std::max(worst, std::abs(mid - x(i)));
  }
  return worst / std::max(1.0, x.lpNorm<Eigen::Infinity>());
}

// max_ij |J - Jfd| / max(1, max_ij |J|)
double RelativeJacobianError(ncp::SquareFunction& F, const Vector& x) {
  SparseMatrix J;
  if (!F.Jacobian(x, &J)) return INFINITY;
  DenseMatrix Jfd;
  if (!CentralDifferenceJacobian(F, x, 1e-6, &Jfd)) return INFINITY;
  const DenseMatrix Jd(J);
  return (Jd - Jfd).lpNorm<Eigen::Infinity>() / std::max(1.0, Jd.lpNorm<Eigen::Infinity>());
}

}  // namespace

TEST_CASE("MCPLIB equilibrium problems are well formed", "[collection][mcplib]") {
  std::vector<TestProblem> problems = McplibEquilibriumProblems();
  REQUIRE(!problems.empty());
  for (TestProblem& p : problems) {
    INFO(p.name);
    const int n = p.NumVariables();
    CHECK(p.lower.size() == n);
    CHECK(p.upper.size() == n);
    CHECK_FALSE(p.source.empty());
    CHECK_FALSE(p.starts.empty());
    CHECK_FALSE(p.solutions.empty());
    CHECK((p.lower.array() <= p.upper.array()).all());
    for (const StartPoint& s : p.starts) CHECK(s.x.size() == n);
  }
}

TEST_CASE("MCPLIB equilibrium Jacobians match central differences",
          "[collection][mcplib]") {
  std::vector<TestProblem> problems = McplibEquilibriumProblems();
  for (TestProblem& p : problems) {
    std::vector<std::pair<std::string, Vector>> points;
    for (const StartPoint& s : p.starts) points.emplace_back("start " + s.label, s.x);
    for (std::size_t k = 0; k < p.solutions.size(); ++k)
      points.emplace_back("solution " + std::to_string(k), p.solutions[k]);
    for (const auto& [label, x] : points) {
      const double error = RelativeJacobianError(*p.F, x);
      INFO(p.name << " at " << label << ": relative Jacobian error " << error);
      CHECK(error <= 1e-6);
    }
  }
}

TEST_CASE("MCPLIB equilibrium known solutions satisfy complementarity",
          "[collection][mcplib]") {
  std::vector<TestProblem> problems = McplibEquilibriumProblems();
  for (TestProblem& p : problems) {
    for (const Vector& s : p.solutions) {
      CHECK((s.array() >= p.lower.array()).all());
      CHECK((s.array() <= p.upper.array()).all());
      const double residual = RelativeNaturalResidual(p, s);
      INFO(p.name << ": relative natural residual of the known solution " << residual);
      CHECK(residual <= 1e-6);
    }
  }
}

TEST_CASE("MCPLIB equilibrium problems with the default solver", "[solver][mcplib]") {
  std::vector<TestProblem> problems = McplibEquilibriumProblems();
  const ncp::Options options;  // the defaults
  for (TestProblem& p : problems) {
    for (const StartPoint& start : p.starts) {
      Vector x = start.x;
      ncp::Summary summary;
      ncp::Solve(options, *p.F, p.lower, p.upper, &x, &summary);
      const double residual = RelativeNaturalResidual(p, x);
      double distance = INFINITY;
      for (const Vector& s : p.solutions)
        distance = std::min(distance, (x - s).lpNorm<Eigen::Infinity>() /
                                          std::max(1.0, s.lpNorm<Eigen::Infinity>()));
      std::printf("[mcplib] %-10s n=%3d start %-6s: %s, %d iterations, natural residual "
                  "%.2e, distance to known solution %.2e\n",
                  p.name.c_str(), p.NumVariables(), start.label.c_str(),
                  ncp::ToString(summary.termination), summary.iterations, residual,
                  distance);
      if (std::getenv("NCP_PRINT_SOLUTIONS") != nullptr) {
        for (Eigen::Index i = 0; i < x.size(); ++i) std::printf("%.17g,\n", x(i));
      }
      INFO(p.name << " from " << start.label << ": " << summary.BriefReport()
                  << "; message: " << summary.message);
      if (const ExpectedFailure* failure =
              p.FindExpectedFailure(start.label, options.ncp_function)) {
        INFO("documented failure: " << failure->reason);
        CHECK_FALSE(summary.IsSolutionUsable());
        continue;
      }
      CHECK(summary.termination == ncp::TerminationType::kConverged);
      CHECK(residual <= 1e-8);
      if (p.isolated_solutions) CHECK(distance <= 1e-6);
    }
  }
}
