// The MCPLIB / GAMS model library problems of mcplib_nlp.hpp: analytic Jacobians against
// central differences, the stored solutions against a natural residual recomputed here,
// and the default solver from every standard start (outcome printed; convergence asserted
// where it holds, documented failures asserted to be honest).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/checks.hpp"
#include "ncp_collection/mcplib_nlp.hpp"

using ncp::DenseMatrix;
using ncp::SparseMatrix;
using ncp::TerminationType;
using ncp::Vector;
using namespace ncp::collection;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Natural residual written out here, independently of collection::NaturalResidual:
// r_i = x_i - mid(l_i, u_i, x_i - F_i(x)), scaled by 1 + |x_i| + |F_i(x)| (relative).
double RelativeNaturalResidual(TestProblem& p, const Vector& x) {
  Vector Fx(p.NumVariables());
  if (!p.F->Evaluate(x, &Fx)) return kInf;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double y = x(i) - Fx(i);
    const double mid = std::max(p.lower(i), std::min(p.upper(i), y));
    const double r = std::abs(x(i) - mid) / (1.0 + std::abs(x(i)) + std::abs(Fx(i)));
    if (!std::isfinite(r)) return kInf;
    worst = std::max(worst, r);
  }
  return worst;
}

// max_ij |J_ij - Jfd_ij| / max(1, max_ij |J_ij|)
double RelativeJacobianError(TestProblem& p, const Vector& x) {
  SparseMatrix J;
  if (!p.F->Jacobian(x, &J)) return kInf;
  DenseMatrix Jfd;
  if (!CentralDifferenceJacobian(*p.F, x, 1e-6, &Jfd)) return kInf;
  const DenseMatrix Jd(J);
  return (Jd - Jfd).lpNorm<Eigen::Infinity>() /
         std::max(1.0, Jd.lpNorm<Eigen::Infinity>());
}

}  // namespace

TEST_CASE("mcplib_nlp: the set is complete and well formed", "[collection][mcplib]") {
  std::vector<TestProblem> problems = McplibNlpProblems();
  REQUIRE(problems.size() >= 8);
  for (TestProblem& p : problems) {
    INFO(p.name);
    const int n = p.NumVariables();
    CHECK(n > 0);
    CHECK(!p.source.empty());
    CHECK(p.lower.size() == n);
    CHECK(p.upper.size() == n);
    CHECK((p.lower.array() <= p.upper.array()).all());
    CHECK(!p.starts.empty());
    CHECK(!p.solutions.empty());
    for (const StartPoint& s : p.starts) CHECK(s.x.size() == n);
    for (const Vector& s : p.solutions) CHECK(s.size() == n);
  }
}

TEST_CASE(
    "mcplib_nlp: analytic Jacobians match central differences at the starts and "
    "at the solutions",
    "[collection][mcplib]") {
  for (TestProblem& p : McplibNlpProblems()) {
    std::vector<std::pair<std::string, Vector>> points;
    for (const StartPoint& s : p.starts) points.emplace_back("start " + s.label, s.x);
    for (const Vector& s : p.solutions) points.emplace_back("solution", s);
    for (const auto& [label, x] : points) {
      INFO(p.name << " at " << label);
      CHECK(RelativeJacobianError(p, x) <= 1e-6);
    }
  }
}

TEST_CASE("mcplib_nlp: the stored solutions satisfy complementarity",
          "[collection][mcplib]") {
  for (TestProblem& p : McplibNlpProblems()) {
    for (const Vector& s : p.solutions) {
      INFO(p.name);
      CHECK((s.array() >= p.lower.array()).all());
      CHECK((s.array() <= p.upper.array()).all());
      CHECK(RelativeNaturalResidual(p, s) <= 1e-6);
    }
  }
}

TEST_CASE(
    "mcplib_nlp: Colville's problem reproduces Hock and Schittkowski's published "
    "optimum",
    "[collection][mcplib]") {
  // HS117 (1981): f* = 32.34867897, x* to 7 digits.
  const double x_hs[15] = {0,         0,         5.174136,  0,         3.061093,
                           11.83968,  0,         0,         0.1039071, 0,
                           0.2999929, 0.3334709, 0.3999910, 0.4283145, 0.2239607};
  TestProblem dual = ColvilleDual();
  const Vector z = dual.solutions.at(0);
  for (int i = 0; i < 15; ++i) CHECK(z(i) == Approx(x_hs[i]).margin(2e-4));
  // HS117's objective -b'v + w'Cw + 2 d'w^3 at the stored point, from the published data.
  const double b[10] = {-40, -2, -0.25, -4, -4, -1, -40, -60, 5, 1};
  const double C[5][5] = {{30, -20, -10, 32, -10},
                          {-20, 39, -6, -31, 32},
                          {-10, -6, 10, -6, -10},
                          {32, -31, -6, 39, -20},
                          {-10, 32, -10, -20, 30}};
  const double d[5] = {4, 8, 10, 6, 2};
  double f = 0;
  for (int k = 0; k < 10; ++k) f -= b[k] * z(k);
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) f += C[i][j] * z(10 + i) * z(10 + j);
    f += 2 * d[i] * std::pow(z(10 + i), 3);
  }
  CHECK(f == Approx(32.34867897).epsilon(1e-8));
  // Duality: the multipliers of HS117 are the primal variables w, and colvnlp's solution
  // is (w, v).
  for (int i = 0; i < 5; ++i) CHECK(z(15 + i) == Approx(z(10 + i)).margin(1e-9));
  TestProblem primal = ColvilleNlp();
  const Vector y = primal.solutions.at(0);
  for (int i = 0; i < 5; ++i) CHECK(y(i) == Approx(z(10 + i)).margin(1e-9));
  for (int k = 0; k < 10; ++k) CHECK(y(5 + k) == Approx(z(k)).margin(1e-9));
}

TEST_CASE("mcplib_nlp: the default solver from every standard start",
          "[solver][collection][mcplib]") {
  for (TestProblem& p : McplibNlpProblems()) {
    for (const StartPoint& start : p.starts) {
      Vector x = start.x;
      ncp::Summary summary;
      const ncp::Options options;  // the library's defaults
      ncp::Solve(options, *p.F, p.lower, p.upper, &x, &summary);
      const double residual = RelativeNaturalResidual(p, x);
      double distance = kInf;
      for (const Vector& s : p.solutions)
        distance = std::min(distance, (x - s).lpNorm<Eigen::Infinity>() /
                                          (1.0 + s.lpNorm<Eigen::Infinity>()));
      std::printf(
          "mcplib_nlp: %-9s n=%2d start %-6s -> %s, %d iterations, relative "
          "natural residual %.2e, distance to stored solution %.2e\n",
          p.name.c_str(), p.NumVariables(), start.label.c_str(),
          ncp::ToString(summary.termination), summary.iterations, residual, distance);
      INFO(p.name << " from " << start.label << ": " << summary.BriefReport() << "; "
                  << summary.message);
      if (const ExpectedFailure* failure =
              p.FindExpectedFailure(start.label, options.ncp_function)) {
        INFO("documented failure: " << failure->reason);
        CHECK_FALSE(summary.IsSolutionUsable());
        CHECK(summary.termination != TerminationType::kConverged);
        CHECK(residual > 1e-8);
        continue;
      }
      CHECK(summary.termination == TerminationType::kConverged);
      CHECK(residual <= 1e-8);
      if (p.isolated_solutions) CHECK(distance <= 1e-6);
    }
  }
}
