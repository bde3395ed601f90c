// The box-MCP entry: bounds of +-1e20 (the GAMS/PATH "no bound") are infinite, and a
// start point outside [l, u] is projected onto the box. Residuals are recomputed here
// from F, l, u; the runs with +-1e20 are compared with the same runs with +-inf.
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/affine_function.hpp"
#include "ncp_collection/collection.hpp"
#include "solve_support.hpp"

using ncp::NcpFunction;
using ncp::TerminationType;
using ncp::Vector;
using namespace ncp::collection;
using namespace ncp::test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Natural residual of a converged run (||Phi||_inf <= 1e-10; see test_solve_collection).
constexpr double kResidualTolerance = 1e-8;

Vector ReplaceInfinities(const Vector& bound, double big) {
  Vector out = bound;
  for (Eigen::Index i = 0; i < out.size(); ++i)
    if (std::isinf(out(i))) out(i) = out(i) > 0 ? big : -big;
  return out;
}

ncp::SparseMatrix Tridiagonal(int n) {  // 2 on the diagonal, -1 beside it: SPD
  ncp::SparseMatrix M(n, n);
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0);
    if (i > 0) t.emplace_back(i, i - 1, -1.0);
    if (i + 1 < n) t.emplace_back(i, i + 1, -1.0);
  }
  M.setFromTriplets(t.begin(), t.end());
  return M;
}

}  // namespace

TEST_CASE("bounds of +-1e20 are infinite: same runs as with +-inf", "[box_mcp]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  ncp::Options options;
  options.ncp_function = function;
  for (TestProblem& problem : StandardCollection()) {
    if (problem.NumVariables() > 100) continue;  // the small ones suffice here
    const Vector lower_big = ReplaceInfinities(problem.lower, 1e20);
    const Vector upper_big = ReplaceInfinities(problem.upper, 1e20);
    for (const StartPoint& start : problem.starts) {
      const Run with_inf = SolveFrom(problem, start.x, options);
      Vector x = start.x;
      ncp::Summary summary;
      ncp::Solve(options, *problem.F, lower_big, upper_big, &x, &summary);
      INFO(problem.name << " from " << start.label << " with " << ToString(function)
                        << ": " << summary.BriefReport() << " vs "
                        << with_inf.summary.BriefReport());
      CHECK(summary.termination == with_inf.summary.termination);
      CHECK(summary.iterations == with_inf.summary.iterations);
      CHECK(summary.num_variables == with_inf.summary.num_variables);  // no slacks added
      if (summary.termination == TerminationType::kConverged)
        CHECK(NaturalResidual(*problem.F, problem.lower, problem.upper, x) <=
              kResidualTolerance);
    }
  }
}

TEST_CASE("free variables given as [-1e20, 1e20] are equations", "[box_mcp]") {
  // F(x) = T x - q with T tridiagonal SPD, all variables free: the linear system T x = q.
  const int n = 5;
  const Vector q = Vector::LinSpaced(n, 1.0, 5.0);
  AffineFunction F(Tridiagonal(n), -q);
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  ncp::Options options;
  options.ncp_function = function;
  Vector x = Vector::Zero(n);
  ncp::Summary summary;
  ncp::Solve(options, F, Vector::Constant(n, -1e20), Vector::Constant(n, 1e20), &x,
             &summary);
  INFO(summary.FullReport());
  REQUIRE(summary.termination == TerminationType::kConverged);
  CHECK(summary.num_equations == n);
  CHECK(summary.iterations == 1);  // one Newton step solves a linear system
  const Vector x_direct = Eigen::MatrixXd(F.M()).lu().solve(q);
  CHECK((x - x_direct).lpNorm<Eigen::Infinity>() <= 1e-12);
}

TEST_CASE("infinite_bound = +inf keeps 1e20 a finite bound", "[box_mcp]") {
  const int n = 3;
  AffineFunction F(Tridiagonal(n), -Vector::Ones(n));
  ncp::Options options;
  options.infinite_bound = kInf;
  Vector x = Vector::Zero(n);
  ncp::Summary summary;
  ncp::Solve(options, F, Vector::Zero(n), Vector::Constant(n, 1e20), &x, &summary);
  REQUIRE(summary.termination == TerminationType::kConverged);
  CHECK(summary.num_variables == 3 * n);  // two-sided: two slacks per variable
  ncp::Options bad;
  bad.infinite_bound = 0.0;
  std::string error;
  CHECK_FALSE(bad.IsValid(&error));
  CHECK_THROWS_AS(ncp::Solver(bad), std::invalid_argument);
}

TEST_CASE("a start point outside [l, u] is projected onto the box", "[box_mcp]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  ncp::Options options;
  options.ncp_function = function;
  SECTION("a standard NCP from x0 < 0") {
    TestProblem problem = PathManualLcp();
    const Run run = SolveFrom(problem, Vector::Constant(4, -3.0), options);
    INFO(run.summary.FullReport());
    REQUIRE(run.summary.termination == TerminationType::kConverged);
    CHECK(run.summary.projected_start_components == 4);
    CHECK(run.summary.message.find("projected") != std::string::npos);
    CHECK(run.natural_residual <= kResidualTolerance);
    CHECK(DistanceToNearest(run.x, problem.solutions) <= 1e-8);
  }
  SECTION("a two-sided obstacle from u0 = 5 and u0 = -5 outside [-0.1, 0.1]") {
    TestProblem problem = Obstacle1D(50, ObstacleKind::kTwoSidedBand);
    for (double u0 : {5.0, -5.0}) {
      const Run run = SolveFrom(problem, Vector::Constant(50, u0), options);
      INFO("u0 = " << u0 << ": " << run.summary.FullReport());
      if (function == NcpFunction::kMin &&
          run.summary.termination != TerminationType::kConverged) {
        // min is not globally convergent; it must at least say so.
        CHECK(run.summary.termination != TerminationType::kNotSolved);
        continue;
      }
      REQUIRE(run.summary.termination == TerminationType::kConverged);
      CHECK(run.summary.projected_start_components == 50);
      CHECK(run.natural_residual <= kResidualTolerance);
    }
  }
  SECTION("starts below x >= 0 that fail when used as given") {
    // Measured with project_start_point = false and Algorithm 1 (FB, min, penalized FB):
    // josephy from x0 = -10 (1, 1, 1, 1) ends at a stationary point of psi (FB, PFB;
    // ||Phi|| ~ 0.27) or in a line-search failure (min, from -1); mathiesen-mod from -10
    // cannot even be evaluated (its F has a domain). Projected, both converge (with the
    // default options; the nonmonotone search also solves josephy unprojected).
    for (auto make : {&Josephy, &ModifiedMathiesen}) {
      TestProblem problem = make();
      const Vector x0 = Vector::Constant(
          4, problem.name == "josephy" && function == NcpFunction::kMin ? -1.0 : -10.0);
      ncp::Options as_given = ncp::Options::Algorithm1();
      as_given.ncp_function = function;
      as_given.project_start_point = false;
      const Run unprojected = SolveFrom(problem, x0, as_given);
      const Run projected = SolveFrom(problem, x0, options);
      INFO(problem.name << ": as given " << unprojected.summary.BriefReport()
                        << "; projected " << projected.summary.BriefReport());
      CHECK(unprojected.summary.termination != TerminationType::kConverged);
      REQUIRE(projected.summary.termination == TerminationType::kConverged);
      CHECK(projected.summary.projected_start_components == 4);
      CHECK(projected.natural_residual <= kResidualTolerance);
    }
  }
  SECTION("a start inside the box is not touched") {
    TestProblem problem = PathManualLcp();
    const Run run = SolveFrom(problem, Vector::Ones(4), options);
    INFO(run.summary.message);
    CHECK(run.summary.projected_start_components == 0);
    CHECK(run.summary.message.find("start point") == std::string::npos);
  }
}

// The one-shot ncp::Solve borrows a Solver kept per thread for n <= 100: every result
// must be the one a fresh Solver gives, whatever was solved before on the same thread.
TEST_CASE("one-shot solves of small problems equal fresh-Solver solves, in any order",
          "[box_mcp][one_shot]") {
  std::vector<TestProblem> problems = StandardCollection();
  for (ncp::LinearSolverType backend :
       {ncp::LinearSolverType::kAuto, ncp::LinearSolverType::kSparseLU,
        ncp::LinearSolverType::kKlu}) {
    for (int pass = 0; pass < 2; ++pass) {  // the second pass meets a used workspace
      for (TestProblem& p : problems) {
        if (p.NumVariables() > 100) continue;
        for (NcpFunction function :
             {NcpFunction::kFischerBurmeister, NcpFunction::kMin}) {
          ncp::Options options = MakeOptions(function, backend);
          const Vector& x0 = p.starts.back().x;
          Vector x_once = x0, x_fresh = x0;
          ncp::Summary once, fresh;
          ncp::Solve(options, *p.F, p.lower, p.upper, &x_once, &once);
          ncp::Solver(options).Solve(*p.F, p.lower, p.upper, &x_fresh, &fresh);
          INFO(p.name << " " << ncp::ToString(function) << " " << ncp::ToString(backend)
                      << " pass " << pass << ": " << once.BriefReport() << " / "
                      << fresh.BriefReport());
          CHECK(once.termination == fresh.termination);
          CHECK(once.iterations == fresh.iterations);
          CHECK(once.residual_evaluations == fresh.residual_evaluations);
          CHECK((x_once - x_fresh).lpNorm<Eigen::Infinity>() == 0.0);
        }
      }
    }
  }
}

TEST_CASE("a one-shot solve called from inside F of another one-shot solve",
          "[box_mcp][one_shot]") {
  // Outer: x >= 0 perp F(x) = x - c with c = y(x) + 1 found by an inner solve of
  // y >= 0 perp y - 2 (so y = 2, c = 3, x = 3).
  int inner_calls = 0;
  ncp::DenseSquareFunction outer(
      1,
      [&](const Vector& x, Vector* F) {
        ncp::DenseSquareFunction inner(
            1,
            [](const Vector& y, Vector* G) {
              (*G)(0) = y(0) - 2.0;
              return true;
            },
            [](const Vector&, ncp::DenseMatrix* J) {
              (*J)(0, 0) = 1.0;
              return true;
            });
        Vector y = Vector::Zero(1);
        ncp::Summary s;
        ncp::SolveNcp(ncp::Options(), inner, &y, &s);
        ++inner_calls;
        if (!s.IsSolutionUsable()) return false;
        (*F)(0) = x(0) - (y(0) + 1.0);
        return true;
      },
      [](const Vector&, ncp::DenseMatrix* J) {
        (*J)(0, 0) = 1.0;
        return true;
      });
  Vector x = Vector::Zero(1);
  ncp::Summary summary;
  ncp::SolveNcp(ncp::Options(), outer, &x, &summary);
  INFO(summary.FullReport());
  REQUIRE(summary.IsSolutionUsable());
  CHECK(std::abs(x(0) - 3.0) <= 1e-9);
  CHECK(inner_calls == summary.residual_evaluations);
}

// Eigen::SparseLU's analyzePattern does not set info(): read after a singular
// factorization it made every later analysis "fail", so a kept Solver never took a Newton
// step again once the pattern changed.
TEST_CASE("a kept SparseLU Solver works after a singular factorization and a new pattern",
          "[box_mcp][one_shot]") {
  ncp::Options options;
  options.linear_solver = ncp::LinearSolverType::kSparseLU;
  ncp::Solver solver(options);
  // Two free variables, F(x) = (x0 + x1 - 1, x0 + x1 - 3): J = [1 1; 1 1] is singular
  // everywhere, every factorization fails (and there is no solution).
  ncp::DenseSquareFunction singular(
      2,
      [](const Vector& x, Vector* F) {
        (*F)(0) = x(0) + x(1) - 1.0;
        (*F)(1) = x(0) + x(1) - 3.0;
        return true;
      },
      [](const Vector&, ncp::DenseMatrix* J) {
        J->setOnes();
        return true;
      });
  const double inf = std::numeric_limits<double>::infinity();
  Vector x = Vector::Zero(2);
  ncp::Summary summary;
  solver.Solve(singular, Vector::Constant(2, -inf), Vector::Constant(2, inf), &x,
               &summary);
  INFO(summary.FullReport());
  CHECK_FALSE(summary.IsSolutionUsable());
  CHECK(summary.linear_solver_failures >= 1);
  TestProblem kojshin = KojimaShindo();
  x = kojshin.starts.front().x;
  solver.Solve(*kojshin.F, kojshin.lower, kojshin.upper, &x, &summary);
  INFO(summary.FullReport());
  CHECK(summary.IsSolutionUsable());
  CHECK(summary.linear_solver_failures == 0);
}

namespace {

// Independent check of a Farkas certificate of a box LCP (types.hpp, kInfeasible): y in
// the dual cone of the bounds' cone, g = M'y with a finite sup over the box, and q'y +
// sup_{x in [l, u]} g'x < 0. Recomputed densely here, with no tolerance.
double FarkasValue(const Eigen::MatrixXd& M, const Vector& q, const Vector& lower,
                   const Vector& upper, const Vector& y) {
  const Vector g = M.transpose() * y;
  double value = q.dot(y);
  for (Eigen::Index i = 0; i < y.size(); ++i) {
    const bool lo = std::isfinite(lower(i)), up = std::isfinite(upper(i));
    if (lo && !up) REQUIRE(y(i) >= 0.0);
    if (!lo && up) REQUIRE(y(i) <= 0.0);
    if (lo && up) REQUIRE(y(i) == 0.0);
    if (g(i) > 0.0) REQUIRE(std::isfinite(upper(i)));
    if (g(i) < 0.0) REQUIRE(std::isfinite(lower(i)));
    if (g(i) != 0.0) value += g(i) * (g(i) > 0.0 ? upper(i) : lower(i));
  }
  return value;
}

struct BoxLcp {
  const char* name;
  Eigen::MatrixXd M;
  Vector q, lower, upper;
};

}  // namespace

TEST_CASE(
    "an LCP without a solution ends infeasible with a checked certificate, x in [l, u]",
    "[box_mcp][infeasible]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  std::vector<BoxLcp> problems;
  // x >= 0 perp -x - 1 >= 0: F < 0 on the whole orthant (issue 29's example).
  problems.push_back({"M = -I, q = -1", -Eigen::MatrixXd::Identity(2, 2),
                      Vector::Constant(2, -1.0), Vector::Zero(2),
                      Vector::Constant(2, kInf)});
  // x <= 0 perp F = 1 - x/2 <= 0 is impossible for x <= 0 (F >= 1); x_1 free with F_1 =
  // x_1.
  Eigen::MatrixXd M2(2, 2);
  M2 << -0.5, 0.0, 0.0, 1.0;
  problems.push_back({"upper bound, F > 0 on the box", M2,
                      (Vector(2) << 1.0, 0.0).finished(), Vector::Constant(2, -kInf),
                      (Vector(2) << 0.0, kInf).finished()});
  // Two rows that need x_0 + x_1 >= 1 and -x_0 - x_1 >= 0 on the orthant.
  Eigen::MatrixXd M3(2, 2);
  M3 << 1.0, 1.0, -1.0, -1.0;
  problems.push_back({"contradictory rows", M3, (Vector(2) << -1.0, 0.0).finished(),
                      Vector::Zero(2), Vector::Constant(2, kInf)});
  for (const BoxLcp& p : problems) {
    INFO(p.name << ", " << ncp::ToString(function));
    AffineFunction F(p.M.sparseView(), p.q);
    ncp::Options options;
    options.ncp_function = function;
    Vector x = Vector::Zero(2);
    ncp::Summary summary;
    ncp::Solver(options).Solve(F, p.lower, p.upper, &x, &summary);
    INFO(summary.message);
    REQUIRE(summary.termination == TerminationType::kInfeasible);
    REQUIRE(summary.infeasibility_certificate.size() == 2);
    CHECK(FarkasValue(p.M, p.q, p.lower, p.upper, summary.infeasibility_certificate) <
          0.0);
    CHECK(summary.message.find("no solution exists") != std::string::npos);
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      CHECK(x(i) >= p.lower(i));
      CHECK(x(i) <= p.upper(i));
    }
  }
}

TEST_CASE("a stuck solve of a solvable or non-affine problem is never called infeasible",
          "[box_mcp][infeasible]") {
  // The same data as the infeasible LCP, but F not declared affine: no claim is made.
  class NotDeclaredAffine : public ncp::SquareFunction {
   public:
    int NumVariables() const override { return 2; }
    bool Evaluate(const Vector& x, Vector* F) override {
      *F = -x - Vector::Ones(2);
      return true;
    }
    bool Jacobian(const Vector&, ncp::SparseMatrix* J) override {
      *J = -Eigen::MatrixXd::Identity(2, 2).sparseView();
      return true;
    }
  } F;
  Vector x = Vector::Zero(2);
  ncp::Summary summary;
  ncp::Solver().Solve(F, Vector::Zero(2), Vector::Constant(2, kInf), &x, &summary);
  CHECK(summary.termination != TerminationType::kInfeasible);
  CHECK(summary.termination != TerminationType::kConverged);
  CHECK(summary.infeasibility_certificate.size() == 0);
  CHECK(x.minCoeff() >= 0.0);  // projected onto the box all the same

  // A solvable LCP (M = I, q = -1: x = 1) converges and carries no certificate.
  AffineFunction G(Eigen::MatrixXd::Identity(2, 2).sparseView(), -Vector::Ones(2));
  x.setZero();
  ncp::Solver().Solve(G, Vector::Zero(2), Vector::Constant(2, kInf), &x, &summary);
  CHECK(summary.termination == TerminationType::kConverged);
  CHECK((x - Vector::Ones(2)).lpNorm<Eigen::Infinity>() <= kResidualTolerance);
  CHECK(summary.infeasibility_certificate.size() == 0);
}

TEST_CASE("the returned x of a box MCP lies in [l, u] whatever the status", "[box_mcp]") {
  // Every collection problem from every start with a small iteration budget: most stop
  // early, inside or outside the box; the returned x must be inside.
  ncp::Options options;
  options.max_iterations = 3;
  for (TestProblem& problem : StandardCollection()) {
    if (problem.NumVariables() > 100) continue;
    for (const StartPoint& start : problem.starts) {
      Vector x = start.x;
      ncp::Summary summary;
      ncp::Solver(options).Solve(*problem.F, problem.lower, problem.upper, &x, &summary);
      INFO(problem.name << " from " << start.label << ": " << summary.message);
      for (Eigen::Index i = 0; i < x.size(); ++i) {
        REQUIRE(x(i) >= problem.lower(i));
        REQUIRE(x(i) <= problem.upper(i));
      }
      CHECK(summary.projected_final_components >= 0);
    }
  }
}
